"""The sweep driver: speeds cut into blocks, blocks run on an executor, curves assembled.

A sweep takes a model factory ``speed -> Model`` (speed in rad/s); for process pools and Dask it
must be picklable (the scene layer's :class:`gear_dyn.scene.sweep.SceneModels` is).
"""

from __future__ import annotations

import collections
import concurrent.futures as cf
import math
import multiprocessing
import os
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.sweep.batch import linear_block
from gear_dyn.analysis.sweep.points import steady_point, transient_point
from gear_dyn.analysis.sweep.types import (
    DIRECTIONS,
    Point,
    SweepCurve,
    SweepOptions,
    SweepResult,
)
from gear_dyn.errors import InputError, check_range
from gear_dyn.models.base import Model
from gear_dyn.solvers import SolverSettings, resolve_method

FloatArray = NDArray[np.float64]
ModelFactory = Callable[[float], Model]

#: seconds of estimated serial work below which a sweep does not start a pool or use an
#: executor: a fork pool of 2 starts in ~0.1 s and pickles the points back, a Dask task costs
#: milliseconds plus each worker's first scene build; benchmarks/bench_sweep.py measures the
#: break-even (workers 1 vs 2, Dask) and the README quotes it
MIN_PARALLEL_S = 0.5
#: speeds of the timed first block of a linear sweep that may go parallel
PROBE_SPEEDS = 64
#: a continuation (backlash) sweep is probed with its first speed, solved from the static
#: state far below resonance: its later speeds cost more. On the backlash scene (24 speeds up
#: and down, benchmarks/bench_sweep.py) with DOP853 sampling the orbits the first speed
#: predicted 0.43-0.48 s of serial work for 2.1 s measured; the estimate is scaled by this
#: (conservative) factor
NONLINEAR_COST_FACTOR = 4.0
#: the same where the orbits are sampled by the exact contact propagator
#: (``exact_contact``): the first speed predicted 0.084-0.094 s (in a fresh process, first
#: calls included: 0.16-0.19 s) for 0.18 s measured
EXACT_CONTACT_COST_FACTOR = 2.0


@dataclass(frozen=True)
class _Task:
    factory: ModelFactory
    settings: SolverSettings
    options: SweepOptions
    periods: int
    steady_periods: int
    speeds: tuple[float, ...]
    y_start: FloatArray | None
    continuation: bool
    orbit_periods: int = 1


def run_block(task: _Task) -> tuple[list[Point], FloatArray | None]:
    """Evaluate a block of speeds in order (the worker function; picklable).

    Returns the points and the last state (the start of the next block of a continuation; the
    last point's ``orbit_periods`` goes with it).
    """
    y = task.y_start
    n_prev = task.orbit_periods
    if task.options.method == "steady" and not task.continuation:
        models = [task.factory(s) for s in task.speeds]
        batch = linear_block(models, task.speeds, task.settings, task.options)
        if batch is not None:
            return batch, None
    points = []
    for s in task.speeds:
        model = task.factory(s)
        if task.options.method == "steady":
            p, y_next = steady_point(model, s, task.settings, task.options, y, n_prev)
            n_prev = p.orbit_periods or n_prev
        else:
            p, y_next = transient_point(model, s, task.settings, task.options, task.periods,
                                        task.steady_periods, y)
        points.append(p)
        if task.continuation and y_next is not None:
            y = y_next
    return points, y


def _default_executor(workers: int | None) -> cf.Executor:
    ctx = None
    if sys.version_info >= (3, 12) and "forkserver" in multiprocessing.get_all_start_methods():
        ctx = multiprocessing.get_context("forkserver")
    return cf.ProcessPoolExecutor(max_workers=workers or os.cpu_count() or 1, mp_context=ctx)


