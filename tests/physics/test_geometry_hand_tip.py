"""Left-hand helices and given tip diameters / tip shortening (gear_dyn.geometry.GearPair)."""

from __future__ import annotations

import math
import tomllib

import pytest

from gear_dyn.errors import InputError, SceneError
from gear_dyn.geometry import GearPair

KW = dict(z1=23, z2=79, module=6e-3, pressure_angle=math.radians(20), face_width=70e-3, x1=0.3,
          x2=-0.1)
RIGHT = GearPair(**KW, helix_angle=math.radians(20))
LEFT = GearPair(**KW, helix_angle=-math.radians(20))

DERIVED = ("alpha_t", "beta_b", "transverse_module", "r1", "r2", "rb1", "rb2", "ra1", "ra2",
           "rf1", "rf2", "a_w", "alpha_wt", "base_pitch", "path_of_contact", "contact_ratio",
           "overlap_ratio", "backlash")


def test_left_hand_is_the_mirror_of_right_hand() -> None:
    # a mirrored pair meshes the same: every derived quantity equals the right-hand pair's
    for name in DERIVED:
        assert getattr(LEFT, name) == pytest.approx(getattr(RIGHT, name), rel=1e-14), name
    assert (LEFT.hand, RIGHT.hand, GearPair(**KW).hand) == ("left", "right", "spur")
    assert LEFT.beta == RIGHT.beta == pytest.approx(math.radians(20))
    assert LEFT.overlap_ratio == pytest.approx(1.27, abs=0.005)  # the rail pair of the issue


def test_helix_magnitude_limits_hold_for_both_hands() -> None:
    with pytest.raises(InputError, match=r"helix_angle = -0.8 rad is out of range"):
        GearPair(**KW, helix_angle=-0.8)
    with pytest.raises(InputError, match=r"0.0001 <= \|x\|"):
        GearPair(**KW, helix_angle=-1e-6)


def test_left_hand_scene_records_the_hand() -> None:
    from gear_dyn.scene import build_pair
    from gear_dyn.scene.build import scene_facts
    from gear_dyn.scene.loader import parse_scene

    text = RAIL_SCENE.replace('helix_angle = "20 deg"', 'helix_angle = "-20 deg"')
    scene = parse_scene(tomllib.loads(text), "left.toml")
    assert build_pair(scene).hand == "left"
    assert scene_facts(scene)["helix_hand"] == "left"


def test_tip_diameter_overrides_the_tip_radius() -> None:
    # Given d_a = the default tip diameter, the pair is the same; a smaller d_a1 shortens the
    # path of contact by exactly the change in sqrt(r_a1^2 - r_b1^2) (the path formula).
    same = GearPair(**KW, helix_angle=math.radians(20), tip_diameter1=2 * RIGHT.ra1,
                    tip_diameter2=2 * RIGHT.ra2)
    for name in DERIVED:
        assert getattr(same, name) == pytest.approx(getattr(RIGHT, name), rel=1e-12), name
    d_a1 = 2 * RIGHT.ra1 - 2e-3
    cut = GearPair(**KW, helix_angle=math.radians(20), tip_diameter1=d_a1)
    assert cut.ra1 == pytest.approx(d_a1 / 2, rel=1e-15)
    drop = math.sqrt(RIGHT.ra1**2 - RIGHT.rb1**2) - math.sqrt((d_a1 / 2) ** 2 - RIGHT.rb1**2)
    assert RIGHT.path_of_contact - cut.path_of_contact == pytest.approx(drop, rel=1e-12)
    assert cut.contact_ratio == pytest.approx(cut.path_of_contact / cut.base_pitch, rel=1e-15)


def test_tip_shortening_cuts_both_tips_by_k_module() -> None:
    k = 0.1
    short = GearPair(**KW, helix_angle=math.radians(20), tip_shortening=k)
    assert RIGHT.ra1 - short.ra1 == pytest.approx(k * 6e-3, rel=1e-12)
    assert RIGHT.ra2 - short.ra2 == pytest.approx(k * 6e-3, rel=1e-12)
    by_d = GearPair(**KW, helix_angle=math.radians(20), tip_diameter1=2 * short.ra1,
                    tip_diameter2=2 * short.ra2)
    assert by_d.contact_ratio == pytest.approx(short.contact_ratio, rel=1e-12)


@pytest.mark.parametrize(("kw", "message"), [
    ({"tip_diameter1": 0.100}, r"tip_diameter1 = 100 mm: the tip must lie above the base "
                               r"circle \(d_b1 = 136.943 mm, d_f1 = 135.457 mm\); valid range "
                               r"> 136.943 mm"),
    ({"tip_diameter2": 0.48}, r"tip_diameter2 = 480 mm: the tip must lie above the root circle"),
    ({"tip_diameter1": -1.0}, r"tip_diameter1 = -1 m is out of range"),
    ({"tip_shortening": -0.1}, r"tip_shortening = -0.1 is out of range"),
    ({"tip_shortening": 0.1, "tip_diameter1": 0.16}, r"not both"),
])
def test_bad_tips_are_refused(kw: dict[str, float], message: str) -> None:
    with pytest.raises(InputError, match=message):
        GearPair(**KW, helix_angle=math.radians(20), **kw)


RAIL_SCENE = """
[gear]
teeth_pinion = 23
teeth_gear = 79
module = "6 mm"
pressure_angle = "20 deg"
helix_angle = "20 deg"
face_width = "70 mm"
profile_shift_pinion = 0.3
profile_shift_gear = -0.1
[operating]
speed = "4000 rpm"
torque = "2000 N*m"
"""


def test_scene_tip_keys_reach_the_pair_and_name_the_key() -> None:
    from gear_dyn.scene import build_pair
    from gear_dyn.scene.loader import parse_scene

    text = RAIL_SCENE.replace('face_width = "70 mm"',
                              'face_width = "70 mm"\ntip_diameter_pinion = "160 mm"')
    assert build_pair(parse_scene(tomllib.loads(text), "t.toml")).ra1 == pytest.approx(0.08)
    text = RAIL_SCENE.replace('face_width = "70 mm"',
                              'face_width = "70 mm"\ntip_shortening = 0.1')
    assert build_pair(parse_scene(tomllib.loads(text), "t.toml")).ra1 == pytest.approx(
        RIGHT.ra1 - 0.1 * 6e-3, rel=1e-12)
    bad = RAIL_SCENE.replace('face_width = "70 mm"',
                             'face_width = "70 mm"\ntip_diameter_pinion = "130 mm"')
    with pytest.raises(SceneError, match=r"t.toml: gear.tip_diameter_pinion = 130 mm: the tip "
                                         r"must lie above the base circle"):
        build_pair(parse_scene(tomllib.loads(bad), "t.toml"))


def test_scene_keys_list_the_tip_inputs() -> None:
    from gear_dyn.scene.core import GEAR
    from gear_dyn.scene.reference import table_reference

    text = table_reference(GEAR)
    for key in ("tip_diameter_pinion", "tip_diameter_gear", "tip_shortening"):
        assert f"| `{key}` |" in text
    assert "| `helix_angle` | quantity | rad (e.g. deg) | 0 deg | -45 <= value <= 45 deg |" in text
