"""``gear-dyn sweep --workers 2`` stopped by SIGTERM or Ctrl-C while its pool computes: exit
143 / 130, one line on stderr, the previous output folder kept as it was, no pool process left.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from child_signals import default_ctrl_c

ROOT = Path(__file__).resolve().parents[2]
BACKLASH = ROOT / "gear_dyn" / "scenes" / "helicopter_tail_backlash.toml"


def _children(pid: int) -> list[int]:
    out = subprocess.run(["pgrep", "-P", str(pid)], capture_output=True, text=True).stdout
    return [int(x) for x in out.split()]


def _ignores_sigint(pid: int) -> bool:
    """Whether the process ignores SIGINT (Linux: the SigIgn mask in /proc/PID/status)."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except FileNotFoundError:
        return False
    mask = next(int(ln.split()[1], 16) for ln in status.splitlines() if ln.startswith("SigIgn"))
    return bool(mask & (1 << (signal.SIGINT - 1)))


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (FileNotFoundError, ProcessLookupError):
        return False
    return state != "Z"


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc, uses pgrep")
@pytest.mark.parametrize(("sig", "group", "code", "said"), [
    (signal.SIGTERM, False, 143, "terminated (SIGTERM)"),  # the command alone, e.g. kill PID
    (signal.SIGINT, True, 130, "interrupted"),  # Ctrl-C: the whole foreground group
])
def test_stopped_while_the_pool_computes(tmp_path: Path, sig: int, group: bool, code: int,
                                         said: str) -> None:
    out = tmp_path / "out"
    out.mkdir()
    (out / "previous.csv").write_text("kept\n")
    # DOP853 pinned: 4000 speeds are minutes of work (400 took 20 s on an idle machine) in
    # blocks of speeds, so the pool is still busy when the signal comes, however loaded the
    # machine is
    cmd = [sys.executable, "-m", "gear_dyn.cli", "sweep", str(BACKLASH), "--speeds",
           "3000 rpm:16000 rpm:4000", "--workers", "2", "--method", "DOP853", "--out", str(out),
           "--quiet"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True, env={**os.environ, "MPLBACKEND": "Agg"},
                            preexec_fn=default_ctrl_c)
    try:
        deadline = time.monotonic() + 120
        # spawn's resource tracker and the two workers, each past its start-up (imports):
        # the workers ignore SIGINT from there on (a Ctrl-C while a new process still imports
        # gear_dyn is its own: Python prints that process's KeyboardInterrupt)
        while sum(_ignores_sigint(p) for p in _children(proc.pid)) < 3:
            assert proc.poll() is None and time.monotonic() < deadline, proc.communicate()
            time.sleep(0.1)
        time.sleep(0.5)  # the workers are on their blocks
        pool = _children(proc.pid)
        if group:
            os.killpg(proc.pid, sig)
        else:
            proc.send_signal(sig)
        _stdout, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    assert proc.returncode == code
    # one line: the pool's processes ignore Ctrl-C and are stopped by the command
    assert err.count("\n") == 1 and said in err and "no partial output was kept" in err, err
    assert sorted(p.name for p in out.iterdir()) == ["previous.csv"]
    assert (out / "previous.csv").read_text() == "kept\n"
    deadline = time.monotonic() + 30
    while any(_alive(p) for p in pool) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not any(_alive(p) for p in pool)
