"""Progress: a bar on a terminal, a line per 10 % off a terminal (after 1 s), none with
--quiet."""

from __future__ import annotations

import io
import subprocess
import sys
from pathlib import Path

import pytest

from gear_dyn.cli.app import build_parser
from gear_dyn.cli.progress import Stages, _lines, counter

SCENE = Path(__file__).resolve().parents[2] / "examples" / "scenes" / "helicopter_tail.toml"
# every command that can run longer than ~2 s, with its required arguments
LONG = {
    "sweep": ["sweep", "s.toml", "--speeds", "1 rpm:2 rpm:2", "--out", "o"],
    "bench": ["bench", "s.toml", "--out", "o"],
    "cosim": ["cosim", "f.fmu", "--out", "o"],
    "demo": ["demo"],
    "excitation": ["excitation", "s.toml", "--out", "o"],
    "stiffness": ["stiffness", "s.toml", "--out", "o"],
    "relief": ["relief", "s.toml"],
    "fmu build": ["fmu", "build", "s.toml", "--out", "f.fmu"],
    "fmu check": ["fmu", "check", "f.fmu"],
    "contact": ["contact", "s.toml", "--out", "o", "--dynamics"],
    "bifurcation": ["bifurcation", "s.toml", "--speeds", "1 rpm:2 rpm:2", "--out", "o"],
    "response": ["response", "s.toml", "--speeds", "1 rpm:2 rpm", "--out", "o"],
}


class _Tty(io.StringIO):
    def isatty(self) -> bool:
        return True


@pytest.mark.parametrize("name", sorted(LONG))
def test_quiet_accepted(name: str) -> None:
    args = build_parser().parse_args([*LONG[name], "--quiet"])
    assert getattr(args, "quiet", getattr(args, "no_progress", None)) is True


def test_bar_on_a_terminal_only() -> None:
    tty = _Tty()
    show = counter("speed", stream=tty)
    assert show is not None
    show(3, 10)
    show(10, 10)
    # drawn in place (carriage returns) and cleared when done
    assert "0/10" in tty.getvalue() and "speed" in tty.getvalue() and "\r" in tty.getvalue()
    assert counter("speed", quiet=True, stream=_Tty()) is None
    assert counter("speed", quiet=True, stream=io.StringIO()) is None
    tty = _Tty()
    with Stages(["load", "solve"], stream=tty) as st:
        st.next()
    assert "load" in tty.getvalue() and "/2 stages" in tty.getvalue()
    plain = io.StringIO()
    with Stages(["load", "solve"], stream=plain) as st:
        st.next()
    assert plain.getvalue() == ""


def test_lines_off_a_terminal(monkeypatch: pytest.MonkeyPatch) -> None:
    import time

    clock = [100.0]
    monkeypatch.setattr(time, "perf_counter", lambda: clock[0])
    plain = io.StringIO()
    show = counter("speed", stream=plain)
    assert show is not None
    show(0, 40)
    show(5, 40)  # 12 % within the first second: silent
    clock[0] += 2.0
    for done in range(6, 41):
        show(done, 40)
    lines = plain.getvalue().splitlines()
    # one line per 10 % step from 20 % on (10 % passed inside the first second), no redraws
    assert [ln.split()[1] for ln in lines] == [f"{p}%" for p in range(20, 101, 10)]
    assert "\r" not in plain.getvalue() and lines[-1].startswith("gear-dyn: 100% (40/40 speeds")


@pytest.mark.parametrize("cmd", [
    ["sweep", str(SCENE), "--speeds", "3000 rpm:4000 rpm:40", "--workers", "1"],
    ["relief", str(SCENE)],
])
def test_no_bar_off_a_terminal(cmd: list[str], tmp_path: Path) -> None:
    if cmd[0] == "sweep":
        cmd = [*cmd, "--out", str(tmp_path / "o")]
    run = subprocess.run([sys.executable, "-m", "gear_dyn.cli", *cmd], capture_output=True,
                         text=True, check=True)
    # tqdm draws with carriage returns and block characters; none of them off a terminal
    for mark in ("\r", "█", "it/s", "stages"):
        assert mark not in run.stderr and mark not in run.stdout


@pytest.mark.skipif(not hasattr(__import__("os"), "fork") or sys.platform == "win32",
                    reason="needs a POSIX pseudo-terminal")
def test_bar_in_a_pseudo_terminal() -> None:
    # a fresh pseudo-terminal reports 0 x 0: the bar must still be drawn
    import os
    import pty

    pid, fd = pty.fork()
    if pid == 0:  # the child: the command with stderr on the terminal
        os.execv(sys.executable, [sys.executable, "-m", "gear_dyn.cli", "relief", str(SCENE)])
    out = b""
    while True:
        try:
            chunk = os.read(fd, 4096)
        except OSError:
            break
        if not chunk:
            break
        out += chunk
    os.waitpid(pid, 0)
    assert b"/2 stages" in out and b"\r" in out


def test_a_line_from_the_first_second_off_a_terminal() -> None:
    """Off a terminal the first line comes when the work has run ``after`` seconds, before any
    10 % step is reached (the first block of a sweep can take far longer); then per step. The
    stages say which one is under way. (``after`` is 1 s in the commands.)"""
    import time

    plain = io.StringIO()
    show = _lines("speed", plain, after=0.05)
    show(0, 10)
    time.sleep(0.4)
    assert plain.getvalue().startswith("gear-dyn: 0% (0/10 speeds, ")
    show(10, 10)
    assert plain.getvalue().splitlines()[-1].startswith("gear-dyn: 100% (10/10 speeds")
    plain = io.StringIO()
    with Stages(["load", "solve"], stream=plain, after=0.05) as st:
        time.sleep(0.4)
        assert plain.getvalue().startswith("gear-dyn: stage 1/2, load (")
        st.next()
        assert plain.getvalue().splitlines()[-1].startswith("gear-dyn: stage 2/2, solve (")
    quiet = io.StringIO()
    with Stages(["load"], quiet=True, stream=quiet, after=0.0):
        time.sleep(0.1)
    assert quiet.getvalue() == ""
