"""Where independent tasks run: the calling process, a local process pool, or any executor.

One choice shared by the speed sweep (:mod:`gear_dyn.analysis.sweep`) and the bifurcation
diagram (:mod:`gear_dyn.analysis.motion.diagram`): ``workers=None`` (or 1) runs in the calling
process with the builtin ``map``; ``workers=N`` on a process pool of N processes (started with
``spawn``, shut down at the end); an ``executor`` (any :class:`concurrent.futures.Executor`, e.g.
a Dask ``distributed.Client(...).get_executor()``) through its own ``map``, not shut down. Both
(and the tolerance study) cut each direction's speeds into blocks (:func:`speed_blocks`) and run
them with :func:`run_blocks`, one :class:`SpeedBlock` per task.
"""

from __future__ import annotations

import concurrent.futures as cf
import multiprocessing
import signal
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any, Generic, TypeVar

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError, SolverError, check_range
from gear_dyn.geometry import check_speed

#: ``map(fn, tasks)``: the builtin or an executor's
MapFn = Callable[[Callable[[Any], Any], Iterable[Any]], Iterator[Any]]


def _leave_ctrl_c_to_the_caller() -> None:
    """Pool processes ignore Ctrl-C (SIGINT): the calling process gets it and stops them."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def check_workers(workers: int | None, executor: cf.Executor | None) -> None:
    """Refuse a bad ``workers`` (1..4096) or both ``workers`` and ``executor``.

    Raises
    ------
    InputError
        Out of range, or both given.
    """
    if workers is not None:
        check_range("workers", workers, "", low=1, high=4096)
        if executor is not None:
            raise InputError("give workers (a local process pool) or an executor, not both")


@contextmanager
def task_map(workers: int | None = None, executor: cf.Executor | None = None
             ) -> Iterator[tuple[MapFn, str]]:
    """``(map, label)`` for running tasks where the caller asked.

    Parameters
    ----------
    workers : int or None
        None or 1: the calling process; N >= 2: a process pool of N processes (each imports
        gear_dyn, so the task function and its arguments must be picklable, and a script that
        asks for it guards its top level with ``if __name__ == "__main__":``).
    executor : concurrent.futures.Executor or None
        Used as given (not together with ``workers``).

    Yields
    ------
    (callable, str)
        The ``map`` to call and where it runs: ``serial``, ``process pool, N workers`` or the
        executor's class name (``ClientExecutor`` for Dask).

    Raises
    ------
    InputError
        As :func:`check_workers`.
    SolverError
        A process of the pool ended before returning its task (``BrokenProcessPool``): the
        message names the usual cause, a script without a ``__main__`` guard.

    Notes
    -----
    Interrupted (Ctrl-C, or SIGTERM turned into an exception by ``gear-dyn``) or failed, the
    pool's processes are terminated at once rather than left to finish their tasks.
    """
    check_workers(workers, executor)
    if executor is not None:
        yield executor.map, type(executor).__name__
        return
    if workers is None or workers <= 1:
        yield map, "serial"
        return
    before = set(multiprocessing.active_children())
    pool = cf.ProcessPoolExecutor(max_workers=workers,
                                  mp_context=multiprocessing.get_context("spawn"),
                                  initializer=_leave_ctrl_c_to_the_caller)
    try:
        yield pool.map, f"process pool, {workers} workers"
    except cf.process.BrokenProcessPool as exc:
        for process in set(multiprocessing.active_children()) - before:
            process.terminate()
        raise SolverError(
            f"workers = {workers}: a process of the pool ended before returning its task "
            f"({exc}). The pool's processes start with 'spawn' and import the calling script "
            "again: a script that passes workers >= 2 must guard its top level with "
            "'if __name__ == \"__main__\":' (the processes' own traceback above says so when "
            "that is the cause); else a process was killed (out of memory?). workers = None "
            "runs in the calling process") from exc
    except BaseException:
        for process in set(multiprocessing.active_children()) - before:
            process.terminate()
        raise
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def check_speeds(speeds: Any, what: str) -> NDArray[np.float64]:
    """The speeds of a scan in rad/s, sorted, duplicates removed, each in the one speed range
    (:func:`gear_dyn.geometry.check_speed`); ``what`` names the scan in the message.

    Raises
    ------
    InputError
        No speeds, or one out of range.

    Examples
    --------
    >>> check_speeds([400.0, 300.0, 400.0], "sweep")
    array([300., 400.])
    """
    sp = np.unique(np.asarray(speeds, dtype=float))
    if sp.size < 1:
        raise InputError(f"{what}: no speeds given")
    for s in (sp[0], sp[-1]):
        check_speed(float(s))
    return sp


def speed_blocks(speeds: NDArray[np.float64], directions: Sequence[str], size: int
                 ) -> dict[str, list[tuple[float, ...]]]:
    """Each direction's speeds in its order (``up``: as sorted, ``down``: reversed), cut into
    blocks of ``size`` speeds (the last may be shorter)."""
    return {d: [tuple(float(v) for v in order[i:i + size]) for i in range(0, order.size, size)]
            for d in directions for order in [speeds if d == "up" else speeds[::-1]]}


#: what a scan does at each speed (its model factory and settings)
Job = TypeVar("Job")


@dataclass(frozen=True)
class SpeedBlock(Generic[Job]):
    """One task of a speed scan (sweep, bifurcation diagram, tolerance study).

    Attributes
    ----------
    job : object
        What the scan does at each speed: its model factory and settings (the same for every
        block of the scan; picklable for a pool).
    speeds : tuple of float
        The block's pinion speeds in rad/s, in the order evaluated.
    start : object
        Where the block's chain starts (the state the previous block of its direction ended
        in; the scan's start value for the first block, or every block not chained).
    """

    job: Job
    speeds: tuple[float, ...]
    start: Any = None


def run_blocks(run_map: MapFn, fn: Callable[[Any], tuple[list[Any], Any]],
               blocks: dict[str, list[tuple[float, ...]]], job: Any, start: Any,
               chained: bool = True, progress: Callable[[int, int], None] | None = None
               ) -> dict[str, list[Any]]:
    """Every block of every direction through ``run_map`` (the builtin ``map`` or an executor's).

    ``fn(SpeedBlock(job, speeds, state))`` returns a block's points and the state where it
    ended (``fn`` and ``job`` picklable for a pool). Chained, one call per round:
    the i-th block of every direction, each from the state where its direction's previous
    block ended (``start`` for the first). Not chained, all blocks in one call, each from
    ``start``. The tasks do not depend on ``run_map``, so neither do the points.
    ``progress(done, total)`` counts points after each block, in sweep order. Returns each
    direction's points in sweep order.
    """
    points: dict[str, list[Any]] = {d: [] for d in blocks}
    state = dict.fromkeys(blocks, start)
    total = sum(len(blk) for c in blocks.values() for blk in c)
    done = 0
    rounds = ([[(d, c[i]) for d, c in blocks.items() if i < len(c)]
               for i in range(max(len(c) for c in blocks.values()))] if chained
              else [[(d, blk) for d, c in blocks.items() for blk in c]])
    for jobs in rounds:
        tasks = [SpeedBlock(job, blk, state[d]) for d, blk in jobs]
        for (d, _blk), (pts, end) in zip(jobs, run_map(fn, tasks), strict=True):
            points[d] += pts
            state[d] = end
            done += len(pts)
            if progress is not None:
                progress(done, total)
    return points
