"""compare_scenes on real sweeps: the ranking follows the peak force, a linear response to a
transmission error scales with it exactly, and the flags fire where they should; the backlash
hint when nothing can open the gap."""

from __future__ import annotations

import copy
import math
import tomllib
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import gear_dyn
from gear_dyn.analysis.sweep import RPM
from gear_dyn.scene import load_scene, parse_scene, run_scene
from gear_dyn.scene.sweep import sweep_scene

SCENES = Path(__file__).resolve().parents[2] / "gear_dyn" / "scenes"


def linear_te_scene(amplitude: str, name: str) -> Any:
    """The packaged constant-stiffness oscillator without backlash, forced by a first-harmonic
    transmission error of ``amplitude``: a linear time-invariant system, so its dynamic force
    is proportional to the transmission error."""
    data = tomllib.loads((SCENES / "backlash_constant_stiffness.toml").read_text())
    data = copy.deepcopy(data)
    del data["backlash"]
    data["scene"]["name"] = name
    data["transmission_error"]["cos"] = [amplitude]
    return parse_scene(data)


def test_ranking_follows_the_peak_force_of_a_stronger_excitation() -> None:
    weak, strong = linear_te_scene("1 um", "te 1 um"), linear_te_scene("2 um", "te 2 um")
    speeds = "5000 rpm:6500 rpm:4"
    cmp = gear_dyn.compare_scenes([strong, weak], speeds, rtol=1e-6)
    assert cmp.baseline == "te 2 um" and cmp.ranking == ("te 1 um", "te 2 um")
    s, w = cmp.designs
    # linear in the transmission error: (F/W - 1) doubles with it, at every speed; the sweeps
    # hold the steady state to rtol = 1e-6
    for cs, cw in zip(cmp.sweeps[0].curves, cmp.sweeps[1].curves, strict=True):
        np.testing.assert_allclose(cs.peak_force_ratio - 1, 2 * (cw.peak_force_ratio - 1),
                                   rtol=1e-5)
        np.testing.assert_allclose(cs.rms_dte, 2 * cw.rms_dte, rtol=1e-5)
    assert w["peak_peak_force_ratio_delta_pct"] == pytest.approx(
        100 * ((1 + (s["peak_peak_force_ratio"] - 1) / 2) / s["peak_peak_force_ratio"] - 1),
        rel=1e-5)
    assert w["peak_rms_dte_m_delta_pct"] == pytest.approx(-50.0, rel=1e-5)
    # the same values as the scene's own sweep
    alone = sweep_scene(weak, speeds, rtol=1e-6)
    assert w["peak_peak_force_ratio"] == alone.peak("peak_force_ratio").value
    # below f_n the response rises to the top of the range: the peak lies at its end, which is
    # also the scenes' operating speed (6500 rpm)
    assert w["flags"] == ["peak_at_range_end"] and s["flags"] == ["peak_at_range_end"]
    assert w["operating_speed_rpm"] == pytest.approx(6500.0)
    assert w["operating_peak_force_ratio"] == w["peak_peak_force_ratio"]
    # a spur pair under load: the loaded contact gives a contact stress, sigma_H ~ sqrt(F)
    assert w["static_contact_stress_pa"] > 0
    assert w["peak_contact_stress_pa"] == pytest.approx(
        w["static_contact_stress_pa"] * math.sqrt(w["peak_dynamic_factor"]), rel=1e-12)


def test_linear_model_invalid_at_the_resonance_and_operating_speed_off_range() -> None:
    scene = load_scene("helicopter_tail")
    cmp = gear_dyn.compare_scenes(["helicopter_tail"], "7000 rpm:8000 rpm:5")
    row = cmp.designs[0]
    assert "linear_model_invalid_at_peak" in row["flags"]
    assert "operating_speed_outside_range" in row["flags"]
    assert "peak_at_range_end" not in row["flags"]
    # the operating speed (3319 rpm) from its own one-speed sweep, against a transient run
    # (estimated error 2e-11 of the static deflection; the two agree to the sweep's rtol 1e-8)
    run = run_scene(scene)
    assert row["operating_peak_force_ratio"] == pytest.approx(run.peak_force_ratio, rel=1e-6)
    assert any("linear model goes negative" in w for w in cmp.warnings)


def test_operating_speed_inside_the_range_is_swept_with_it() -> None:
    cmp = gear_dyn.compare_scenes(["helicopter_tail"], "3000 rpm:3600 rpm:3")
    rpm = cmp.sweeps[0].curves[0].speed / RPM
    np.testing.assert_allclose(rpm, [3000.0, 3300.0, 3319.0, 3600.0])
    assert "operating_speed_outside_range" not in cmp.designs[0]["flags"]
    row = cmp.designs[0]
    assert row["operating_peak_force_ratio"] == cmp.sweeps[0].curves[0].peak_force_ratio[2]
    assert cmp.speed_range_rpm == pytest.approx((3000.0, 3600.0))


def test_backlash_hint_when_nothing_can_open_the_gap() -> None:
    scene = load_scene("helicopter_tail_backlash")
    # the claim of the hint: with k(t) alone F/W does not depend on the load
    light, heavy = (run_scene(scene, speed="3319 rpm", torque=t, periods=60)
                    for t in ("300 N*m", "2000 N*m"))
    assert light.peak_force_ratio == pytest.approx(heavy.peak_force_ratio, rel=1e-9)
    assert any("does not scale with W" in w for w in light.extra["warnings"])
    res = sweep_scene(scene, ["3319 rpm"])
    assert any("does not scale with W" in w for w in res.warnings)
    # a transmission error can open the gap: no hint
    forced = load_scene("backlash_constant_stiffness")
    assert not sweep_scene(forced, ["3000 rpm"]).warnings
    # no backlash: no hint either
    assert not sweep_scene(load_scene("helicopter_tail"), ["3319 rpm"]).warnings


def test_which_tables_can_open_the_gap() -> None:
    from gear_dyn.scene.hints import backlash_gap_hint, load_independent_excitations
    from gear_dyn.scene.validated import Scene

    base = load_scene("helicopter_tail_backlash").tables

    def scene(**extra: Any) -> Scene:
        return Scene(source="<t>", tables={**base, **extra})
    assert load_independent_excitations(scene()) == []
    assert backlash_gap_hint(scene()) is not None
    assert backlash_gap_hint(scene(), separated=True) is None  # the gap opens anyway
    te = scene(transmission_error={"cos": [1e-6], "sin": None})
    assert load_independent_excitations(te) == ["transmission_error"]
    assert backlash_gap_hint(te) is None
    # deviations switched off excite nothing
    assert backlash_gap_hint(scene(deviations={"pattern": "none"})) is not None
    assert backlash_gap_hint(scene(deviations={"pattern": "random"})) is None
    plain = {k: v for k, v in base.items() if k != "backlash"}
    assert backlash_gap_hint(Scene(source="<t>", tables=plain)) is None