class _Inline(cf.Executor):
    """Runs each task at once in this process (``workers=1``)."""

    def submit(self, fn: Any, /, *args: Any, **kwargs: Any) -> cf.Future[Any]:
        fut: cf.Future[Any] = cf.Future()
        try:
            fut.set_result(fn(*args, **kwargs))
        except BaseException as exc:  # handed to the caller through the future
            fut.set_exception(exc)
        return fut


def _checked_speeds(speeds: Sequence[float] | FloatArray, direction: str, block: int,
                    workers: int | None) -> FloatArray:
    if direction not in DIRECTIONS:
        raise InputError(f"direction = {direction!r}: valid choices are {', '.join(DIRECTIONS)}")
    check_range("block", block, "", low=1, high=10_000)
    if workers is not None:
        check_range("workers", workers, "", low=1, high=4096)
    sp = np.unique(np.asarray(speeds, dtype=float))
    if sp.size < 1:
        raise InputError("sweep: no speeds given")
    for s in (sp[0], sp[-1]):
        check_range("speed", s, "rad/s", low=0.0, high=1e5, low_open=True)
    return sp


def _block_size(block: int | None, n: int, nonlinear: bool, n_par: int) -> int:
    """Speeds per task (see :func:`sweep`, ``block``)."""
    if block is not None:
        return block
    if nonlinear:
        return 8
    return max(32, -(-n // (20 if n_par == 1 else 8 * (n_par + 1))))


def _directions(direction: str, nonlinear: bool) -> tuple[str, ...]:
    if direction == "auto":
        return ("up", "down") if nonlinear else ("up",)
    if direction == "both":
        return ("up", "down")
    return (direction,)


def _run_chains(ex: cf.Executor, template: dict[str, Any],
                chains: dict[str, list[tuple[float, ...]]], nonlinear: bool,
                progress: Callable[[int, int], None] | None,
                seed: tuple[str, list[Point], FloatArray | None] | None = None,
                share: bool = False, in_flight: int = 4) -> dict[str, list[list[Point]]]:
    """Run every block: all at once (linear) or block after block per direction (continuation,
    each block starting from the previous block's last state).

    ``seed``: the first block of one direction, already run (direction, points, last state).
    ``share``: this process runs blocks too while the executor works (linear: it takes blocks
    from the end of the queue, the executor from the front, at most ``in_flight`` at a time;
    continuation: it runs the first direction's chain, the executor the others), so a pool
    never leaves this process idle and the sweep is not slower than running it here alone.
    """
    results: dict[str, list[list[Point]]] = {d: [[] for _ in chains[d]] for d in chains}
    total = sum(len(blk) for c in chains.values() for blk in c)
    state = {"done": 0}
    pending: dict[cf.Future[Any], tuple[str, int]] = {}
    local: list[tuple[str, int, FloatArray | None, int]] = []
    own = next(iter(chains)) if (share and nonlinear) else None
    queue: collections.deque[tuple[str, int]] = collections.deque()

    def task(d: str, i: int, y0: FloatArray | None, n_per: int) -> _Task:
        return _Task(speeds=chains[d][i], y_start=y0, continuation=nonlinear,
                     orbit_periods=n_per, **template)

    def start(d: str, i: int, y0: FloatArray | None = None, n_per: int = 1) -> None:
        if d == own:
            local.append((d, i, y0, n_per))
        else:
            pending[ex.submit(run_block, task(d, i, y0, n_per))] = (d, i)

    def finish(d: str, i: int, points: list[Point], y_end: FloatArray | None) -> None:
        results[d][i] = points
        state["done"] += len(points)
        if progress is not None:
            progress(state["done"], total)
        if nonlinear and i + 1 < len(chains[d]):
            start(d, i + 1, y_end, points[-1].orbit_periods or 1)

    def harvest(block: bool) -> None:
        if block:
            cf.wait(list(pending), return_when=cf.FIRST_COMPLETED)
        for fut in [f for f in pending if f.done()]:
            d, i = pending.pop(fut)
            finish(d, i, *fut.result())

    try:
        for d in chains:
            if seed is not None and d == seed[0]:
                finish(d, 0, seed[1], seed[2])
                queue.extend((d, i) for i in range(1, len(chains[d])) if not nonlinear)
            elif nonlinear:
                start(d, 0)
            else:
                queue.extend((d, i) for i in range(len(chains[d])))
        while queue or pending or local:
            while queue and len(pending) < in_flight:
                start(*queue.popleft())
            harvest(block=False)
            job = local.pop(0) if local else (queue.pop() + (None, 1) if share and queue
                                              else None)
            if job is not None:
                finish(job[0], job[1], *run_block(task(*job)))
            elif pending:
                harvest(block=True)
    finally:
        for fut in pending:  # after a failure or an interrupt: drop the queued blocks
            fut.cancel()
    return results


def _probe(chains: dict[str, list[tuple[float, ...]]], dirs: tuple[str, ...],
           template: dict[str, Any], nonlinear: bool, n_par: int, size: int,
           min_parallel_s: float, executor: cf.Executor | None
           ) -> tuple[tuple[str, list[Point], FloatArray | None], int, str]:
    """Run the first block (backlash: the first speed) here, timed; keep ``n_par`` or fall
    back to 1 when the work left is estimated below ``min_parallel_s``. Rearranges ``chains``
    of a continuation sweep: the first direction in blocks here, each other direction one task
    (its blocks would otherwise wait for this process between blocks)."""
    d0 = dirs[0]
    first = chains[d0][0][:1 if nonlinear else PROBE_SPEEDS]
    t0 = time.perf_counter()
    points, y_end = run_block(_Task(speeds=first, y_start=None, continuation=nonlinear,
                                    **template))
    left = sum(len(b) for c in chains.values() for b in c) - len(points)
    estimate = (time.perf_counter() - t0) / len(points) * left
    if nonlinear:
        model = template["factory"](first[0])
        exact = resolve_method(model, np.zeros(2), template["settings"].method) == "exact_contact"
        estimate *= EXACT_CONTACT_COST_FACTOR if exact else NONLINEAR_COST_FACTOR
    label = "_Inline"
    if estimate < min_parallel_s:
        n_par = 1
        name = type(executor).__name__ if executor is not None else "process pool"
        label = (f"serial: {estimate:.2g} s of work left after the first block, below "
                 f"the {min_parallel_s:g} s where {name} pays off")
    rest = [v for blk in chains[d0] for v in blk][len(first):]
    chains[d0] = [first] + [tuple(rest[i:i + size]) for i in range(0, len(rest), size)]
    if nonlinear:
        if n_par > 1:
            for d in dirs[1:]:
                chains[d] = [tuple(v for blk in chains[d] for v in blk)]
    return (d0, points, y_end), n_par, label


def sweep(
    factory: ModelFactory,
    speeds: Sequence[float] | FloatArray,
    *,
    settings: SolverSettings | None = None,
    periods: int = 200,
    steady_periods: int | None = None,
    name: str = "",
    options: SweepOptions | None = None,
    direction: str = "auto",
    executor: cf.Executor | None = None,
    workers: int | None = None,
    block: int | None = None,
    progress: Callable[[int, int], None] | None = None,
    min_parallel_s: float = MIN_PARALLEL_S,
) -> SweepResult:
    """Sweep a model over pinion speeds.

    Parameters
    ----------
    factory : callable
        ``factory(speed) -> Model``, speed in rad/s; picklable for process pools and Dask
        (e.g. :class:`gear_dyn.scene.sweep.SceneModels`).
    speeds : sequence of float
        Pinion speeds in rad/s (> 0); sorted, duplicates removed.
    settings : SolverSettings or None
        Solver settings of every speed (default: the defaults).
    periods, steady_periods : int
        Transient method: mesh periods per run and of its measured window (default: half).
    name : str
        Name stored in the result (the scene's).
    options : SweepOptions or None
        Method and spectrum settings (default: steady state).
    direction : {"auto", "up", "down", "both"}
        ``auto``: up and down for nonlinear models, up only for linear ones.
    executor : concurrent.futures.Executor or None
        Where blocks run (e.g. ``distributed.Client(...).get_executor()``); it is not shut
        down. None: a process pool over ``workers`` local cores, shut down at the end.
    workers : int or None
        Local processes when ``executor`` is None, this one included (a pool of
        ``workers - 1`` beside it; default: all cores; 1 runs in-process).
    block : int or None
        Speeds per task (1..10000). None: continuation sweeps 8; linear sweeps about 20 blocks
        in one process, 8 per process in parallel, at least 32 speeds (a linear block is one
        vectorised evaluation, :func:`gear_dyn.analysis.sweep.batch.linear_block`).
    progress : callable or None
        ``progress(done, total)`` after each finished block.
    min_parallel_s : float
        The first block runs in this process and is timed; when the remaining work, estimated
        from it, is below ``min_parallel_s`` seconds, the rest runs here too (no pool is
        started, ``executor`` is not used) and ``SweepResult.executor`` says so. 0: always use
        the executor / pool.

    Returns
    -------
    SweepResult

    Raises
    ------
    InputError
        Bad speeds, options or direction; the steady method on a model it does not cover.
    SolverError
        An integration failed.
    """
    opts = options or SweepOptions()
    settings = settings or SolverSettings()
    sp = _checked_speeds(speeds, direction, 8 if block is None else block, workers)
    model = factory(float(sp[0]))
    nonlinear = not model.is_linear
    if opts.method == "steady" and not model.mesh_periodic:
        raise InputError(f"sweep method 'steady' covers the single-DOF model; this scene's model "
                         f"is {type(model).__name__}: use method 'transient'")
    dirs = _directions(direction, nonlinear)
    n_par = 1 if (executor is None and workers == 1) else (workers or os.cpu_count() or 1)
    if nonlinear and len(dirs) == 1:
        n_par = 1  # one continuation chain: its blocks run one after the other anyway
    size = _block_size(block, sp.size, nonlinear, n_par)
    chains = {d: [tuple(float(v) for v in order[i:i + size]) for i in range(0, order.size, size)]
              for d in dirs for order in [sp if d == "up" else sp[::-1]]}
    n_steady = int(periods // 2 if steady_periods is None else steady_periods)
    template: dict[str, Any] = dict(factory=factory, settings=settings, options=opts,
                                    periods=int(periods), steady_periods=n_steady)
    start = time.perf_counter()
    seed, label = None, "_Inline"
    if n_par > 1:  # time the first block here, then decide whether a pool pays off
        seed, n_par, label = _probe(chains, dirs, template, nonlinear, n_par, size,
                                    min_parallel_s, executor)
    own = executor is None or n_par == 1
    # this process works beside the pool: workers - 1 more processes make ``workers`` in all
    ex: cf.Executor = _Inline() if n_par == 1 else (
        executor if executor is not None else _default_executor(n_par - 1))
    if n_par > 1:
        label = type(ex).__name__
    try:
        results = _run_chains(ex, template, chains, nonlinear, progress, seed,
                              share=n_par > 1, in_flight=2 * n_par)
    finally:
        if own:
            ex.shutdown(wait=True, cancel_futures=True)
    curves = tuple(SweepCurve.from_points(d, [p for blk in results[d] for p in blk])
                   for d in dirs)
    orders = np.arange(1, opts.window_periods * opts.harmonics + 1) / opts.window_periods
    fn = model.natural_frequency
    return SweepResult(
        scene_name=name, curves=curves, orders=orders,
        natural_frequency=math.nan if fn is None else float(fn),
        static_load=float(model.static_load), nonlinear=nonlinear, options=opts,
        settings=settings, run_time_s=time.perf_counter() - start, executor=label,
    )
