"""The sweep driver: speeds cut into blocks, blocks run here or on an executor, curves assembled.

Where the blocks run and why the numbers do not depend on it: :func:`sweep` and docs/sweep.md,
"Parallel runs". Linear sweeps cut the speeds into blocks of a fixed size, each evaluated on its
own; continuation sweeps (backlash) follow each direction's chain of speeds, each block starting
from the state where the previous block of its direction ended.
"""

from __future__ import annotations

import concurrent.futures as cf
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.dynamic_factor import quasi_static_model_of, quasi_static_reference
from gear_dyn.analysis.executor import (
    SpeedBlock,
    check_speeds,
    check_workers,
    run_blocks,
    speed_blocks,
    task_map,
)
from gear_dyn.analysis.sweep.batch import linear_block
from gear_dyn.analysis.sweep.orbit_jumps import find_jumps
from gear_dyn.analysis.sweep.points import steady_point, transient_point
from gear_dyn.analysis.sweep.types import (
    DIRECTIONS,
    Point,
    SweepCurve,
    SweepOptions,
    SweepResult,
)
from gear_dyn.analysis.threads import blas_limited
from gear_dyn.errors import InputError, check_range
from gear_dyn.models.base import Model
from gear_dyn.solvers import SolverSettings

FloatArray = NDArray[np.float64]
ModelFactory = Callable[[float], Model]

#: speeds per block of a continuation (backlash) sweep
CONTINUATION_BLOCK = 8
#: a linear sweep is cut into about this many blocks (progress steps, tasks for a pool) ...
LINEAR_BLOCKS = 20
#: ... of at least this many speeds (a linear block is one vectorised evaluation)
LINEAR_MIN_BLOCK = 32


@dataclass(frozen=True)
class _Job:
    """What a sweep does at each speed (the job of its :class:`.executor.SpeedBlock`)."""

    factory: ModelFactory
    settings: SolverSettings
    options: SweepOptions
    periods: int
    steady_periods: int
    continuation: bool


#: where a direction's continuation stands: (last state or None, mesh periods of its orbit)
_ChainState = tuple[FloatArray | None, int]


@blas_limited
def _run_block(block: SpeedBlock[_Job]) -> tuple[list[Point], _ChainState]:
    """Evaluate a block of speeds in order (the worker function; picklable).

    Returns the points and where the continuation stands after the block (the start of the
    next block of the same direction).
    """
    job = block.job
    y, n_prev = block.start
    if job.options.method == "steady" and not job.continuation:
        models = [job.factory(s) for s in block.speeds]
        batch = linear_block(models, block.speeds, job.settings, job.options)
        if batch is not None:
            return batch, (None, 1)
    points = []
    for s in block.speeds:
        model = job.factory(s)
        if job.options.method == "steady":
            p, y_next = steady_point(model, s, job.settings, job.options, y, n_prev)
            n_prev = p.orbit_periods or n_prev
        else:
            p, y_next = transient_point(model, s, job.settings, job.options, job.periods,
                                        job.steady_periods, y)
        points.append(p)
        if job.continuation and y_next is not None:
            y = y_next
    return points, (y, n_prev)


def _checked(speeds: Sequence[float] | FloatArray, direction: str, block: int | None,
             workers: int | None, executor: cf.Executor | None) -> FloatArray:
    if direction not in DIRECTIONS:
        raise InputError(f"direction = {direction!r}: valid choices are {', '.join(DIRECTIONS)}")
    if block is not None:
        check_range("block", block, "", low=1, high=10_000)
    check_workers(workers, executor)
    return check_speeds(speeds, "sweep")


