"""Every packaged scene at pinion speeds from 1 to 100 000 rpm: it runs or it is refused.

``gear-dyn run`` (in-process, :func:`gear_dyn.cli.app.main`) on a copy of each packaged scene
with ``[operating] speed`` set to 1, 10, ..., 100 000 rpm returns 0 (and the run's mesh
frequency is ``n z1 / 60``), or 2 with one stderr line naming ``operating.speed`` and a valid
range (of the speed itself, or of the natural periods a solver run may span at that speed). Never 1
(an internal error): the backlash scene at 1 rpm once ended in a ZeroDivisionError of the contact
root finder (velocities of 1e-316 m/s, rounding noise of a settled response, whose secant had equal
end values).

Two mesh periods (``--periods 2``) are enough to reach every part of a run (transient, error
estimate, stability check, figures). Below 100 rpm the runs take ``--method auto``: there a mesh
period spans thousands of natural periods, and the scenes' explicit DOP853 needs ~1.8e4 steps per
mesh period (the run says so in a warning); with it one run at 1 rpm takes about a minute.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest

from gear_dyn.cli.app import main
from gear_dyn.scene import load_scene
from gear_dyn.scene.packaged import packaged_names, scene_path

SPEEDS_RPM = (1, 10, 100, 1_000, 10_000, 100_000)
#: below this speed the runs use --method auto (see the module docstring)
EXPLICIT_METHOD_FROM_RPM = 100

pytestmark = pytest.mark.slow


def scene_at(name: str, rpm: int, folder: Path) -> Path:
    """A copy of packaged scene ``name`` with ``[operating] speed = "<rpm> rpm"``."""
    text, n = re.subn(r'(?m)^speed\s*=\s*"[^"]*"', f'speed = "{rpm} rpm"',
                      scene_path(name).read_text(encoding="utf-8"))
    assert n == 1, f"{name}: expected one speed line, found {n}"
    path = folder / f"{name}_{rpm}rpm.toml"
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize("rpm", SPEEDS_RPM)
@pytest.mark.parametrize("name", packaged_names())
def test_runs_or_is_refused_with_the_valid_range(name: str, rpm: int, tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    path = scene_at(name, rpm, tmp_path)
    scene = load_scene(path)
    assert scene.get("operating")["speed"] == pytest.approx(rpm * math.pi / 30, rel=1e-12)
    args = ["run", str(path), "--out", str(tmp_path / "out"), "--periods", "2"]
    if rpm < EXPLICIT_METHOD_FROM_RPM:
        args += ["--method", "auto"]
    code = main(args)
    captured = capsys.readouterr()
    assert code in (0, 2), f"exit {code}: {captured.err}"
    if code == 2:  # the speed out of its range, or a run too long for the solver at that speed
        lines = captured.err.splitlines()
        assert len(lines) == 1, captured.err
        assert "operating.speed" in lines[0] and "valid range" in lines[0], lines[0]
        return
    summary = json.loads((tmp_path / "out" / "summary.json").read_text(encoding="utf-8"))
    z1 = scene.get("gear")["teeth_pinion"]
    assert summary["mesh_frequency_hz"] == pytest.approx(rpm * z1 / 60, rel=1e-12)
    # two periods may be all transient (the eccentric pair at 10 000 rpm pulls on the teeth
    # throughout: a negative peak), so only finiteness is a property of every run here
    assert math.isfinite(summary["dynamic_factor"]) and math.isfinite(summary["rms_dte_m"])
