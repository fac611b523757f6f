"""Where independent tasks run: the calling process, a local process pool, or any executor.

One choice shared by the speed sweep (:mod:`gear_dyn.analysis.sweep`) and the bifurcation
diagram (:mod:`gear_dyn.analysis.motion.diagram`): ``workers=None`` (or 1) runs in the calling
process with the builtin ``map``; ``workers=N`` on a process pool of N processes (started with
``spawn``, shut down at the end); an ``executor`` (any :class:`concurrent.futures.Executor`, e.g.
a Dask ``distributed.Client(...).get_executor()``) through its own ``map``, not shut down.
"""

from __future__ import annotations

import concurrent.futures as cf
import multiprocessing
import signal
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from typing import Any

from gear_dyn.errors import InputError, check_range

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
    except BaseException:
        for process in set(multiprocessing.active_children()) - before:
            process.terminate()
        raise
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