def _block_size(block: int | None, n: int, nonlinear: bool) -> int:
    """Speeds per block (see :func:`sweep`, ``block``); never depends on the executor."""
    if block is not None:
        return block
    if nonlinear:
        return CONTINUATION_BLOCK
    return max(LINEAR_MIN_BLOCK, -(-n // LINEAR_BLOCKS))


def _directions(direction: str, nonlinear: bool) -> tuple[str, ...]:
    if direction == "auto":
        return ("up", "down") if nonlinear else ("up",)
    if direction == "both":
        return ("up", "down")
    return (direction,)


@blas_limited
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
    workers: int | None = None,
    executor: cf.Executor | None = None,
    block: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> SweepResult:
    """Sweep a model over pinion speeds.

    Runs in the calling process unless ``workers`` or ``executor`` is given; then blocks of
    speeds go out through the executor's ``map``. The numbers are the same either way (the
    blocks and what they start from do not depend on where they run).

    Parameters
    ----------
    factory : callable
        ``factory(speed) -> Model``, speed in rad/s; picklable for ``workers`` and
        ``executor`` (e.g. :class:`gear_dyn.scene.sweep.SceneModels`).
    speeds : sequence of float
        Pinion speeds in rad/s (> 0, at most 1e5); sorted, duplicates removed.
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
    workers : int or None
        Local processes (1..4096): ``None`` or 1 runs in the calling process; N >= 2 runs the
        blocks on a process pool of N processes (started with ``spawn``, shut down at the
        end; each process imports gear_dyn, so a script that asks for it guards its top level
        with ``if __name__ == "__main__":``, as for any such pool). Not together with
        ``executor``.
    executor : concurrent.futures.Executor or None
        Runs the blocks through its ``map`` (e.g. ``distributed.Client(...).get_executor()``
        for a Dask cluster); it is not shut down.
    block : int or None
        Speeds per block (1..10000). None: continuation (backlash) sweeps 8; linear sweeps about
        20 blocks of at least 32 speeds (a linear block is one vectorised evaluation,
        :func:`gear_dyn.analysis.sweep.batch.linear_block`). Blocks are the tasks of a pool and
        the steps of ``progress``. A continuation sweep runs its directions side by side, so it
        keeps at most two processes busy.
    progress : callable or None
        ``progress(done, total)`` after each finished block, in sweep order.

    Returns
    -------
    SweepResult
        With the dynamic factor K_dyn of every speed against one quasi-static run of the model
        (:mod:`gear_dyn.analysis.dynamic_factor`), as ``gear-dyn run`` computes it.

    Raises
    ------
    InputError
        Bad speeds, options, direction, block or workers, or both workers and executor given;
        the steady method on a model it does not cover.
    SolverError
        An integration failed.
    """
    opts = options or SweepOptions()
    settings = settings or SolverSettings()
    sp = _checked(speeds, direction, block, workers, executor)
    start = time.perf_counter()
    model = factory(float(sp[0]))
    nonlinear = not model.is_linear
    period = int(getattr(model, "excitation_period", 1))
    if opts.method == "steady" and period > 1:
        raise InputError(f"sweep method 'steady' takes one mesh period as the period of the "
                         f"response; this scene's transmission error repeats every {period} mesh "
                         f"periods (deviations: shaft orders): use method 'transient' with "
                         f"steady_periods >= {period}, or the tolerance study (exact over that "
                         "period)")
    if opts.method == "steady" and not model.mesh_periodic:
        raise InputError(f"sweep method 'steady' covers the single-DOF model; this scene's model "
                         f"is {type(model).__name__}: use method 'transient'")
    dirs = _directions(direction, nonlinear)
    size = _block_size(block, sp.size, nonlinear)
    n_steady = int(periods // 2 if steady_periods is None else steady_periods)
    if n_steady < period:
        raise InputError(f"steady_periods = {n_steady}: the transmission error repeats every "
                         f"{period} mesh periods (deviations: shaft orders); a window shorter "
                         f"than that misses part of the response: valid range >= {period}")

    with task_map(workers, executor) as (run_map, label):
        if progress is not None:
            progress(0, sp.size * len(dirs))  # a bar from the start, before a block is done
        # backlash: each direction a chain of blocks (continuation); linear: blocks on their own
        job = _Job(factory, settings, opts, int(periods), n_steady, nonlinear)
        points = run_blocks(run_map, _run_block, speed_blocks(sp, dirs, size), job, (None, 1),
                            chained=nonlinear, progress=progress)
    # one quasi-static reference for the whole sweep: its peak force does not depend on speed
    qs_model = quasi_static_model_of(factory, float(sp[0]), model)
    reference = None if qs_model is None else quasi_static_reference(qs_model, settings)
    jump = math.nan if reference is None else float(reference["peak_force_ratio"])
    # jumps of the response from the orbits: candidate pairs continued here, in the calling
    # process (none for a linear model: its periodic response is unique)
    curves = tuple(replace(c, jumps=find_jumps(c, factory, settings.rtol,
                                               orbits=opts.method == "steady"))
                   for c in (SweepCurve.from_points(d, points[d], jump) for d in dirs))
    orders = np.arange(1, opts.window_periods * opts.harmonics + 1) / opts.window_periods
    fn = model.natural_frequency
    return SweepResult(
        scene_name=name, curves=curves, orders=orders,
        natural_frequency=math.nan if fn is None else float(fn),
        static_load=float(model.static_load), nonlinear=nonlinear, options=opts,
        settings=settings, run_time_s=time.perf_counter() - start, executor=label,
        quasi_static=reference,
    )
