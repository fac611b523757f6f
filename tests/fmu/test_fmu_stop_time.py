"""Every example scene's FMU: outputs independent of the stop time the master announces, and
of the communication step up to the solver's stated error."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gear_dyn.fmu.build import build_fmu
from gear_dyn.fmu.cosim import FmuSession

pytestmark = pytest.mark.fmu

SCENES = sorted((Path(__file__).resolve().parents[2] / "examples" / "scenes").glob("*.toml"))


def _rows(fmu: Path, names: list[str], stop: float | None, h: float, n: int) -> np.ndarray:
    with FmuSession(fmu) as s:
        s.instantiate()
        s.initialize(0.0, stop)
        rows = [s.get(names)]
        for k in range(n):
            s.step(k * h, h)
            rows.append(s.get(names))
        s.terminate()
    return np.array(rows)


@pytest.mark.parametrize("scene", SCENES, ids=[p.stem for p in SCENES])
def test_outputs_do_not_depend_on_stop_time_or_step(scene: Path, tmp_path: Path) -> None:
    """Six mesh periods at 16 steps per period, with no stop time, with the grid's end and
    with a later one announced: identical outputs to 1e-12 of each output's largest value.
    At twice the step the common points differ by at most 100 rtol of that value (the solver
    is kept across steps; only where it is read changes)."""
    built = build_fmu(scene, tmp_path / f"{scene.stem}.fmu")
    spec = built.spec
    names = [v["name"] for v in spec["variables"] if v["causality"] == "output"]
    h = 1 / (16 * spec["mesh_frequency"])
    n = 96
    free = _rows(built.path, names, None, h, n)
    scale = np.max(np.abs(free), axis=0) + 1e-300
    for stop in (n * h, 3 * n * h):
        announced = _rows(built.path, names, stop, h, n)
        assert np.all(np.abs(announced - free) <= 1e-12 * scale), (stop, names)
    coarse = _rows(built.path, names, n * h, 2 * h, n // 2)
    rtol = spec["experiment"]["tolerance"]
    assert np.all(np.abs(coarse - free[::2]) <= 100 * rtol * scale), names
