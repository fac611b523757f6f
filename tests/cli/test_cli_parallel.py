"""task_in_child: the forked task is done exactly once, by the child or else by the parent."""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from gear_dyn.cli import _parallel
from gear_dyn.cli._parallel import task_in_child

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
    assert not _parallel.spare_core()
    monkeypatch.setattr(_parallel.os, "sched_getaffinity", lambda pid: {0}, raising=False)
    monkeypatch.setattr(_parallel.os, "getloadavg", lambda: (0.0, 0.0, 0.0))
    assert not _parallel.spare_core()
