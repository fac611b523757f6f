"""One task in a forked child while the command goes on (two figures drawn at once).

matplotlib draws in one thread; a run's two PNGs are independent, so ``gear-dyn run`` draws the
time history in a forked child while it draws the spectrum itself, when a core is free for it
(:func:`spare_core`). The child only writes its file; the parent waits for it. Without a child
(no ``fork`` on this platform, other threads running, no spare core, the fork failed) or when the
child failed, the parent does the task itself, so errors surface in the parent with the
command's usual handling and exit codes.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
from collections.abc import Callable, Iterator

#: signals the command turns into exceptions (app.py): held back while forking, so that none
#: lands inside fork's own at-fork hooks (where Python ignores the exception it raises)
_HELD = (signal.SIGINT, signal.SIGTERM)


@contextlib.contextmanager
def task_in_child(task: Callable[[], object]) -> Iterator[None]:
    """Run ``task`` in a forked child during the ``with`` block; done (by the child or, if that
    failed, in this process) when the block exits normally. If the block raises (also by a
    signal), the child is killed and the exception propagates."""
    pid = 0
    try:
        with _held_signals() as mask:
            pid = _fork_for(task, mask)
        yield  # a signal that came during the fork is raised here, with pid known
        if pid:
            _, status = os.waitpid(pid, 0)
            pid, done = 0, os.waitstatus_to_exitcode(status) == 0
        else:
            done = False
    except BaseException:
        if pid:
            with contextlib.suppress(OSError):
                os.kill(pid, signal.SIGKILL)
                os.waitpid(pid, 0)
        raise
    if not done:
        task()  # no child, or it failed: do it here (its error, if any, is the command's)


@contextlib.contextmanager
def _held_signals() -> Iterator[set[int | signal.Signals] | None]:
    """Block SIGINT/SIGTERM for the block (where the platform can); yields the previous mask."""
    if not hasattr(signal, "pthread_sigmask"):
        yield None
        return
    old = signal.pthread_sigmask(signal.SIG_BLOCK, _HELD)
    try:
        yield old
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def spare_core() -> bool:
    """Whether a core is free for a child: the 1-minute load average (this process included)
    is at most the usable cores minus one. On a busy machine a child would only compete with
    its parent for the same cores, and forking costs time of its own.
    """
    try:
        cores = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        cores = os.cpu_count() or 1
    try:
        load = os.getloadavg()[0]
    except (AttributeError, OSError):
        return cores > 1
    return cores > 1 and load <= cores - 1


def _fork_for(task: Callable[[], object], mask: set[int | signal.Signals] | None) -> int:
    """The child's pid (0: not forked: no fork here, other threads running, no spare core, the
    fork failed)."""
    if not hasattr(os, "fork") or threading.active_count() > 1 or not spare_core():
        return 0
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()  # nothing buffered is written twice
    try:
        pid = os.fork()
    except OSError:
        return 0
    if pid:
        return pid
    code = 1
    try:  # the child: the task, then out without the parent's cleanup (staged output...)
        if mask is not None:
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        task()
        code = 0
    except BaseException:  # noqa: S110 - the parent redoes the task and reports the error
        pass
    finally:
        os._exit(code)


__all__ = ["task_in_child"]
