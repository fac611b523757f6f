"""Potential-energy (PEM) stiffness of a spur tooth pair (Wang et al. 2024, eqs. 5-6).

The tooth (:mod:`gear_dyn.stiffness.tooth`) is a cantilever of variable section clamped at the
root chord, loaded at the contact point by the normal force along the line of action; bending,
shear, axial (Yang & Lin 1987, Tian 2004, Chaari et al. 2009), fillet-foundation (Sainsot et al.
2004) and Hertz (Yang & Sun 1985) compliances add:

    1/K = 1/k_h + sum over both gears (1/k_b + 1/k_s + 1/k_a + 1/k_f)

(the terms are written out in docs/stiffness.md). Every term scales with 1/B. The integrals are
cumulative tables (cached per tooth), so a curve costs a few interpolations per contact position.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from gear_dyn.errors import InputError
from gear_dyn.geometry import GearPair
from gear_dyn.stiffness.periodic import FloatArray
from gear_dyn.stiffness.tooth import (
    DEFAULT_OPTIONS,
    ToothOptions,
    beam_integrals,
    half_angle,
    tooth_table,
)

# Sainsot, Velex & Duverger (2004), J. Mech. Design 126, table 1: columns A..F for L*, M*, P*, Q*.
SAINSOT = np.array([
    [-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045],    # L*
    [60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086],    # M*
    [-50.952e-5, 185.50e-3, 0.0538e-4, 53.300e-3, 0.2895, 0.9236],     # P*
    [-6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904],   # Q*
])

SHEAR_FACTOR = 1.2  # energy shear factor of a rectangular section


@dataclass(frozen=True, eq=False)
class PairCompliance:
    """Compliances (m/N) of one tooth pair at the contact positions, split by term.

    Attributes
    ----------
    hertz : ndarray
        Hertzian contact compliance of the pair.
    bending, shear, axial, fillet : ndarray, shape (2, N)
        Tooth compliances of pinion (row 0) and gear (row 1).
    """

    hertz: FloatArray
    bending: FloatArray
    shear: FloatArray
    axial: FloatArray
    fillet: FloatArray

    @property
    def total(self) -> FloatArray:
        """Total compliance 1/K of the pair in m/N."""
        return self.hertz + np.sum(self.bending + self.shear + self.axial + self.fillet, axis=0)

    @property
    def stiffness(self) -> FloatArray:
        """Single-pair stiffness K in N/m."""
        return 1.0 / self.total


def sainsot_coefficients(h_fi: float, theta_f: float) -> FloatArray:
    """Sainsot (2004) ``(L*, M*, P*, Q*)`` at ``h_fi = r_f/r_int`` and ``theta_f`` (rad)."""
    basis = np.array([1 / theta_f**2, h_fi**2, h_fi / theta_f, 1 / theta_f, h_fi, 1.0])
    return SAINSOT @ basis


def beam_compliances(eta: FloatArray, half: FloatArray, eta_load: ArrayLike, x_load: ArrayLike,
                     load_angle: ArrayLike, youngs_modulus: float, shear_modulus: float,
                     face_width: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Bending, shear and axial compliances (m/N) of a variable-section cantilever.

    Parameters
    ----------
    eta : ndarray
        Increasing grid of centre-line coordinates from the clamp (eta[0] = 0), in m.
    half : ndarray
        Half thickness at ``eta`` in m (> 0).
    eta_load, x_load : array_like
        Load point: centre-line coordinate and half thickness (lever of the axial component), m.
    load_angle : array_like
        Angle a1 (rad) between the force and the normal to the centre line.
    youngs_modulus, shear_modulus : float
        E and G in Pa.
    face_width : float
        Face width B in m.

    Returns
    -------
    (bending, shear, axial) : tuple of ndarray
        Compliances in m/N, broadcast over the load arrays.
    """
    eta = np.asarray(eta, dtype=float)
    j0, j1, j2, k0 = beam_integrals(eta, np.asarray(half, dtype=float))
    return _compliances_from_tables(eta, j0, j1, j2, k0, np.asarray(eta_load, dtype=float),
                                    np.asarray(x_load, dtype=float),
                                    np.asarray(load_angle, dtype=float), youngs_modulus,
                                    shear_modulus, face_width)


