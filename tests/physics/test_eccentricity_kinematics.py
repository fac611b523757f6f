"""Eccentric kinematics (Liu et al. 2017, eqs. 1-13) against closed forms and a second
derivation."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gear_dyn.eccentricity import Eccentricity, EccentricMesh
from gear_dyn.errors import InputError
from gear_dyn.geometry import GearPair

W1 = 1500 * 2 * math.pi / 60  # the input speed of Liu et al. (2017): 1500 rpm


def eccentric_pair(beta_deg: float = 15.0) -> GearPair:
    return GearPair(18, 70, 3e-3, math.radians(20), 0.04, math.radians(beta_deg))


def test_error_free_pair_reduces_to_involute_kinematics() -> None:
    pair = eccentric_pair()
    mesh = EccentricMesh(pair, Eccentricity(), W1)
    t = np.linspace(0.0, 0.2, 1001)
    k = mesh.kinematics(t)
    # "exactly" z2/z1: the only error is floating-point rounding of r_w1, r_w2 (a few ulp)
    np.testing.assert_allclose(k.ratio, 70 / 18, rtol=1e-13, atol=0)
    np.testing.assert_allclose(k.w2, W1 * 18 / 70, rtol=1e-13, atol=0)
    np.testing.assert_allclose(k.l, pair.a_w, rtol=1e-15)
    np.testing.assert_allclose(k.alpha, pair.alpha_wt, rtol=1e-13)
    np.testing.assert_allclose(k.xp, pair.rw1, rtol=1e-13)
    np.testing.assert_allclose(k.travel, pair.rb1 * W1 * t, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(k.l_ac, pair.start_of_contact, rtol=1e-13)
    np.testing.assert_allclose(k.l_cd, pair.path_of_contact, rtol=1e-12)
    np.testing.assert_allclose(k.l_cp, pair.pitch_point - pair.start_of_contact, rtol=1e-12)
    np.testing.assert_allclose(k.arm1, pair.rb1, rtol=1e-13)
    np.testing.assert_allclose(k.arm2, pair.rb2, rtol=1e-13)
    assert np.max(np.abs(k.e_ecc)) < 1e-15


def test_law_of_gearing_matches_the_displacement_relation() -> None:
    """w2 from eq. 12 (pitch point) vs d(theta2)/dt from unwinding the involutes: two derivations.

    theta2 is sampled finely and differentiated with central differences (error O(dt^2)
    ~ (w1 dt)^2 e/r ~ 1e-9 relative here); 1e-7 leaves a margin for the fixed-point tolerance.
    """
    mesh = EccentricMesh(eccentric_pair(), Eccentricity(2e-4, 2e-4, 0.4, 1.3), W1)
    t = np.linspace(0.0, 0.16, 80001)
    k = mesh.kinematics(t)
    dth2 = np.gradient(k.theta2, t)
    np.testing.assert_allclose(dth2[2:-2], k.w2[2:-2], rtol=1e-7)
    de = np.gradient(k.e_ecc, t)
    scale = np.max(np.abs(k.e_ecc_rate))
    assert np.max(np.abs(de[2:-2] - k.e_ecc_rate[2:-2])) < 1e-6 * scale


def test_tangent_points_and_pitch_point_geometry() -> None:
    """A, B lie on the base circles with radii normal to AB; eq. 11's literal form gives x_P."""
    pair = eccentric_pair()
    mesh = EccentricMesh(pair, Eccentricity(2e-4, 1e-4, 0.0, 2.0), W1)
    k = mesh.kinematics(np.linspace(0, 0.3, 301))
    np.testing.assert_allclose(np.hypot(k.xa - k.x1, k.ya - k.y1), pair.rb1, rtol=1e-13)
    np.testing.assert_allclose(np.hypot(k.xb - k.x2, k.yb - k.y2), pair.rb2, rtol=1e-13)
    ux, uy = k.xb - k.xa, k.yb - k.ya
    np.testing.assert_allclose(np.hypot(ux, uy), k.ab, rtol=1e-12)
    # radius O1'A is perpendicular to AB (tangency); relative to |AB| r_b1
    assert np.max(np.abs((k.xa - k.x1) * ux + (k.ya - k.y1) * uy)) < 1e-12 * pair.rb1 * k.ab.max()
    xp_eq11 = k.xb - k.yb * (k.xb - k.xa) / (k.yb - k.ya)  # seed eq. 11 as printed
    np.testing.assert_allclose(k.xp, xp_eq11, rtol=1e-12)
    # v = w1 * distance from O1 to the line of action (cross product, independent of eq. 13)
    dist = np.abs(k.xa * uy - k.ya * ux) / k.ab
    np.testing.assert_allclose(k.v, W1 * dist, rtol=1e-12)


