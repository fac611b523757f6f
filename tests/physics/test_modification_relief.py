"""Tip relief curves, height/length conversion and recommended amounts (Wang et al. 2024;
Han n.d.)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gear_dyn.errors import InputError
from gear_dyn.geometry import GearPair
from gear_dyn.modification import (
    CURVES,
    ProfileModification,
    TipRelief,
    height_from_length,
    length_from_height,
    long_relief_length,
    recommended_relief,
    relief_shape,
)


@pytest.fixture
def tail() -> GearPair:
    """The helicopter tail pair (Jiang et al. 2018) treated as spur: z 23/64, m 6 mm, 22.5 deg,
    B 50 mm."""
    return GearPair(23, 64, 6e-3, math.radians(22.5), 50e-3, youngs_modulus1=207e9,
                    youngs_modulus2=207e9)


@pytest.mark.parametrize("curve", CURVES)
def test_curves_start_at_zero_and_reach_amount_at_tip(curve: str) -> None:
    r = TipRelief(amount=30e-6, length=4e-3, curve=curve)
    # exact end values: f(0) = 0 and f(1) = 1 (sin(pi/2) = 1 to rounding, hence 1e-18 m)
    assert r.depth(0.0) == 0.0
    assert abs(float(r.depth(4e-3)) - 30e-6) < 1e-18
    # no relief before the start, the full amount beyond the tip
    assert r.depth(-1e-3) == 0.0 and abs(float(r.depth(5e-3)) - 30e-6) < 1e-18
    # monotone rise in between
    x = np.linspace(0, 4e-3, 201)
    assert np.all(np.diff(r.depth(x)) > 0)


@pytest.mark.parametrize("curve", CURVES)
def test_curve_slope_matches_finite_difference(curve: str) -> None:
    u = np.linspace(0.05, 0.95, 19)
    h = 1e-6
    f_hi, _ = relief_shape(u + h, curve)
    f_lo, _ = relief_shape(u - h, curve)
    _, df = relief_shape(u, curve)
    # central difference error ~ h^2 f''' ~ 1e-12 relative; 1e-7 leaves room for rounding
    np.testing.assert_allclose(df, (f_hi - f_lo) / (2 * h), rtol=1e-7)


def test_power_curve_exponents() -> None:
    u = 0.5
    expected = {"linear": 0.5, "yoshio": 0.5**1.2, "walker": 0.5**1.5, "parabolic": 0.25}
    for curve, value in expected.items():
        assert float(relief_shape(u, curve)[0]) == pytest.approx(value, rel=1e-15)
    # sine decision: quarter wave, sin(pi/4) at mid-length (not sin(pi/2) = 1 as printed)
    assert float(relief_shape(u, "sine")[0]) == pytest.approx(math.sqrt(0.5), rel=1e-15)


def test_height_and_length_conversion_against_roll_angles(tail: GearPair) -> None:
    # independent form: L = r_b (tan a_a - tan a_y), cos a_y = r_b / (r_a - h)
    for gear, ra, rb in ((1, tail.ra1, tail.rb1), (2, tail.ra2, tail.rb2)):
        h = 2.4e-3
        a_a, a_y = math.acos(rb / ra), math.acos(rb / (ra - h))
        expected = rb * (math.tan(a_a) - math.tan(a_y))
        length = length_from_height(tail, gear, h)
        assert length == pytest.approx(expected, rel=1e-12)  # rounding only
        assert height_from_length(tail, gear, length) == pytest.approx(h, rel=1e-12)


def test_relief_position_on_line_of_action(tail: GearPair) -> None:
    mod = ProfileModification(pinion=TipRelief(20e-6, 3e-3), gear=TipRelief(10e-6, 2e-3))
    # pinion relief: full at E, zero 3 mm before; gear relief: full at A, zero 2 mm after
    s_a, s_e = tail.start_of_contact, tail.end_of_contact
    assert float(mod.separation(tail, s_e)) == pytest.approx(20e-6, rel=1e-12)
    assert float(mod.separation(tail, s_a)) == pytest.approx(10e-6, rel=1e-12)
    assert float(mod.separation(tail, s_e - 3e-3)) == pytest.approx(0.0, abs=1e-18)
    assert float(mod.separation(tail, s_a + 2e-3)) == pytest.approx(0.0, abs=1e-18)
    assert float(mod.separation(tail, s_e - 1.5e-3)) == pytest.approx(10e-6, rel=1e-12)


def test_recommended_amounts_worked_case(tail: GearPair) -> None:
    """Hand computation: F_t = 1474.4 N m / 69 mm = 21368.116 N, w_t = 427.3623 N/mm."""
    torque = 1474.4
    hb = recommended_relief(tail, torque, "handbook")
    assert hb.amount_pinion * 1e6 == pytest.approx(26.0945, abs=1e-4)  # 9 + 0.04 * 427.3623
    assert hb.amount_gear * 1e6 == pytest.approx(21.0945, abs=1e-4)  # 4 + 0.04 * 427.3623
    assert hb.height_pinion == pytest.approx(2.4e-3, rel=1e-12)  # 0.4 m_n
    du = recommended_relief(tail, torque, "dudley")
    assert du.amount_pinion * 1e6 == pytest.approx(17.5219, abs=1e-4)  # 4.1 * 21368.116 / 5e6 mm
    assert du.amount_gear * 1e6 == pytest.approx(27.7786, abs=1e-4)  # 6.5 * 21368.116 / 5e6 mm
    ni = recommended_relief(tail, torque, "niemann")
    assert ni.amount_pinion * 1e6 == pytest.approx(54.0, abs=1e-9)  # 0.009 * 6 mm
    assert ni.height_gear * 1e3 == pytest.approx(2.958, abs=1e-12)  # 0.493 * 6 mm
    s1 = recommended_relief(tail, torque, "wang2024")
    assert s1.amount_pinion == pytest.approx(hb.amount_pinion, rel=1e-15)
    # long relief: (eps - 1) p_bt; eps = 1.58495 and p_bt = pi 6 mm cos 22.5 deg = 17.4147 mm
    assert s1.length_pinion * 1e3 == pytest.approx(0.58495 * 17.4147, rel=1e-4)
    assert long_relief_length(tail) == s1.length_gear
    # handbook constants shift the amounts one for one
    hb2 = recommended_relief(tail, torque, "handbook", handbook_a=13.0, handbook_b=0.0)
    assert (hb2.amount_pinion - hb.amount_pinion) * 1e6 == pytest.approx(4.0, abs=1e-9)
    assert (hb.amount_gear - hb2.amount_gear) * 1e6 == pytest.approx(4.0, abs=1e-9)


def test_bad_inputs_are_refused(tail: GearPair) -> None:
    with pytest.raises(InputError, match="relief curve = 'cubic'"):
        TipRelief(10e-6, 1e-3, "cubic")
    with pytest.raises(InputError, match="relief amount"):
        TipRelief(-1e-6, 1e-3)
    with pytest.raises(InputError, match="relief rule = 'kiss'"):
        recommended_relief(tail, 100.0, "kiss")
    with pytest.raises(InputError, match="handbook_a"):
        recommended_relief(tail, 100.0, "handbook", handbook_a=20.0)
    with pytest.raises(InputError, match="relief height"):
        length_from_height(tail, 1, 0.05)
    with pytest.raises(InputError, match="relief length"):
        ProfileModification(pinion=TipRelief(10e-6, 0.2)).check(tail)