def _compliances_from_tables(eta: FloatArray, j0: FloatArray, j1: FloatArray, j2: FloatArray,
                             k0: FloatArray, eta_p: FloatArray, x_p: FloatArray,
                             a1: FloatArray, e: float, g: float,
                             b: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    c, s = np.cos(a1), np.sin(a1)
    big_a = eta_p * c - x_p * s  # moment arm constant: M = F (A - c eta)
    i0 = np.interp(eta_p, eta, j0)
    i1 = np.interp(eta_p, eta, j1)
    i2 = np.interp(eta_p, eta, j2)
    ik = np.interp(eta_p, eta, k0)
    # 1/(E I) = 3 / (2 E B x^3)
    bending = 1.5 / (e * b) * np.maximum(big_a**2 * i0 - 2 * big_a * c * i1 + c**2 * i2, 0.0)
    shear = SHEAR_FACTOR * c**2 / (2 * g * b) * ik
    axial = s**2 / (2 * e * b) * ik
    return bending, shear, axial


def contact_radii(pair: GearPair, s: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Contact radii (m) of pinion and gear at ``s`` (m from T1 along the line of action)."""
    r1 = np.sqrt(pair.rb1**2 + s**2)
    r2 = np.sqrt(pair.rb2**2 + (pair.line_of_action_length - s) ** 2)
    return r1, r2


def _check_positions(pair: GearPair, s: ArrayLike) -> FloatArray:
    arr = np.asarray(s, dtype=float)
    lo, hi = pair.start_of_contact, pair.end_of_contact
    tol = 1e-9 * pair.base_pitch
    if arr.size and (np.nanmin(arr) < lo - tol or np.nanmax(arr) > hi + tol
                     or not np.all(np.isfinite(arr))):
        raise InputError(
            f"contact position s outside the path of contact: valid range {lo * 1e3:.6g} .. "
            f"{hi * 1e3:.6g} mm from T1"
        )
    return np.clip(arr, lo, hi)


def tooth_load_geometry(pair: GearPair, gear: int,
                        radius: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Contact point ``(y_P, x_P)`` in the tooth frame (m) and load angle a1 (rad) at ``radius``."""
    rb = pair.rb1 if gear == 1 else pair.rb2
    psi = half_angle(pair, gear, radius)
    a_c = np.arccos(np.clip(rb / radius, -1.0, 1.0))
    return radius * np.cos(psi), radius * np.sin(psi), a_c - psi


def potential_energy_compliances(pair: GearPair, s: ArrayLike,
                                 options: ToothOptions = DEFAULT_OPTIONS) -> PairCompliance:
    """Term-by-term compliances of one tooth pair in contact at ``s``.

    Parameters
    ----------
    pair : GearPair
        The pair (spur; for helical pairs the transverse section is used per unit face width).
    s : array_like
        Contact positions in m from T1 along the line of action, within
        ``[pair.start_of_contact, pair.end_of_contact]``.
    options : ToothOptions
        Fillet radius, bore radii, plane strain, grid size.

    Returns
    -------
    PairCompliance
        Hertz, bending, shear, axial and fillet-foundation compliances in m/N.

    Raises
    ------
    InputError
        Positions outside the path of contact; undercut tooth; bad options.
    """
    sv = _check_positions(pair, s)
    radii = contact_radii(pair, sv)
    b = pair.face_width
    per_gear = []  # (bending, shear, axial, fillet) of each gear
    for gear, rc in ((1, radii[0]), (2, radii[1])):
        e = pair.youngs_modulus1 if gear == 1 else pair.youngs_modulus2
        nu = pair.poisson1 if gear == 1 else pair.poisson2
        g = e / (2 * (1 + nu))
        if options.plane_strain:
            e, g = e / (1 - nu**2), g  # G is unchanged in plane strain
        t = tooth_table(pair, gear, options)
        y_p, x_p, a1 = tooth_load_geometry(pair, gear, rc)
        per_gear.append((*_compliances_from_tables(
            t.eta, t.j0, t.j1, t.j2, t.k0, y_p - t.y_root, x_p, a1, e, g, b
        ), fillet_compliance(pair, gear, rc, options)))
    bending, shear, axial, fillet = (np.array(c) for c in zip(*per_gear, strict=True))
    return PairCompliance(hertz=np.full_like(sv, hertz_compliance(pair)), bending=bending,
                          shear=shear, axial=axial, fillet=fillet)


def fillet_compliance(pair: GearPair, gear: int, radius: ArrayLike,
                      options: ToothOptions = DEFAULT_OPTIONS) -> FloatArray:
    """Fillet-foundation compliance (m/N) of Sainsot et al. (2004) for a load at ``radius`` (m).

    ``cos^2 a1 / (E B) [L* (u_f/S_f)^2 + M* (u_f/S_f) + P* (1 + Q* tan^2 a1)]`` with ``u_f`` the
    radial distance from the root circle to where the force line crosses the centre line and
    ``S_f = 2 r_f theta_f`` the root arc thickness.
    """
    rc = np.asarray(radius, dtype=float)
    e = pair.youngs_modulus1 if gear == 1 else pair.youngs_modulus2
    t = tooth_table(pair, gear, options)
    y_p, x_p, a1 = tooth_load_geometry(pair, gear, rc)
    lm, mm, pm, qm = sainsot_coefficients(t.r_f / t.r_int, t.theta_f)
    u_f = y_p - x_p * np.tan(a1) - t.r_f
    ratio = u_f / (2 * t.r_f * t.theta_f)
    return np.asarray(np.cos(a1) ** 2 / (e * pair.face_width) * (
        lm * ratio**2 + mm * ratio + pm * (1 + qm * np.tan(a1) ** 2)
    ))


def hertz_compliance(pair: GearPair) -> float:
    """Hertzian compliance ``2 / (pi B E*)`` in m/N (= 4 (1 - nu^2) / (pi E B) for like steels)."""
    return 2.0 / (math.pi * pair.face_width * pair.effective_youngs_modulus)


def potential_energy_pair_stiffness(pair: GearPair, s: ArrayLike,
                                    options: ToothOptions = DEFAULT_OPTIONS) -> FloatArray:
    """Single-pair stiffness K(s) in N/m by the potential-energy method.

    Parameters
    ----------
    pair : GearPair
    s : array_like
        Contact positions in m from T1 along the line of action (start..end of contact).
    options : ToothOptions

    Returns
    -------
    ndarray
        Stiffness in N/m, same shape as ``s``.

    Raises
    ------
    InputError
        Positions outside the path of contact; undercut tooth; bad options.

    Examples
    --------
    >>> import math
    >>> from gear_dyn.geometry import GearPair
    >>> pair = GearPair(19, 48, 3.2e-3, math.radians(20), 16e-3, youngs_modulus1=206.8e9,
    ...                 youngs_modulus2=206.8e9)
    >>> k = potential_energy_pair_stiffness(pair, pair.pitch_point)
    >>> 1e8 < float(k) < 4e8
    True
    """
    return potential_energy_compliances(pair, s, options).stiffness
