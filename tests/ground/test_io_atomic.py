"""Files and output folders are written whole or not at all (gear_dyn.io), also when the
process is killed while it writes."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from child_signals import default_ctrl_c

import gear_dyn.io as gio
from gear_dyn.errors import InputError

HELI = Path(__file__).resolve().parents[2] / "examples" / "scenes" / "helicopter_tail.toml"


def _hidden(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.startswith("."))


def _snapshot(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def test_write_bytes_replaces_whole_and_leaves_no_temp(tmp_path: Path) -> None:
    target = tmp_path / "a.txt"
    target.write_text("old")
    gio.write_text(target, "new content")
    assert target.read_text() == "new content"
    assert _hidden(tmp_path) == []


def test_failed_write_keeps_the_old_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The rename is the last step: if anything fails before it, the old file is untouched
    and the temporary file is removed."""
    target = tmp_path / "a.txt"
    target.write_text("old")

    def boom(src: str, dst: str) -> None:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(gio.os, "replace", boom)
    with pytest.raises(InputError, match=r"a.txt: cannot write \(No space left on device\); "
                       "nothing was changed"):
        gio.write_text(target, "new")
    assert target.read_text() == "old"
    assert _hidden(tmp_path) == []


def test_files_get_the_usual_permissions(tmp_path: Path) -> None:
    """Like open(): 0666 and 0777 minus the umask (mkstemp alone would give 0600)."""
    mask = os.umask(0o022)
    os.umask(mask)
    f = gio.write_text(tmp_path / "x.txt", "x")
    assert f.stat().st_mode & 0o777 == 0o666 & ~mask
    with gio.staged_output(tmp_path / "out") as tmp:
        gio.write_text(tmp / "y.txt", "y")
    assert (tmp_path / "out").stat().st_mode & 0o777 == 0o777 & ~mask


def test_write_into_a_missing_folder_is_an_input_error(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="cannot write here"):
        gio.write_text(tmp_path / "no" / "such" / "x.txt", "x")
    with pytest.raises(InputError, match="is a folder, expected a file name"):
        gio.write_text(tmp_path, "x")
    with pytest.raises(InputError, match="is a folder, expected a file name"):
        gio.write_text("", "x")
    assert _hidden(tmp_path) == []


