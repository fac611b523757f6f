"""The tip-relief rule constants handbook_a/handbook_b are lengths: the unit rule applies."""

from __future__ import annotations

import pytest

from gear_dyn.cli import main
from gear_dyn.errors import SceneError
from gear_dyn.modification.relief import tangential_load_per_width
from gear_dyn.scene import build_pair, parse_scene
from gear_dyn.scene.modification import relief_from_scene

BASE = {
    "gear": {"teeth_pinion": 23, "teeth_gear": 64, "module": "6 mm",
             "pressure_angle": "22.5 deg", "face_width": "50 mm"},
    "operating": {"speed": "3319 rpm", "torque": "1474.4 N*m"},
}


def _scene(**relief: object) -> dict:
    return {**BASE, "tip_relief": {"rule": "handbook", **relief}}


@pytest.mark.parametrize("key", ["handbook_a", "handbook_b"])
def test_plain_number_is_refused_with_the_in_range_reading_first(key: str) -> None:
    with pytest.raises(SceneError) as info:
        parse_scene(_scene(**{key: 7}), "s.toml")
    msg = str(info.value)
    # 7 um lies in both ranges (a: 5..13 um, b: 0..8 um), 7 mm in neither: um is proposed first
    assert f'tip_relief.{key} = 7: give a unit, e.g. "7 um" (or "7 mm"' in msg


def test_constants_with_units_reach_the_rule() -> None:
    """C_a1 = a + 0.04 w_t, C_a2 = b + 0.04 w_t um (w_t in N/mm), with a and b given in mm."""
    scene = parse_scene(_scene(handbook_a="0.013 mm", handbook_b="0 um"), "s.toml")
    mod = relief_from_scene(scene)
    w_t = tangential_load_per_width(build_pair(scene), 1474.4)  # N/mm, F_t at the pitch circle
    assert mod.pinion is not None and mod.gear is not None
    assert mod.pinion.amount == pytest.approx((13.0 + 0.04 * w_t) * 1e-6, rel=1e-12)
    assert mod.gear.amount == pytest.approx((0.0 + 0.04 * w_t) * 1e-6, rel=1e-12)


def test_out_of_range_constant_names_field_and_range() -> None:
    with pytest.raises(SceneError, match=r"tip_relief.handbook_a = '20 um' is out of range"):
        parse_scene(_scene(handbook_a="20 um"), "s.toml")


def test_cli_refuses_a_plain_constant_with_exit_2(tmp_path, capsys) -> None:
    path = tmp_path / "hb.toml"
    path.write_text(
        '[gear]\nteeth_pinion = 23\nteeth_gear = 64\nmodule = "6 mm"\nface_width = "50 mm"\n'
        '[operating]\nspeed = "3319 rpm"\ntorque = "1474.4 N*m"\n'
        '[tip_relief]\nrule = "handbook"\nhandbook_b = 4\n')
    assert main(["relief", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and 'handbook_b = 4: give a unit, e.g. "4 um"' in err[0]
