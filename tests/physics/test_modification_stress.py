"""Hertz contact stress along the path of contact (Wang et al. 2024, eqs. 27-31)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gear_dyn.errors import InputError
from gear_dyn.geometry import GearPair
from gear_dyn.modification import (
    ProfileModification,
    TipRelief,
    contact_stress,
    effective_modulus,
    hertz_line_contact,
    loaded_contact,
    profile_curvature,
)

PAIR = GearPair(23, 64, 6e-3, math.radians(22.5), 50e-3, youngs_modulus1=207e9,
                youngs_modulus2=110e9, poisson1=0.3, poisson2=0.34)


def test_pitch_point_stress_matches_iso_closed_form() -> None:
    """ISO 6336-2 nominal pitch-point stress for one pair carrying the whole load:
    sigma = Z_E Z_H sqrt(F_t (u + 1) / (d1 B u)), Z_H = sqrt(2 / (cos^2 a_t tan a_t)) for a spur
    pair at standard centre distance, Z_E = sqrt(1 / (pi ((1 - nu1^2)/E1 + (1 - nu2^2)/E2)))."""
    torque = 1474.4
    f_t = torque / PAIR.r1
    u = PAIR.z2 / PAIR.z1
    a = PAIR.alpha_t
    z_h = math.sqrt(2 / (math.cos(a) ** 2 * math.tan(a)))
    z_e = math.sqrt(1 / (math.pi * ((1 - 0.3**2) / 207e9 + (1 - 0.34**2) / 110e9)))
    iso = z_e * z_h * math.sqrt(f_t * (u + 1) / (2 * PAIR.r1 * PAIR.face_width * u))
    f_n = torque / PAIR.rb1
    sigma, half = contact_stress(PAIR, PAIR.pitch_point, f_n)
    assert float(sigma) == pytest.approx(iso, rel=1e-12)  # same closed form, rounding only
    # two cylinders with the involute radii at the pitch point, Johnson's half-width
    rho1, rho2 = PAIR.r1 * math.sin(a), PAIR.r2 * math.sin(a)
    e_star = 1 / ((1 - 0.3**2) / 207e9 + (1 - 0.34**2) / 110e9)
    r_eff = rho1 * rho2 / (rho1 + rho2)
    b = math.sqrt(4 * f_n * r_eff / (math.pi * PAIR.face_width * e_star))
    assert float(half) == pytest.approx(b, rel=1e-12)
    # peak pressure and mean pressure: p0 = 2 F / (pi b B) (elliptical distribution)
    assert float(sigma) == pytest.approx(2 * f_n / (math.pi * b * PAIR.face_width), rel=1e-12)


def test_effective_modulus_uses_both_materials() -> None:
    e = effective_modulus(207e9, 0.3, 207e9, 0.3)
    assert e == pytest.approx(207e9 / (2 * (1 - 0.09)), rel=1e-15)


def _modified_involute_curvature(rb: float, relief: ProfileModification, pair: GearPair,
                                 rho: float) -> float:
    """Curvature of the relieved pinion flank by finite differences of the drawn curve."""
    def point(r: float) -> np.ndarray:
        th = r / rb  # roll angle
        p = rb * np.array([math.cos(th) + th * math.sin(th), math.sin(th) - th * math.cos(th)])
        n = np.array([-math.sin(th), math.cos(th)])  # towards the tangent point (the material)
        d, _ = relief.roll_depth(pair, 1, np.array([r]))
        return p + float(d[0]) * n

    h = 2e-5
    p0, pp, pm = point(rho), point(rho + h), point(rho - h)
    d1 = (pp - pm) / (2 * h)
    d2 = (pp - 2 * p0 + pm) / h**2
    return abs(d1[0] * d2[1] - d1[1] * d2[0]) / float(np.hypot(*d1)) ** 3


def test_relieved_flank_curvature_against_drawn_curve() -> None:
    length = 5e-3
    mod = ProfileModification(pinion=TipRelief(50e-6, length, "parabolic"))
    start = PAIR.tip_reach1 - length
    for rho in (start + 1e-3, start + 2.5e-3, start + 4e-3):
        drawn = _modified_involute_curvature(PAIR.rb1, mod, PAIR, rho)
        model = float(profile_curvature(PAIR, 1, rho, mod, half_width=1e-7))
        # exact offset-curve formula; the second derivative is averaged over +-0.5 um (error
        # ~ 1e-13 relative for a parabola); finite differences with h = 20 um: ~ 1e-7 relative
        assert model == pytest.approx(drawn, rel=1e-6)
        assert model > 1 / rho  # relieving the tip makes it more convex


def test_stress_along_path_with_and_without_relief() -> None:
    torque = 1474.4
    lc = loaded_contact(PAIR, lambda s: np.full(np.shape(s), 5e8), torque)
    view = lc.along_path()
    sigma, half = contact_stress(PAIR, view.position, view.force)
    # sigma^2 proportional to the pair load at fixed geometry: halves the load, sigma / sqrt 2
    s2, _ = contact_stress(PAIR, view.position, 0.5 * view.force)
    np.testing.assert_allclose(s2, sigma / math.sqrt(2), rtol=1e-12)
    assert np.all(np.isfinite(sigma)) and np.all(half >= 0)
    mod = ProfileModification(TipRelief(30e-6, 4e-3, "linear"), TipRelief(30e-6, 4e-3, "linear"))
    lm = loaded_contact(PAIR, lambda s: np.full(np.shape(s), 5e8), torque, mod)
    vm = lm.along_path()
    sm, _ = contact_stress(PAIR, vm.position, vm.force, mod)
    # the relief unloads the entry point A, where the unmodified stress is highest with this K
    assert sm[0] < sigma[0]


def test_bad_contact_inputs() -> None:
    with pytest.raises(InputError, match="contact force"):
        hertz_line_contact(-1.0, 0.01, 100.0, 1e11)
    with pytest.raises(InputError, match="non-conformal"):
        hertz_line_contact(1.0, 0.01, -5.0, 1e11)
    with pytest.raises(InputError, match="roll distance"):
        profile_curvature(PAIR, 1, 0.0)