def test_staged_output_swaps_the_whole_folder(tmp_path: Path) -> None:
    """The new output replaces the old one as a whole: files of the old run that the new run
    does not write are gone, nothing is mixed."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "stale.csv").write_text("from an older run")
    (out / "summary.json").write_text("{}")
    with gio.staged_output(out) as tmp:
        assert tmp.parent == tmp_path and tmp != out
        gio.write_json(tmp / "summary.json", {"a": 1.0, "b": float("nan")})
    assert sorted(p.name for p in out.iterdir()) == ["summary.json"]
    assert (out / "summary.json").read_text() == '{\n  "a": 1.0,\n  "b": null\n}\n'
    assert _hidden(tmp_path) == []


@pytest.mark.parametrize("exc", [RuntimeError("bug"), KeyboardInterrupt()])
def test_staged_output_failure_keeps_the_previous_folder(tmp_path: Path,
                                                         exc: BaseException) -> None:
    out = tmp_path / "out"
    out.mkdir()
    (out / "summary.json").write_text("previous")
    with pytest.raises(type(exc)), gio.staged_output(out) as tmp:
        gio.write_text(tmp / "summary.json", "half")
        raise exc
    assert _snapshot(out) == {"summary.json": b"previous"}
    assert _hidden(tmp_path) == []


def test_a_folder_with_other_things_is_never_replaced(tmp_path: Path) -> None:
    """--out pointing at a folder that holds a scene, notes or a subfolder (e.g. the scene's
    own folder): refused before anything is written, since the swap would delete them."""
    runs = tmp_path / "runs"
    runs.mkdir()
    (runs / "my.toml").write_text("[gear]\n")
    (runs / "notes.txt").write_text("precious")
    before = _snapshot(runs)
    with pytest.raises(InputError, match=r"holds 2 item\(s\) gear_dyn does not write "
                       r"\(my.toml, notes.txt\)"), gio.staged_output(runs):
        raise AssertionError("never reached")
    assert _snapshot(runs) == before
    (runs / "my.toml").unlink()
    (runs / "notes.txt").unlink()
    (runs / "sub").mkdir()
    with pytest.raises(InputError, match=r"\(sub\)"), gio.staged_output(runs):
        raise AssertionError("never reached")
    assert _hidden(tmp_path) == []


def test_the_current_folder_is_never_replaced(tmp_path: Path,
                                             monkeypatch: pytest.MonkeyPatch) -> None:
    work = tmp_path / "work"
    (work / "sub").mkdir(parents=True)
    monkeypatch.chdir(work / "sub")
    for target in (".", "..", str(work)):
        with pytest.raises(InputError, match="current folder"), gio.staged_output(target):
            raise AssertionError("never reached")
    assert (work / "sub").is_dir()


def test_the_cli_refuses_the_scene_folder_as_output(tmp_path: Path) -> None:
    """gear-dyn run runs/my.toml --out runs: exit 2, scene and notes kept."""
    from gear_dyn.cli.app import main

    runs = tmp_path / "runs"
    runs.mkdir()
    scene = runs / "my.toml"
    scene.write_bytes(HELI.read_bytes())
    (runs / "notes.txt").write_text("precious")
    assert main(["run", str(scene), "--out", str(runs), "--periods", "2"]) == 2
    assert scene.read_bytes() == HELI.read_bytes() and (runs / "notes.txt").exists()


def test_staged_output_refuses_a_file_as_target(tmp_path: Path) -> None:
    f = tmp_path / "out"
    f.write_text("not a folder")
    with pytest.raises(InputError, match="not a folder"), gio.staged_output(f):
        pass
    assert f.read_text() == "not a folder"


def _dead_pid() -> int:
    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait()
    return p.pid


def test_leftovers_of_a_killed_process_are_cleaned(tmp_path: Path) -> None:
    """A .partial folder of a dead process is removed by the next staged_output; one of a live
    process (ours) is left alone."""
    dead = _dead_pid()
    stale = tmp_path / f".out.{dead}.abc123.partial"
    stale.mkdir()
    (stale / "timeseries.csv").write_text("half")
    live = tmp_path / f".out.{os.getpid()}.xyz.partial"
    live.mkdir()
    with gio.staged_output(tmp_path / "out") as tmp:
        gio.write_text(tmp / "a", "a")
    assert not stale.exists() and live.exists()
    live.rmdir()
    assert _hidden(tmp_path) == []


def test_killed_inside_the_swap_the_previous_output_comes_back(tmp_path: Path) -> None:
    """Killed between 'old folder moved aside' and 'new folder moved in': the target is
    missing and .out.PID.*.old holds the complete previous output; the next staged_output
    puts it back before doing anything else."""
    dead = _dead_pid()
    old = tmp_path / f".out.{dead}.q1w2e3.old"
    old.mkdir()
    (old / "summary.json").write_text("previous")
    target = tmp_path / "out"
    with pytest.raises(RuntimeError), gio.staged_output(target):
        assert _snapshot(target) == {"summary.json": b"previous"}
        raise RuntimeError("this run fails")
    assert _snapshot(target) == {"summary.json": b"previous"}
    assert _hidden(tmp_path) == []


# ---------------------------------------------------------------------------------------------
# real processes killed while they write


def _start_run(out: Path, cwd: Path) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, "-m", "gear_dyn.cli", "run", str(HELI), "--out", str(out),
         "--periods", "6000"],
        cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        env={**os.environ, "MPLBACKEND": "Agg"}, preexec_fn=default_ctrl_c,
    )


def _wait_for_partial(proc: subprocess.Popen[str], folder: Path, timeout: float = 240) -> bool:
    """Poll until the run has created its staging folder (it is writing), or it ended."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if any(p.name.endswith(".partial") for p in folder.iterdir()):
            return True
        if proc.poll() is not None:
            return False
        time.sleep(0.002)
    raise AssertionError("the run neither wrote nor ended")


