"""The dynamic factor beside ISO 6336-1 K_v compares like for like: K_dyn = F_max / F_qs,max
tends to 1 at low speed for every stiffness model (Tamminana, Kahraman & Vijayakar 2007), the
stiffness-jump overshoot F_qs,max / W is stated beside it, and the peak force at resonance is
the figure the run gave before (docs/dynamic_factor.md)."""

from __future__ import annotations

import copy
import tomllib
from typing import Any

import numpy as np
import pytest

import gear_dyn as gd
from gear_dyn.analysis.report import summarize
from gear_dyn.scene.build import ISO_DOUBLE_FACTOR
from gear_dyn.scene.packaged import scene_path


def _packaged(name: str) -> dict[str, Any]:
    return tomllib.loads(scene_path(name).read_text())


def _with(base: dict[str, Any], table: str, **values: Any) -> Any:
    d = copy.deepcopy(base)
    d.setdefault(table, {}).update(values)
    return gd.parse_scene(d)


def _quasi_static_tolerance(res: gd.Result) -> float:
    """The run at crawl speed is itself quasi-static with the reference's error terms (inertia,
    ring-down left at the next jump, sampling of the peak), so the two may differ by both."""
    return 2 * res.extra["quasi_static"]["estimated_error"]


#: 100 rpm: f_m / f_n = 0.013 (quasi-static, below the reference's 1/64), and 4096 samples per
#: mesh period still give 54 per natural period, so the run sees the ring-down after each jump
#: (at 10 rpm it would see 5: its peak would be wherever a sample falls)
CRAWL = "100 rpm"


@pytest.mark.parametrize("method", ["iso6336", "potential_energy"])
def test_quasi_static_run_gives_one(method: str) -> None:
    scene = _with(_packaged("helicopter_tail"), "stiffness", method=method)
    res = gd.run_scene(scene, speed=CRAWL, periods=4, steady_periods=2,
                       samples_per_period=4096)
    tol = _quasi_static_tolerance(res)
    assert tol < 1e-2  # the stated error is small enough for the test to mean something
    assert res.dynamic_factor == pytest.approx(1.0, abs=tol)
    # the overshoot itself is there, stated beside the figure
    assert res.extra["stiffness_jump_factor"] > 1 + tol
    assert res.peak_force_ratio == pytest.approx(
        res.dynamic_factor * res.extra["stiffness_jump_factor"], rel=1e-12)


def test_quasi_static_run_gives_one_with_tip_relief() -> None:
    # DOP853 as the scene says
    res = gd.run_scene(gd.load_scene("helicopter_tail_relief"), speed=CRAWL, periods=4,
                       steady_periods=2, samples_per_period=4096)
    tol = _quasi_static_tolerance(res) + 10 * res.extra["estimated_error"]["max_rel"]
    assert res.dynamic_factor == pytest.approx(1.0, abs=tol)


def test_rectangular_overshoot_is_the_stiffness_ratio() -> None:
    """With the ISO wave the quasi-static peak is the force right after a single -> double
    switch, W k_double / k_single (the deflection W / k_single cannot follow the jump)."""
    res = gd.run_scene(gd.load_scene("helicopter_tail"), periods=20)
    k = res.outputs["stiffness"]
    assert float(k.max() / k.min()) == pytest.approx(ISO_DOUBLE_FACTOR, rel=1e-12)
    jump = res.extra["stiffness_jump_factor"]
    assert jump == pytest.approx(ISO_DOUBLE_FACTOR, rel=res.extra["quasi_static"][
        "estimated_error"])
    s = summarize(res)
    for key in ("dynamic_factor", "peak_force_ratio", "stiffness_jump_factor",
                "stiffness_jump_definition", "quasi_static"):
        assert key in s


def test_peak_force_at_resonance_is_unchanged() -> None:
    """At the resonance peak of helicopter_tail (f_m = f_n, 7599 rpm) the peak force ratio is
    the old dynamic factor: computed here from the force series, and by the sweep's steady state
    (monodromy, a second method); K_dyn is that over the rectangular wave's 1.75."""
    scene = gd.load_scene("helicopter_tail")
    sweep = gd.sweep_scene(scene, "7300 rpm:7900 rpm:25")
    c = sweep.curves[0]
    i = int(np.nanargmax(c.peak_force_ratio))
    assert int(np.nanargmax(c.dynamic_factor)) == i  # K_dyn: F_max / W over one constant
    assert 0 < i < len(c.speed) - 1  # an interior peak: the resonance is inside the range
    res = gd.run_scene(scene, speed=float(c.speed[i]), si=True)
    force = res.outputs["mesh_force"][res.steady]
    old = float(force.max() / res.static_load)
    assert res.peak_force_ratio == old
    # exact transient over 100 steady periods against the periodic orbit: rounding only
    assert res.peak_force_ratio == pytest.approx(c.peak_force_ratio[i], rel=1e-7)
    err = res.extra["quasi_static"]["estimated_error"]
    assert res.dynamic_factor == pytest.approx(old / ISO_DOUBLE_FACTOR, rel=err)
    # the sweep's K_dyn at resonance is the run's: one reference per sweep, the run's own
    assert c.dynamic_factor[i] == pytest.approx(res.dynamic_factor, rel=1e-7)
    assert sweep.stiffness_jump_factor == res.extra["stiffness_jump_factor"]
