"""Forked work (gear_dyn/cli/_parallel.py): each task or job is done exactly once, by the child
or else by the parent; a child is killed when the command fails."""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from gear_dyn.cli import _parallel
from gear_dyn.cli._parallel import child_tasks, forerunner, task_in_child

pytestmark = pytest.mark.skipif(not hasattr(os, "fork"), reason="no os.fork on this platform")


def writer(path: Path, fail_in_child: bool = False) -> Callable[[], None]:
    parent = os.getpid()

    def task() -> None:
        if fail_in_child and os.getpid() != parent:
            raise RuntimeError("child fails")
        path.write_text(str(os.getpid()))

    return task


@pytest.fixture
def single_threaded(monkeypatch: pytest.MonkeyPatch) -> None:
    """As in the gear-dyn process (a test run may have left helper threads behind), on a
    machine with a core to spare (a test run keeps it busy)."""
    monkeypatch.setattr(_parallel.threading, "active_count", lambda: 1)
    monkeypatch.setattr(_parallel, "spare_core", lambda: True)


def test_the_child_does_the_task(tmp_path: Path, single_threaded: None) -> None:
    out = tmp_path / "a.txt"
    with task_in_child(writer(out)):
        pass
    assert int(out.read_text()) != os.getpid()


def test_with_other_threads_the_parent_does_it(tmp_path: Path,
                                               monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(_parallel.threading, "active_count", lambda: 2)
    monkeypatch.setattr(_parallel, "spare_core", lambda: True)
    out = tmp_path / "t.txt"
    with task_in_child(writer(out)):
        pass
    assert int(out.read_text()) == os.getpid()


def test_a_failed_child_is_redone_in_the_parent(tmp_path: Path, single_threaded: None) -> None:
    out = tmp_path / "b.txt"
    with task_in_child(writer(out, fail_in_child=True)):
        pass
    assert int(out.read_text()) == os.getpid()


def test_without_fork_the_parent_does_it(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delattr(_parallel.os, "fork")
    out = tmp_path / "c.txt"
    with task_in_child(writer(out)):
        assert not out.exists()
    assert int(out.read_text()) == os.getpid()


def test_an_error_in_the_block_kills_the_child(tmp_path: Path, single_threaded: None) -> None:
    out = tmp_path / "d.txt"

    def slow() -> None:
        time.sleep(30)
        out.write_text("late")

    t0 = time.perf_counter()
    with pytest.raises(KeyError), task_in_child(slow):
        raise KeyError("parent fails")
    assert time.perf_counter() - t0 < 10
    time.sleep(0.2)
    assert not out.exists()


def test_on_a_busy_machine_the_parent_does_it(tmp_path: Path,
                                              monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(_parallel.threading, "active_count", lambda: 1)
    monkeypatch.setattr(_parallel.os, "getloadavg", lambda: (64.0, 64.0, 64.0))
    out = tmp_path / "busy.txt"
    with task_in_child(writer(out)):
        pass
    assert int(out.read_text()) == os.getpid()


def test_spare_core_reads_the_load(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(_parallel.os, "sched_getaffinity", lambda pid: {0, 1}, raising=False)
    monkeypatch.setattr(_parallel.os, "getloadavg", lambda: (0.9, 0.0, 0.0))
    assert _parallel.spare_core()
    monkeypatch.setattr(_parallel.os, "getloadavg", lambda: (1.5, 0.0, 0.0))
    assert _parallel.spare_core()
    monkeypatch.setattr(_parallel.os, "getloadavg", lambda: (2.0, 0.0, 0.0))
    assert not _parallel.spare_core()
    monkeypatch.setattr(_parallel.os, "sched_getaffinity", lambda pid: {0}, raising=False)
    monkeypatch.setattr(_parallel.os, "getloadavg", lambda: (0.0, 0.0, 0.0))
    assert not _parallel.spare_core()


def appender(path: Path, name: str, fail_in_child: bool = False) -> Callable[[], None]:
    """A task that appends ``name pid`` to ``path`` (one line per time it is done)."""
    parent = os.getpid()

    def task() -> None:
        if fail_in_child and os.getpid() != parent:
            raise RuntimeError("child fails")
        with path.open("a") as f:
            f.write(f"{name} {os.getpid()}\n")

    return task


def lines(path: Path) -> list[tuple[str, int]]:
    return [(a, int(b)) for a, b in (line.split() for line in path.read_text().splitlines())]


def test_child_tasks_in_order_each_once(tmp_path: Path, single_threaded: None) -> None:
    out = tmp_path / "log.txt"
    with child_tasks(appender(out, "a"), appender(out, "b")) as work:
        work.wait(0)
        assert lines(out)[0][0] == "a"  # a is done when wait(0) returns (b may be, too)
    done = lines(out)
    assert [n for n, _ in done] == ["a", "b"]
    assert all(pid != os.getpid() for _, pid in done)


def test_what_the_child_did_not_finish_the_parent_does(tmp_path: Path,
                                                       single_threaded: None) -> None:
    out = tmp_path / "log.txt"
    with child_tasks(appender(out, "a"), appender(out, "b", fail_in_child=True)) as work:
        work.wait(0)
    done = lines(out)
    assert [n for n, _ in done] == ["a", "b"]
    assert done[0][1] != os.getpid() and done[1][1] == os.getpid()


def test_child_tasks_without_a_child(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(_parallel, "can_fork", lambda: False)
    out = tmp_path / "log.txt"
    with child_tasks(appender(out, "a"), appender(out, "b")) as work:
        assert not out.exists()
        work.wait(0)
        assert lines(out) == [("a", os.getpid())]
    assert lines(out) == [("a", os.getpid()), ("b", os.getpid())]


def _append_job(path: str, name: str) -> None:
    with open(path, "a") as f:
        f.write(f"{name} {os.getpid()}\n")


def _failing_job(path: str, name: str, parent: int) -> None:
    if os.getpid() != parent:
        raise RuntimeError("child fails")
    _append_job(path, name)


def _warm_log(path: Path) -> Callable[[], None]:
    def warm() -> None:
        _append_job(str(path), "warm")
    return warm


def test_the_forerunner_warms_then_does_the_job(tmp_path: Path, single_threaded: None) -> None:
    import functools

    out = tmp_path / "log.txt"
    with forerunner(_warm_log(out)) as runner:
        runner.run(functools.partial(_append_job, str(out), "job"))
    done = lines(out)
    assert [n for n, _ in done] == ["warm", "job"]
    assert done[0][1] == done[1][1] != os.getpid()  # both in the one child


def test_a_failed_forerunner_job_is_redone_here(tmp_path: Path, single_threaded: None) -> None:
    import functools

    out = tmp_path / "log.txt"
    with forerunner(lambda: None) as runner:
        runner.run(functools.partial(_failing_job, str(out), "job", os.getpid()))
    assert lines(out) == [("job", os.getpid())]


def test_a_job_that_does_not_pickle_is_done_here(tmp_path: Path, single_threaded: None) -> None:
    out = tmp_path / "log.txt"
    with forerunner(lambda: None) as runner:
        runner.run(appender(out, "local"))  # a closure: it cannot travel to the child
    assert lines(out) == [("local", os.getpid())]


def test_a_forerunner_that_failed_to_warm_leaves_the_job_here(tmp_path: Path,
                                                              single_threaded: None) -> None:
    import functools

    def warm() -> None:
        raise ImportError("no matplotlib")

    out = tmp_path / "log.txt"
    with forerunner(warm) as runner:
        runner.run(functools.partial(_append_job, str(out), "job"))
    assert lines(out) == [("job", os.getpid())]


def test_an_error_before_the_job_kills_the_forerunner(tmp_path: Path,
                                                      single_threaded: None) -> None:
    out = tmp_path / "log.txt"
    pids: list[int] = []
    with pytest.raises(KeyError), forerunner(_warm_log(out)) as runner:
        pids.append(runner._pid)
        raise KeyError("bad scene")
    assert pids[0] > 0
    with pytest.raises(ChildProcessError):
        os.waitpid(pids[0], os.WNOHANG)  # reaped: no zombie left behind


def _late_write(path: str, name: str) -> None:
    time.sleep(1.0)
    _append_job(path, name)


def _job_with_a_grandchild(path: str) -> None:
    import functools

    with child_tasks(functools.partial(_late_write, path, "grandchild")):
        _late_write(path, "child")


def test_an_interrupted_job_stops_the_child_and_its_children(tmp_path: Path,
                                                             single_threaded: None) -> None:
    """Interrupted while the forerunner works (e.g. SIGTERM while it draws), the command stops
    it and the child it forked before cleaning up: nothing writes into the output after."""
    import functools
    import signal

    out = tmp_path / "log.txt"

    def interrupt(signum: int, frame: object) -> None:
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGALRM, interrupt)
    try:
        signal.setitimer(signal.ITIMER_REAL, 0.4)
        with pytest.raises(KeyboardInterrupt), forerunner(lambda: None) as runner:
            runner.run(functools.partial(_job_with_a_grandchild, str(out)))
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    time.sleep(1.5)  # past the moment both would have written
    assert not out.exists()
