"""Involute pair geometry against hand calculations (ISO 21771; the pairs of Liu et al. 2017 and
Jiang et al. 2018)."""

from __future__ import annotations

import math

import pytest

from gear_dyn.errors import InputError
from gear_dyn.geometry import GearPair, inverse_involute, involute, mesh_frequency, output_speed


def test_textbook_spur_pair_by_hand() -> None:
    """z 19/48, m 3.2 mm, 20 deg, standard addendum, no shift.

    By hand (mm): r1 = 3.2*19/2 = 30.4, r2 = 3.2*48/2 = 76.8, a = 107.2;
    rb1 = 30.4 cos 20 = 28.56665, rb2 = 76.8 cos 20 = 72.16839; ra1 = 33.6, ra2 = 80.0;
    sqrt(33.6^2 - 28.56665^2) = sqrt(1128.96 - 816.0535) = 17.68915;
    sqrt(80^2 - 72.16839^2) = sqrt(6400 - 5208.2765) = 34.52138;
    a sin 20 = 107.2 * 0.342020 = 36.66456; g_a = 15.54597 (15.54594 with more digits);
    p_b = pi 3.2 cos 20 = 10.053096 * 0.939693 = 9.446821; eps_a = 15.54594 / 9.446821 = 1.645626.
    Tolerance 1e-5 relative: the hand values carry 6-7 digits.
    """
    p = GearPair(19, 48, 3.2e-3, math.radians(20), 0.016)
    assert p.r1 == pytest.approx(30.4e-3, rel=1e-12)
    assert p.r2 == pytest.approx(76.8e-3, rel=1e-12)
    assert p.a_w == pytest.approx(107.2e-3, rel=1e-12)
    assert p.rb1 == pytest.approx(28.56665e-3, rel=1e-6)
    assert p.rb2 == pytest.approx(72.16839e-3, rel=1e-6)
    assert p.ra1 == pytest.approx(33.6e-3, rel=1e-12)
    assert p.path_of_contact == pytest.approx(15.54597e-3, rel=1e-5)
    assert p.base_pitch == pytest.approx(9.446821e-3, rel=1e-6)
    assert p.contact_ratio == pytest.approx(1.645626, rel=1e-5)
    assert p.backlash == pytest.approx(0.0, abs=1e-12)


def test_helical_ratios_by_hand() -> None:
    """Helical z 18/70, m_n 3 mm, 20 deg, beta 15 deg, B 30 mm.

    tan a_t = tan 20 / cos 15 = 0.376808 -> a_t = 20.6469 deg; overlap ratio
    eps_b = B sin b / (pi m_n) = 30 * 0.258819 / (pi 3) = 0.823847 (same as B tan b_b / p_bt);
    base helix: sin b_b = sin b cos a_n = 0.243210 -> b_b = 14.0761 deg (eq. 29 of Liu et al. 2017,
    'sin b_b = tan b cos a_t', would give 14.5 deg: the typo is not implemented).
    """
    p = GearPair(18, 70, 3e-3, math.radians(20), 0.03, helix_angle=math.radians(15))
    assert math.degrees(p.alpha_t) == pytest.approx(20.6469, abs=1e-4)
    assert p.overlap_ratio == pytest.approx(0.823847, rel=1e-5)
    assert math.sin(p.beta_b) == pytest.approx(math.sin(math.radians(15)) * math.cos(
        math.radians(20)), rel=1e-12)
    assert math.degrees(p.beta_b) == pytest.approx(14.0761, abs=1e-4)


def test_helicopter_tail_kinematics(heli_pair: GearPair) -> None:
    """Table 1 of Jiang et al. (2018): mesh frequency 1272 Hz, output speed 1192.7 rpm at 3319 rpm
    input.

    f_m = 23 * 3319 / 60 = 1272.283 Hz; n2 = 3319 * 23 / 64 = 1192.77 rpm (the paper truncates to
    1192.7). Exact kinematics: compared to 1e-12 against the same fractions.
    """
    w1 = 3319 * 2 * math.pi / 60
    assert mesh_frequency(heli_pair, w1) == pytest.approx(23 * 3319 / 60, rel=1e-12)
    assert round(mesh_frequency(heli_pair, w1)) == 1272
    n2 = output_speed(heli_pair, w1) * 60 / (2 * math.pi)
    assert n2 == pytest.approx(3319 * 23 / 64, rel=1e-12)
    assert math.floor(n2 * 10) / 10 == pytest.approx(1192.7)


def test_shifted_centre_distance_and_backlash() -> None:
    """Moving the centres apart by d raises a_wt and opens backlash ~ 2 d sin a_wt.

    For a small offset d, j_n = 2 d sin(a_w) to first order (any gear text): d = 0.1 mm,
    a = 20 deg gives 68.4 um; tolerance 1 % covers the second-order term.
    """
    p0 = GearPair(19, 48, 3.2e-3, math.radians(20), 0.016)
    p = GearPair(19, 48, 3.2e-3, math.radians(20), 0.016, center_distance=p0.a_w + 1e-4)
    assert p.alpha_wt > p0.alpha_wt
    assert p.contact_ratio < p0.contact_ratio
    assert p.backlash == pytest.approx(2e-4 * math.sin(math.radians(20)), rel=1e-2)


def test_profile_shift_zero_backlash_center() -> None:
    """x1 = 0.5, x2 = 0: inv a_w = inv a + 2 tan a (x1+x2)/(z1+z2) and zero backlash there."""
    p = GearPair(12, 40, 2e-3, math.radians(20), 0.02, x1=0.5)
    inv_w = involute(math.radians(20)) + 2 * math.tan(math.radians(20)) * 0.5 / 52
    a_w = 52e-3 * math.cos(math.radians(20)) / math.cos(inverse_involute(inv_w))
    assert p.a_w == pytest.approx(a_w, rel=1e-12)
    assert p.backlash == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        (dict(module=-6e-3), "module"),
        (dict(module=0.0), "module"),
        (dict(z1=0), "z1"),
        (dict(z1=10), "undercut"),
        (dict(face_width=-1.0), "face_width"),
        (dict(addendum_coef=0.5, clearance_coef=0.25), "contact_ratio|mesh"),
        (dict(x1=1.4), "pointed"),
        (dict(center_distance=0.05), "center_distance"),
    ],
)
def test_impossible_pairs_are_refused(kwargs: dict, match: str) -> None:
    base = dict(z1=19, z2=48, module=3.2e-3, pressure_angle=math.radians(20), face_width=0.016)
    base.update(kwargs)
    with pytest.raises(InputError, match=match):
        GearPair(**base)
