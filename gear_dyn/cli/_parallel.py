"""Work in forked children while the command goes on: the two cores of a run used at once.

matplotlib imports and draws in one thread. ``gear-dyn run`` therefore forks twice
(gear_dyn/cli/output.py):

- at its start, a :class:`Forerunner` that imports the plotting stack while the command reads
  the scene and solves, then draws the figures from the result the command sends it;
- while drawing, :func:`child_tasks`: a child that draws half of the figures (one column of the
  time history, the spectrum) while its parent draws the other half.

A child only writes files (or fills memory shared with its parent); the parent waits for it.
Without a child (no ``fork`` on this platform, other threads running, a single usable core or
all cores busy (:func:`spare_core`), the fork failed) or when the child failed, the parent does
the work itself, so errors surface in the parent with the command's usual handling and exit
codes.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
from collections.abc import Callable, Iterator, Sequence

#: signals the command turns into exceptions (app.py): held back while forking, so that none
#: lands inside fork's own at-fork hooks (where Python ignores the exception it raises)
_HELD = (signal.SIGINT, signal.SIGTERM)

Task = Callable[[], object]


class ChildTasks:
    """Tasks done in order by a forked child while the parent goes on.

    The parent can wait for any one of them (:meth:`wait`); whatever the child did not report
    done, because it failed or was never forked, the parent does itself, once.
    """

    def __init__(self, tasks: Sequence[Task]) -> None:
        self._tasks = list(tasks)
        self._done = 0  # tasks done, by the child or here, in order
        self._pid = 0
        self._progress = -1  # read end of the child's progress pipe (one byte per task)

    def start(self) -> None:
        """Fork the child (or not: then :meth:`wait` does the tasks here)."""
        r, w = os.pipe()
        self._progress = r

        def child() -> None:
            os.close(r)
            for task in self._tasks:
                task()
                os.write(w, b".")

        try:
            with _held_signals() as mask:
                self._pid = fork_child(child, mask)
            # a signal that came during the fork is raised here, with the pid known
        finally:
            os.close(w)
        if not self._pid:
            os.close(r)
            self._progress = -1

    def wait(self, index: int) -> None:
        """Return when task ``index`` is done (by the child, or else here)."""
        while self._done <= index and self._progress >= 0:
            got = os.read(self._progress, index + 1 - self._done)
            if not got:  # the child is gone: what it did not report, this process does
                self._reap()
                break
            self._done += len(got)
        while self._done <= index:
            self._tasks[self._done]()
            self._done += 1

    def finish(self) -> None:
        """Every task done (the child, exiting, is reaped later: :func:`_reap_soon`)."""
        self.wait(len(self._tasks) - 1)
        if self._progress >= 0:
            os.close(self._progress)
            self._progress = -1
        if self._pid:
            _reap_soon(self._pid)
            self._pid = 0

    def kill(self) -> None:
        """Stop the child (the command failed or was interrupted)."""
        if self._pid:
            with contextlib.suppress(OSError):
                os.kill(self._pid, signal.SIGKILL)
        self._reap()

    def _reap(self) -> None:
        if self._progress >= 0:
            os.close(self._progress)
            self._progress = -1
        if self._pid:
            with contextlib.suppress(OSError):
                os.waitpid(self._pid, 0)
            self._pid = 0


@contextlib.contextmanager
def child_tasks(*tasks: Task) -> Iterator[ChildTasks]:
    """Run ``tasks`` in order in a forked child during the ``with`` block; all done (by the
    child or, where it failed, here) when the block exits normally. If the block raises (also
    by a signal), the child is killed and the exception propagates."""
    work = ChildTasks(tasks)
    try:
        work.start()
        yield work
    except BaseException:
        work.kill()
        raise
    work.finish()


@contextlib.contextmanager
def task_in_child(task: Task) -> Iterator[None]:
    """One task in a forked child during the ``with`` block (see :func:`child_tasks`)."""
    with child_tasks(task):
        yield


class Forerunner:
    """A child forked at a command's start that gets ready (``warm``: imports) while the
    command computes, then does the one job the command sends it (:meth:`run`).

    The job is pickled to the child, so it must be a module-level function or a
    ``functools.partial`` of one with picklable arguments. If the child could not be forked,
    failed to get ready or failed at the job, :meth:`run` does the job here.
    """

    def __init__(self, warm: Task) -> None:
        self._warm = warm
        self._pid = 0
        self._jobs = -1  # write end of the pipe the job travels through
        self._done = -1  # read end of the pipe the child reports the job done through

    def start(self) -> None:
        """Fork the child (or not: then :meth:`run` does the job here)."""
        r, w = os.pipe()  # the job, to the child
        done_r, done_w = os.pipe()  # one byte back when the job is done
        warm = self._warm

        def child() -> None:
            import gc
            import pickle

            os.close(w)
            os.close(done_r)
            # a short life ended by os._exit: no cyclic collections (importing matplotlib
            # makes many objects, each collection scans them all again)
            gc.disable()
            warm()
            with os.fdopen(r, "rb") as jobs:
                job = pickle.load(jobs)
            job()
            os.write(done_w, b".")

        self._jobs, self._done = w, done_r
        try:
            with _held_signals() as mask:
                self._pid = fork_child(child, mask, own_group=True)
            # a signal that came during the fork is raised here, with the pid known
        finally:
            os.close(r)
            os.close(done_w)
        if not self._pid:
            self._close()

    def run(self, job: Task) -> None:
        """Do ``job``: send it to the child and wait until it is done (or do it here)."""
        import pickle

        done = False
        if self._pid:
            try:
                payload = pickle.dumps(job, protocol=pickle.HIGHEST_PROTOCOL)
            except (pickle.PicklingError, AttributeError, TypeError):
                payload = b""  # the job does not travel: the child is stopped, done here
            if payload:
                try:
                    done = self._send(payload)
                except BaseException:  # interrupted: the child (and its own children) stop
                    self.kill()  # before the caller cleans up what they might still write
                    raise
                if done:  # its exit is not waited for: it tears down while this goes on
                    _reap_soon(self._pid)
                else:
                    os.waitpid(self._pid, 0)
                self._pid = 0
        self.kill()
        if not done:
            job()

    def _send(self, payload: bytes) -> bool:
        """Send the pickled job; whether the child reported it done (else it failed)."""
        try:
            with os.fdopen(self._jobs, "wb") as pipe:
                self._jobs = -1
                pipe.write(payload)
        except OSError:
            pass  # the child is gone: its end of the done pipe is closed, read gives b""
        return os.read(self._done, 1) == b"."

    def _close(self) -> None:
        for fd in (self._jobs, self._done):
            if fd >= 0:
                os.close(fd)
        self._jobs = self._done = -1

    def kill(self) -> None:
        """Stop the child and the children it forked (its process group), e.g. when the
        command failed or was interrupted."""
        self._close()
        if self._pid:
            with contextlib.suppress(OSError):
                os.killpg(self._pid, signal.SIGKILL)
            with contextlib.suppress(OSError):
                os.kill(self._pid, signal.SIGKILL)  # not its group leader yet
            with contextlib.suppress(OSError):
                os.waitpid(self._pid, 0)
            self._pid = 0


@contextlib.contextmanager
def forerunner(warm: Task) -> Iterator[Forerunner]:
    """A :class:`Forerunner` for the ``with`` block; killed when the block raises or ends
    without having sent it a job."""
    runner = Forerunner(warm)
    try:
        runner.start()
        yield runner
    finally:
        runner.kill()


def forerunner_of(args: object, warm: Task) -> contextlib.AbstractContextManager[Forerunner]:
    """The forerunner ``gear-dyn`` started for this command before parsing its arguments
    (``args.plotter``, see cli/app.py), or a new one (a command called without ``main``)."""
    runner = getattr(args, "plotter", None)
    if isinstance(runner, Forerunner):
        return contextlib.nullcontext(runner)
    return forerunner(warm)


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
    """Whether another core can work beside this process: two or more usable cores and a
    1-minute load average below their number. On a machine whose cores are all busy a child
    would only compete with its parent for them, and forking costs time of its own.
    """
    try:
        cores = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        cores = os.cpu_count() or 1
    try:
        load = os.getloadavg()[0]
    except (AttributeError, OSError):
        return cores > 1
    return cores > 1 and load < cores


#: children that reported their work done and were left to exit on their own
_EXITING: list[int] = []


def _reap_soon(pid: int) -> None:
    """Reap ``pid`` now if it has exited, else at a later fork (its exit - tearing down a
    process that imported matplotlib takes milliseconds - overlaps the parent's work)."""
    _EXITING.append(pid)
    _reap_exited()


def _reap_exited() -> None:
    for pid in list(_EXITING):
        try:
            gone = os.waitpid(pid, os.WNOHANG)[0] != 0
        except ChildProcessError:
            gone = True
        if gone:
            _EXITING.remove(pid)


def can_fork() -> bool:
    """Whether :func:`fork_child` would fork: ``fork`` here, no other threads, a spare core."""
    return hasattr(os, "fork") and threading.active_count() == 1 and spare_core()


def fork_child(main: Task, mask: set[int | signal.Signals] | None, own_group: bool = False
               ) -> int:
    """Fork a child that runs ``main`` and exits (0 if it returned, 1 if it raised), without
    the parent's clean-up (staged output, exit handlers). The child's pid, or 0 when not
    forked: no fork here, other threads running, no spare core, the fork failed.

    Called with SIGINT/SIGTERM held (:func:`_held_signals`); the child sets ``mask``.
    ``own_group``: the child leads a process group of its own, so that it can be stopped
    together with the children it forks (``os.killpg``); it ignores SIGTTOU, so that writing
    to the terminal from outside the foreground group never stops it."""
    _reap_exited()
    if not can_fork():
        return 0
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()  # nothing buffered is written twice
    try:
        pid = os.fork()
    except OSError:
        return 0
    if pid:
        if own_group:
            with contextlib.suppress(OSError):  # also in the child: whichever runs first
                os.setpgid(pid, pid)
        return pid
    code = 1
    try:  # the child
        if own_group:
            os.setpgid(0, 0)
            signal.signal(signal.SIGTTOU, signal.SIG_IGN)
        if mask is not None:
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        main()
        code = 0
    except BaseException:  # noqa: S110 - the parent redoes the work and reports the error
        pass
    finally:
        os._exit(code)


__all__ = ["ChildTasks", "Forerunner", "can_fork", "child_tasks", "forerunner", "forerunner_of",
           "fork_child", "spare_core", "task_in_child"]
