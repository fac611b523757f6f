"""The [iso] table: where K_v's deviations, load and tip relief come from, and how absent values
are stated."""

from __future__ import annotations

import pytest

import gear_dyn as gd
from gear_dyn.errors import SceneError
from gear_dyn.scene import parse_scene
from gear_dyn.scene.iso import iso_kv_summary, scene_iso_kv
from gear_dyn.scene.modification import relief_from_scene

BASE = {
    "gear": {"teeth_pinion": 23, "teeth_gear": 64, "module": "6 mm",
             "pressure_angle": "22.5 deg", "face_width": "50 mm"},
    "operating": {"speed": "3319 rpm", "torque": "1474.4 N*m"},
}


def _scene(**iso: object) -> gd.Scene:
    return parse_scene({**BASE, "iso": iso}, "s.toml")


def test_explicit_deviations_and_application_factor_are_used() -> None:
    kv, src = scene_iso_kv(_scene(f_pb="6 um", f_falpha="0.004 mm", application_factor=1.25))
    w = 1.25 * 1474.4 / 0.069 / 0.05  # K_A F_t / b in N/m, F_t = T1 / r1
    assert kv.line_load == pytest.approx(w, rel=1e-12)
    assert kv.b_p[0] == pytest.approx(kv.c_single * 6e-6 / w, rel=1e-12)
    assert kv.b_f[0] == pytest.approx(kv.c_single * 4e-6 / w, rel=1e-12)
    assert src["deviations"] == "[iso] f_pb, f_falpha"


def test_a_plain_deviation_is_refused_with_um_first() -> None:
    with pytest.raises(SceneError, match=r'iso.f_pb = 6: give a unit, e.g. "6 um"'):
        _scene(f_pb=6)


def test_grade_given_is_not_called_assumed() -> None:
    _, src = scene_iso_kv(_scene(accuracy_grade=4))
    assert src["deviations"] == "ISO 1328-1 grade 4"


def test_tip_relief_amount_is_c_a() -> None:
    scene = gd.load_scene("helicopter_tail_relief")
    mod = relief_from_scene(scene)
    c_a = max(r.amount for r in (mod.pinion, mod.gear) if r is not None)
    kv, src = scene_iso_kv(scene)
    assert kv.tip_relief == c_a > 0
    assert kv.b_k == pytest.approx(abs(1 - kv.c_single * c_a / kv.line_load), rel=1e-12)
    assert src["tip_relief"] == "larger amount of [tip_relief]"


def test_running_in_relief_needs_sigma_hlim() -> None:
    kv, src = scene_iso_kv(_scene(running_in="case_hardened", sigma_hlim="1500 MPa"))
    assert kv.tip_relief == pytest.approx(((1500 / 97 - 18.45) ** 2 / 18 + 1.5) * 1e-6)
    assert src["tip_relief"].startswith("running-in C_ay")
    kv, src = scene_iso_kv(_scene(running_in="case_hardened"))
    assert kv.tip_relief == 0.0 and src["tip_relief"] == "no tip relief (C_a = 0)"


def test_zero_load_states_that_kv_is_not_defined() -> None:
    scene = parse_scene({**BASE, "operating": {"speed": "3319 rpm", "torque": 0}}, "s.toml")
    assert iso_kv_summary(scene)["k_v"] is None


def test_through_hardened_without_sigma_hlim_is_refused() -> None:
    with pytest.raises(SceneError, match=r"iso.sigma_hlim: missing"):
        iso_kv_summary(_scene(running_in="through_hardened"))


def test_a_figure_the_formulas_cannot_take_is_noted_not_raised(monkeypatch) -> None:
    """K_v is beside the run: where ISO has no value (here eps_gamma refused), the run goes on."""
    import gear_dyn.stiffness.iso_kv as kv_mod

    def refuse(eps: float) -> None:
        raise kv_mod.InputError(f"eps_gamma = {eps}: out of range")

    monkeypatch.setattr(kv_mod, "cv_coefficients", refuse)
    s = iso_kv_summary(_scene())
    assert s["k_v"] is None and "eps_gamma" in s["note"]
