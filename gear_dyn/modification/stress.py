"""Hertz line-contact stress along the path of contact (Wang et al. 2024, eqs. 27-31).

    1/R = 1/rho1 + 1/rho2,   1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2,
    b = sqrt(4 F R / (pi B E*)),   sigma_H = sqrt(F E* / (pi B R))

with ``rho1 = s``, ``rho2 = T1T2 - s`` on the involutes. On relieved flanks the exact
offset-curve curvature is used, with the relief's second derivative averaged over the contact
width (decision; formula and reasoning in docs/modification.md, "Contact stress").
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gear_dyn.errors import InputError, check_range
from gear_dyn.geometry import GearPair
from gear_dyn.modification.relief import ProfileModification

FloatArray = NDArray[np.float64]


def effective_modulus(e1: float, nu1: float, e2: float, nu2: float) -> float:
    """Contact modulus ``E* = 1 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2)`` in Pa.

    Parameters
    ----------
    e1, e2 : float
        Young's moduli in Pa (> 0).
    nu1, nu2 : float
        Poisson's ratios (0 <= nu < 0.5).

    Raises
    ------
    InputError
        Values out of range.
    """
    check_range("youngs_modulus1", e1, "Pa", low=0.0, low_open=True)
    check_range("youngs_modulus2", e2, "Pa", low=0.0, low_open=True)
    check_range("poisson1", nu1, "", low=0.0, high=0.5, high_open=True)
    check_range("poisson2", nu2, "", low=0.0, high=0.5, high_open=True)
    return 1.0 / ((1 - nu1**2) / e1 + (1 - nu2**2) / e2)


def hertz_line_contact(force: ArrayLike, width: float, curvature_sum: ArrayLike,
                       e_star: float) -> tuple[FloatArray, FloatArray]:
    """Peak pressure and half-width of a Hertz line contact.

    Parameters
    ----------
    force : array_like
        Contact force in N (>= 0).
    width : float
        Contact length B in m (> 0).
    curvature_sum : array_like
        ``1/R = 1/rho1 + 1/rho2`` in 1/m (> 0).
    e_star : float
        Contact modulus E* in Pa (> 0), see :func:`effective_modulus`.

    Returns
    -------
    sigma_h, half_width : ndarray
        Peak contact pressure in Pa and half-width b in m.

    Raises
    ------
    InputError
        Negative force or non-positive curvature sum (a conformal contact).

    Examples
    --------
    >>> s, b = hertz_line_contact(1000.0, 0.01, 1 / 0.01 + 1 / 0.02, 1.1e11)
    >>> round(float(s) / 1e6, 1), round(float(b) * 1e6, 2)
    (724.7, 87.84)
    """
    f = np.asarray(force, dtype=float)
    c = np.asarray(curvature_sum, dtype=float)
    check_range("width", width, "m", low=0.0, low_open=True)
    check_range("e_star", e_star, "Pa", low=0.0, low_open=True)
    if np.any(f < 0) or not np.all(np.isfinite(f)):
        raise InputError("contact force: valid range >= 0 N (finite)")
    if np.any(c <= 0) or not np.all(np.isfinite(c)):
        raise InputError("curvature sum 1/rho1 + 1/rho2: valid range > 0 1/m (non-conformal)")
    sigma = np.sqrt(f * e_star * c / (np.pi * width))
    half = np.sqrt(4.0 * f / (c * np.pi * width * e_star))
    return sigma, half


def profile_curvature(pair: GearPair, gear: int, rho: ArrayLike,
                      modification: ProfileModification | None = None,
                      half_width: ArrayLike = 0.0) -> FloatArray:
    """Curvature (1/m) of gear ``gear``'s flank at roll distance ``rho``, relief included.

    Parameters
    ----------
    pair : GearPair
    gear : int
        1 (pinion) or 2 (gear).
    rho : array_like
        Roll distance from the gear's base-circle tangent point in m (> 0).
    modification : ProfileModification or None
        Reliefs; None gives the involute curvature ``1 / rho``.
    half_width : array_like
        Hertz half-width in m over which the relief's second derivative is averaged (0: the
        pointwise value from the slope's finite difference over a 1 um window).

    Returns
    -------
    ndarray
        Curvature in 1/m.
    """
    r = np.asarray(rho, dtype=float)
    if np.any(r <= 0):
        raise InputError("roll distance rho: valid range > 0 m (contact above the base circle)")
    kappa = 1.0 / r
    if modification is None or modification.is_zero:
        return kappa
    rb = pair.rb1 if gear == 1 else pair.rb2
    b = np.maximum(np.asarray(half_width, dtype=float), 0.5e-6)
    sigma = r**2 / (2 * rb)
    reach = pair.tip_reach1 if gear == 1 else pair.tip_reach2

    def slope_sigma(sig: FloatArray) -> FloatArray:
        rr = np.minimum(np.sqrt(2 * rb * np.maximum(sig, 0.0)), reach)  # rounding at the tip
        _, dd = modification.roll_depth(pair, gear, rr)
        return np.where(rr > 0, dd * rb / np.maximum(rr, 1e-300), 0.0)

    # the window ends at the tip and at the base circle: the flank ends there
    sig_hi = np.minimum(sigma + b, reach**2 / (2 * rb))
    sig_lo = np.maximum(sigma - b, 0.0)
    w2 = (slope_sigma(sig_hi) - slope_sigma(sig_lo)) / np.maximum(sig_hi - sig_lo, 1e-300)
    w, w_rho = modification.roll_depth(pair, gear, r)
    w1 = w_rho * rb / r
    kappa_s = -rb / r**3
    q = 1.0 - kappa * w
    num = q * (q * kappa + w2) + w1 * (kappa_s * w + 2 * kappa * w1)
    return num / (q**2 + w1**2) ** 1.5


def contact_stress(pair: GearPair, position: ArrayLike, force: ArrayLike,
                   modification: ProfileModification | None = None) -> tuple[FloatArray,
                                                                             FloatArray]:
    """Hertz contact stress and half-width of a tooth pair along the path of contact.

    Parameters
    ----------
    pair : GearPair
        Uses face width, both E and nu.
    position : array_like
        Contact position s in m from T1 (``rho1 = s``, ``rho2 = T1T2 - s``).
    force : array_like
        Load of this tooth pair in N (>= 0), e.g. ``sharing * F``.
    modification : ProfileModification or None
        Reliefs: their curvature change is included (averaged over the contact width).

    Returns
    -------
    sigma_h, half_width : ndarray
        Peak contact pressure in Pa and half-width in m.

    Raises
    ------
    InputError
        Contact at or below a base circle, negative force, conformal contact.
    """
    s = np.asarray(position, dtype=float)
    f = np.asarray(force, dtype=float)
    e_star = pair.effective_youngs_modulus
    rho1, rho2 = s, pair.line_of_action_length - s
    c0 = profile_curvature(pair, 1, rho1) + profile_curvature(pair, 2, rho2)
    sigma, half = hertz_line_contact(f, pair.face_width, c0, e_star)
    if modification is None or modification.is_zero:
        return sigma, half
    c = (profile_curvature(pair, 1, rho1, modification, half)
         + profile_curvature(pair, 2, rho2, modification, half))
    return hertz_line_contact(f, pair.face_width, c, e_star)