@pytest.fixture(scope="module")
def previous_output(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A complete output folder of a first run, to be protected."""
    base = tmp_path_factory.mktemp("prev")
    out = base / "out"
    p = _start_run(out, base)
    _, err = p.communicate(timeout=300)
    assert p.returncode == 0, err
    return out


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT, signal.SIGKILL])
def test_signal_while_writing_keeps_previous_output_whole(
    sig: signal.Signals, previous_output: Path, tmp_path: Path
) -> None:
    """A second run into an existing folder is killed while it writes its files: the folder
    still holds the complete first output (byte for byte). SIGTERM and SIGINT end cleanly
    (exit 143 / 130, one stderr line, no temporary folder); SIGKILL cannot be caught and leaves
    a hidden .partial folder, which the next run removes."""
    out = tmp_path / "out"
    os.mkdir(out)
    for f in previous_output.iterdir():
        (out / f.name).write_bytes(f.read_bytes())
    before = _snapshot(out)
    proc = _start_run(out, tmp_path)
    # the staging folder appears after the simulation, when the files (plots, CSV) are being
    # written: 6000 mesh periods make a 47 MB CSV, ~1.5 s of writing (4 periods took 0.2 s,
    # and on a loaded machine the run sometimes finished before the signal)
    assert _wait_for_partial(proc, tmp_path)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=300)
    assert proc.returncode != 0, "the run finished before the signal"
    assert _snapshot(out) == before
    if sig == signal.SIGKILL:
        assert proc.returncode == -signal.SIGKILL
        assert any(n.endswith(".partial") for n in _hidden(tmp_path))
        # the next staging of the same folder cleans the dead run's leftovers
        with pytest.raises(RuntimeError), gio.staged_output(out):
            raise RuntimeError("stop before swapping")
        assert _snapshot(out) == before
    else:
        assert proc.returncode == {signal.SIGTERM: 143, signal.SIGINT: 130}[sig], err
        assert err.count("\n") == 1 and "no partial output was kept" in err
    assert _hidden(tmp_path) == []


def test_signal_while_writing_a_new_folder_leaves_none(tmp_path: Path) -> None:
    """Killed while writing a new output folder: no folder at all (never a partial one)."""
    out = tmp_path / "fresh"
    proc = _start_run(out, tmp_path)
    assert _wait_for_partial(proc, tmp_path)
    proc.send_signal(signal.SIGTERM)
    proc.communicate(timeout=300)
    assert proc.returncode == 143 and not out.exists()
    assert _hidden(tmp_path) == []


def test_forked_workers_still_die_on_sigterm() -> None:
    """cli.main's SIGTERM handler is inherited by forked workers (a sweep's process pool on
    Linux): there it must not turn SIGTERM into an exception the worker could swallow; the
    worker dies by the signal, as it would without gear_dyn."""
    import gear_dyn.cli.app as cli

    old = signal.signal(signal.SIGTERM, cli._on_sigterm)  # noqa: SLF001
    cli._MAIN_PID.append(os.getpid())  # noqa: SLF001
    try:
        pid = os.fork()
        if pid == 0:  # the worker: wait to be terminated
            try:
                time.sleep(30)
            finally:
                os._exit(7)
        time.sleep(0.2)
        os.kill(pid, signal.SIGTERM)
        _, status = os.waitpid(pid, 0)
        assert os.WIFSIGNALED(status) and os.WTERMSIG(status) == signal.SIGTERM
    finally:
        cli._MAIN_PID.pop()  # noqa: SLF001
        signal.signal(signal.SIGTERM, old)


@pytest.mark.skipif(not hasattr(signal, "pthread_kill"),
                    reason="signal.pthread_kill (to send SIGTERM to one thread) is POSIX only")
def test_signal_held_when_another_thread_receives_it() -> None:
    """The staging folder's creation and the swap hold SIGINT/SIGTERM even when the kernel hands
    the signal to another thread of the process (a BLAS worker with OPENBLAS_NUM_THREADS=2, a
    progress bar's monitor): the block runs to its end, then the handler runs once. A mask of
    the main thread alone let the handler run inside the block (a run killed there left an
    empty .partial folder: seen once in CI's two-BLAS-thread suite)."""
    calls: list[str] = []

    def handler(signum: int, frame: object) -> None:
        calls.append("handler")
        raise RuntimeError("delivered")

    old = signal.signal(signal.SIGTERM, handler)
    stop = threading.Event()
    other = threading.Thread(target=stop.wait)
    other.start()
    try:
        with pytest.raises(RuntimeError, match="delivered"), gio._signals_deferred():  # noqa: SLF001
            assert other.ident is not None
            signal.pthread_kill(other.ident, signal.SIGTERM)
            time.sleep(0.2)  # the main thread runs pending handlers during a sleep
            calls.append("block ended")
        assert calls == ["block ended", "handler"]
    finally:
        stop.set()
        other.join()
        signal.signal(signal.SIGTERM, old)
