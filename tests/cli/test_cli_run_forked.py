"""`gear-dyn run` on two cores (a forerunner imports matplotlib and draws; a second child draws
half of the figures) writes what the serial command writes: the same CSV and summary, the same
figures to the 8-bit rounding of laying two parts over each other (tests/plots/test_compose.py).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest
from matplotlib.image import imread

from gear_dyn.cli import _parallel
from gear_dyn.cli.app import main

pytestmark = pytest.mark.skipif(not hasattr(os, "fork"), reason="no os.fork on this platform")


def _run(out: Path, scene: str, forked: bool, monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """Run the command; the pids of the children it forked."""
    forks: list[int] = []
    real = _parallel.fork_child

    def counting(main_: _parallel.Task, mask: object, own_group: bool = False) -> int:
        pid = real(main_, mask, own_group)  # type: ignore[arg-type]
        if pid:
            forks.append(pid)
        return pid

    with monkeypatch.context() as m:
        m.setattr(_parallel.threading, "active_count", lambda: 1)
        m.setattr(_parallel, "spare_core", lambda: forked)
        m.setattr(_parallel, "fork_child", counting)
        assert main(["run", scene, "--out", str(out), "--periods", "60"]) == 0
    return forks


def _untimed(obj: object) -> object:
    """The summary without its measured run times (``run_time_s`` wherever it is)."""
    if isinstance(obj, dict):
        return {k: _untimed(v) for k, v in obj.items() if "time_s" not in k}
    if isinstance(obj, list):
        return [_untimed(v) for v in obj]
    return obj


@pytest.mark.parametrize("scene", ["helicopter_tail", "eccentric_helical"])
def test_forked_run_writes_what_the_serial_run_writes(scene: str, tmp_path: Path,
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    assert _run(tmp_path / "serial", scene, False, monkeypatch) == []
    # the forerunner; the drawing child is forked by the forerunner (not seen here)
    assert len(_run(tmp_path / "forked", scene, True, monkeypatch)) == 1
    a, b = tmp_path / "serial", tmp_path / "forked"
    assert sorted(p.name for p in a.iterdir()) == sorted(p.name for p in b.iterdir())
    assert (a / "timeseries.csv").read_bytes() == (b / "timeseries.csv").read_bytes()
    sa, sb = (_untimed(json.loads((d / "summary.json").read_text())) for d in (a, b))
    assert sa == sb
    assert (a / "spectrum.png").read_bytes() == (b / "spectrum.png").read_bytes()
    ta, tb = (np.rint(imread(d / "time_history.png") * 255).astype(int) for d in (a, b))
    assert ta.shape == tb.shape and np.abs(ta - tb).max() <= 2
    assert np.count_nonzero(ta - tb) < 1e-3 * ta.size