def test_first_order_amplitude_of_the_line_of_action_error() -> None:
    """To first order an eccentricity e moves the flank along the line of action by e sin(...):
    the peak-to-peak of e_ecc is 2 e1 for a pinion-only eccentricity (second-order terms are
    O(e / r_b) ~ 1e-2 relative, hence the 2 % tolerance)."""
    e1 = 2e-4
    mesh = EccentricMesh(eccentric_pair(), Eccentricity(e1, 0.0), W1)
    t = np.linspace(0.0, 1 / 25, 4001)
    k = mesh.kinematics(t)
    assert np.ptp(k.e_ecc) == pytest.approx(2 * e1, rel=2e-2)


def test_scalar_path_equals_array_path() -> None:
    mesh = EccentricMesh(eccentric_pair(), Eccentricity(2e-4, 2e-4, 0.3, 1.0), W1)
    ts = np.random.default_rng(3).uniform(0, 1.4, 40)
    ka = mesh.kinematics(ts)
    for i, t in enumerate(ts):
        kf = mesh.kinematics(float(t))
        assert isinstance(kf.w2, float)
        # same formulas, math vs numpy; the gear-angle iteration stops at 1e-14 rad per rad of
        # pinion angle (th1 <= 220 rad here): th2 agrees to ~2e-12 rad, e_ecc to r_b2 times that
        assert kf.theta2 == pytest.approx(ka.theta2[i], abs=3e-12)
        assert kf.e_ecc == pytest.approx(ka.e_ecc[i], abs=3e-12 * mesh.pair.rb2)
        assert kf.w2 == pytest.approx(ka.w2[i], rel=1e-12)
        assert kf.travel == pytest.approx(ka.travel[i], rel=1e-12)


def test_mean_ratio_over_the_hunting_period_is_nominal() -> None:
    """Teeth cannot slip: over the hunting period theta2 advances exactly theta1 z1 / z2."""
    mesh = EccentricMesh(eccentric_pair(), Eccentricity(2e-4, 2e-4), W1)
    assert mesh.hunting_period == pytest.approx(1.4, rel=1e-14)
    k = mesh.kinematics(np.array([0.0, mesh.hunting_period]))
    assert k.theta2[1] == pytest.approx(k.theta1[1] * 18 / 70, rel=1e-12)


@pytest.mark.parametrize(
    ("ecc", "match"),
    [
        (Eccentricity(1e-3, 1e-3), "half the module"),
        (Eccentricity(8e-4, 7e-4), "contact ratio"),
    ],
)
def test_too_much_eccentricity_is_refused(ecc: Eccentricity, match: str) -> None:
    # spur with short addendum: eps_a = 1.21 at H, 0.80 at H + 1.5 mm
    pair = GearPair(18, 70, 3e-3, math.radians(25), 0.005, 0.0, addendum_coef=0.8)
    with pytest.raises(InputError, match=match):
        EccentricMesh(pair, ecc, W1)


def test_negative_eccentricity_is_refused() -> None:
    with pytest.raises(InputError, match="eccentricity.pinion"):
        Eccentricity(-1e-4, 0.0)
