"""Bugs found by reading the code (issue 14), each pinned by a test that failed before the fix."""

from __future__ import annotations

import csv
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
HELI = ROOT / "gear_dyn" / "scenes" / "helicopter_tail.toml"


def test_csv_keeps_full_precision(tmp_path: Path) -> None:
    """timeseries.csv held 10 significant digits while the exact method states 1e-11 errors:
    every value must read back bit for bit."""
    from gear_dyn.io import write_csv

    rng = np.random.default_rng(1)
    x = rng.standard_normal(200) * 10.0 ** rng.integers(-20, 20, 200)
    write_csv(tmp_path / "a.csv", {"x": x, "y": x * (1 + 1e-15)})
    with open(tmp_path / "a.csv") as f:
        rows = list(csv.reader(f))[1:]
    back = np.array([[float(v) for v in r] for r in rows])
    assert np.array_equal(back[:, 0], x) and np.array_equal(back[:, 1], x * (1 + 1e-15))


def test_scene_accepts_the_periodic_method() -> None:
    """``--method periodic`` was accepted and documented but ``[solver] method = "periodic"``
    in a scene was refused."""
    from gear_dyn.scene import build_plan, parse_scene

    data = tomllib.loads(HELI.read_text())
    data["solver"] = {"method": "periodic", "periods": 20}
    plan = build_plan(parse_scene(data, "periodic.toml"))
    assert plan.settings.method == "periodic"


@pytest.mark.parametrize("method", ["RK45", "LSODA", "BDF"])
def test_budget_advice_never_suggests_the_method_that_ran(method: str) -> None:
    """The exit-3 message of a run out of its budget suggested LSODA to an LSODA run."""
    from gear_dyn.errors import SolverError
    from gear_dyn.solvers import ode, settings

    with pytest.raises(SolverError) as info:
        ode._check_nfev(settings.MAX_NFEV + 1, method, 0.1)  # noqa: SLF001
    advice = str(info.value).split("try ", 1)[1]
    assert method not in advice and ("LSODA" in advice or "Radau" in advice)


def test_rounded_zero_backlash_prints_without_sign() -> None:
    """``gear-dyn stiffness`` printed "backlash -0.000 um" for a zero-backlash centre distance
    (-8e-18 m from rounding)."""
    from gear_dyn.cli.stiffness import _um

    assert _um(-8e-18) == "0.000" and _um(-2.5e-6) == "-2.500" and _um(1e-9) == "0.001"


def test_build_stiffness_is_public() -> None:
    """Documented as ``gear_dyn.build_stiffness`` but not exported at the top level."""
    import gear_dyn as gd

    pair = gd.GearPair(23, 64, 6e-3, math.radians(22.5), 0.05)
    k = gd.build_stiffness(pair, "iso6336")
    assert k.mean == pytest.approx(gd.iso6336_stiffness(pair).k_mesh, rel=1e-12)


def test_result_has_a_short_text_and_html_repr() -> None:
    """A Result in a notebook shows its key figures, not a wall of arrays (issue 17)."""
    import gear_dyn as gd

    res = gd.run_scene(gd.load_scene("helicopter_tail"), periods=20)
    text = repr(res)
    assert len(text) < 400 and f"dynamic factor: {res.dynamic_factor:.4f}" in text
    assert "exact" in text and "20 mesh periods" in text
    html = res._repr_html_()  # noqa: SLF001
    assert html.startswith("<table>") and f"{res.dynamic_factor:.4f}" in html
