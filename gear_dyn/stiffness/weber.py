"""Weber sliced-cantilever tooth stiffness with Hertz contact (Jiang et al. 2018, eqs. 9-12).

``k = F / (d_a1 + d_a2 + d_h)`` (eq. 9): the bending deflections of both teeth, each a cantilever
cut into n slices between the root chord and the contact point (eqs. 10-11), plus the Hertzian
approach ``d_h = 4 (1 - nu^2) F / (pi E B)`` (eq. 12). The paper's printed typos (bending bracket,
polar moment, missing shear factor) are read as intended: docs/stiffness.md lists them. Without
a fillet-foundation term the method as printed is about 2.5 times stiffer than ISO 6336
c_gamma b; ``foundation=True`` adds the Sainsot et al. (2004) term.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from gear_dyn.errors import InputError, current_name
from gear_dyn.geometry import GearPair
from gear_dyn.stiffness.periodic import FloatArray
from gear_dyn.stiffness.potential_energy import (
    _check_positions,
    contact_radii,
    fillet_compliance,
    tooth_load_geometry,
)
from gear_dyn.stiffness.tooth import DEFAULT_OPTIONS, ToothOptions, tooth_table

SHEAR_COEF = 5.0 / 6.0  # s_h for a rectangular section


def weber_modulus(youngs_modulus: float, poisson: float) -> float:
    """The modulus of Jiang et al. (2018), eq. 11: ``E (1 - nu) / ((1 + nu)(1 - 2 nu))`` in Pa."""
    return youngs_modulus * (1 - poisson) / ((1 + poisson) * (1 - 2 * poisson))


#: moduli in the tooth terms: ``jiang2018`` (eq. 11 of Jiang et al. 2018, :func:`weber_modulus`),
#: ``plane_stress`` (E), ``plane_strain`` (E / (1 - nu^2))
MODULI = ("jiang2018", "plane_stress", "plane_strain")
#: old modulus names -> their names now: still accepted, with a FutureWarning
RENAMED_MODULI = {"seed": "jiang2018"}


def current_modulus(modulus: str, where: str = "weber modulus") -> str:
    """``modulus``, or the name an old modulus name (:data:`RENAMED_MODULI`) now has, with a
    :class:`FutureWarning` that names ``where`` (e.g. a scene's key path)."""
    return current_name(modulus, RENAMED_MODULI, where, "modulus", "Jiang et al. 2018, eq. 11")


def weber_tooth_compliance(pair: GearPair, gear: int, radius: ArrayLike, slices: int = 20,
                           options: ToothOptions = DEFAULT_OPTIONS,
                           modulus: str = "jiang2018", foundation: bool = False) -> FloatArray:
    """Weber bending + shear + axial compliance d_a / F (m/N) of one tooth loaded at ``radius``.

    Parameters
    ----------
    pair : GearPair
    gear : int
        1 pinion, 2 gear.
    radius : array_like
        Contact radius in m on that gear.
    slices : int
        Number of slices between the root chord and the contact point (>= 1).
    options : ToothOptions
        Tooth geometry options (fillet radius, grid).
    modulus : str
        Modulus in the tooth terms: "jiang2018" (Jiang et al. 2018, eq. 11,
        ``E (1-nu)/((1+nu)(1-2nu))``, default), "plane_stress" (E) or "plane_strain"
        (``E / (1 - nu^2)``). The old name "seed" of "jiang2018" works, with a FutureWarning.
    foundation : bool
        Add the Sainsot et al. (2004) fillet-foundation compliance (default False: Jiang et al.
        2018 give the method without it).

    Returns
    -------
    ndarray
        Compliance in m/N.

    Raises
    ------
    InputError
        Fewer than one slice, unknown modulus.
    """
    if not isinstance(slices, int) or slices < 1:
        raise InputError(f"slices = {slices!r}: valid range >= 1 (integer)")
    modulus = current_modulus(modulus)
    if modulus not in MODULI:
        raise InputError(f"modulus = {modulus!r}: valid values are {', '.join(MODULI)}")
    e = pair.youngs_modulus1 if gear == 1 else pair.youngs_modulus2
    nu = pair.poisson1 if gear == 1 else pair.poisson2
    e_w = {"jiang2018": weber_modulus(e, nu), "plane_stress": e,
           "plane_strain": e / (1 - nu**2)}[modulus]
    g = e / (2 * (1 + nu))
    b = pair.face_width
    t = tooth_table(pair, gear, options)
    rc = np.asarray(radius, dtype=float)
    y_p, x_p, a_m = tooth_load_geometry(pair, gear, rc)
    eta_p = y_p - t.y_root
    eta_load = eta_p - x_p * np.tan(a_m)
    u = np.linspace(0.0, 1.0, slices + 1)
    ends = eta_p[..., None] * u  # slice ends from the root chord to the contact point
    thick = 2 * np.interp(ends, t.eta, t.half)
    j_end = b * thick**3 / 12
    a_end = b * thick
    j_bar = 2 / (1 / j_end[..., :-1] + 1 / j_end[..., 1:])
    a_bar = 2 / (1 / a_end[..., :-1] + 1 / a_end[..., 1:])
    x_i = np.diff(ends, axis=-1)
    d_i = eta_load[..., None] - ends[..., 1:]
    term = x_i * ((d_i**2 + x_i * d_i + x_i**2 / 3) / (e_w * j_bar)
                  + 1 / (SHEAR_COEF * g * a_bar) + np.tan(a_m)[..., None] ** 2 / (a_bar * e_w))
    out = np.cos(a_m) ** 2 * np.sum(term, axis=-1)
    if foundation:
        out = out + fillet_compliance(pair, gear, rc, options)
    return np.asarray(out)


def weber_hertz_compliance(pair: GearPair) -> float:
    """Hertz compliance ``4 (1 - nu^2) / (pi E B)`` in m/N (pinion E, nu; Jiang et al. 2018,
    eq. 12)."""
    return 4 * (1 - pair.poisson1**2) / (math.pi * pair.youngs_modulus1 * pair.face_width)


def weber_compliances(pair: GearPair, s: ArrayLike, slices: int = 20,
                      options: ToothOptions = DEFAULT_OPTIONS, modulus: str = "jiang2018",
                      foundation: bool = False) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``(d_a1/F, d_a2/F, d_h/F)`` in m/N at contact positions ``s`` (m from T1)."""
    sv = _check_positions(pair, s)
    r1, r2 = contact_radii(pair, sv)
    c1 = weber_tooth_compliance(pair, 1, r1, slices, options, modulus, foundation)
    c2 = weber_tooth_compliance(pair, 2, r2, slices, options, modulus, foundation)
    return c1, c2, np.full_like(sv, weber_hertz_compliance(pair))


def weber_pair_stiffness(pair: GearPair, s: ArrayLike, slices: int = 20,
                         options: ToothOptions = DEFAULT_OPTIONS,
                         modulus: str = "jiang2018", foundation: bool = False) -> FloatArray:
    """Single-pair stiffness ``F / (d_a1 + d_a2 + d_h)`` in N/m (Jiang et al. 2018, eq. 9).

    Parameters
    ----------
    pair : GearPair
    s : array_like
        Contact positions in m from T1 (start..end of contact).
    slices : int
        Slices per tooth (>= 1).
    options : ToothOptions
    modulus : str
        "jiang2018" (eq. 11, default), "plane_stress" or "plane_strain" (see
        :func:`.weber_tooth_compliance`).
    foundation : bool
        Add the Sainsot fillet-foundation compliance (default False, as Jiang et al. 2018).

    Returns
    -------
    ndarray
        Stiffness in N/m, same shape as ``s``.

    Raises
    ------
    InputError
        Positions outside the path of contact, bad slice count or modulus.
    """
    c1, c2, ch = weber_compliances(pair, s, slices, options, modulus, foundation)
    return 1.0 / (c1 + c2 + ch)
