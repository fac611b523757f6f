"""Tooth geometry for the beam-type stiffness methods: involute flank, trochoid root fillet.

The tooth is cut by the pair's basic rack (dedendum ``(ha* + c*) m_n``, tip rounding
``rho_fP = rho* m_n``, default ``rho* = c* / (1 - sin a_n)``, ISO 53 profile A for 20 deg).
Frame: the centre line is the y axis, x the half thickness, in the transverse plane. The flank
is the involute, ``psi(r) = s_t / (2 r) + inv a_t - inv a_r`` for ``r_form <= r <= r_a``; the
fillet is the envelope of the rack rounding (its normal passes through the instantaneous pitch
point). Beam methods clamp the tooth at the root chord ``y_root = r_f cos theta_f``. Helical
pairs use the transverse section (a thin-slice approximation; docs/stiffness.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from gear_dyn.errors import InputError, check_range
from gear_dyn.geometry import GearPair, involute
from gear_dyn.stiffness.periodic import FloatArray


@dataclass(frozen=True)
class ToothOptions:
    """Options of the tooth model used by the potential-energy and Weber methods.

    Parameters
    ----------
    fillet_radius_coef : float or None
        Basic-rack tip rounding radius ``rho_fP / m_n``; None gives the full rounding
        ``c* / (1 - sin a_n)``. Valid 0 .. that maximum.
    bore_radius1, bore_radius2 : float or None
        Bore (rim inner) radius of pinion and gear in m, used by the fillet-foundation term
        (``h_fi = r_f / r_int``). None: half the root radius.
    plane_strain : bool
        Use ``E / (1 - nu^2)`` in the tooth bending, shear and axial terms (wide faces). Default
        False: plane stress, the convention of Yang & Lin 1987, Tian 2004 and Sainsot et al. 2004.
    grid_points : int
        Points of the integration grid along the tooth centre line (>= 200).

    Raises
    ------
    InputError
        Values outside their ranges.
    """

    fillet_radius_coef: float | None = None
    bore_radius1: float | None = None
    bore_radius2: float | None = None
    plane_strain: bool = False
    grid_points: int = 3001

    def __post_init__(self) -> None:
        if self.fillet_radius_coef is not None:
            check_range("fillet_radius_coef", self.fillet_radius_coef, "", low=0.0, high=1.0)
        for name in ("bore_radius1", "bore_radius2"):
            v = getattr(self, name)
            if v is not None:
                check_range(name, v, "m", low=0.0, high=10.0, low_open=True)
        if not isinstance(self.grid_points, int) or self.grid_points < 200:
            raise InputError(f"grid_points = {self.grid_points!r}: valid range >= 200 (integer)")


DEFAULT_OPTIONS = ToothOptions()


@dataclass(frozen=True, eq=False)
class ToothTable:
    """Profile and cumulative section integrals of one tooth (SI units).

    Attributes
    ----------
    y_profile, x_profile : ndarray
        Profile points (centre-line coordinate, half thickness) from the root to the tip, in m.
    eta : ndarray
        Grid of ``y - y_root`` in m along the centre line, from 0 to the tip.
    half : ndarray
        Half thickness ``x(eta)`` in m on the grid.
    j0, j1, j2, k0 : ndarray
        Cumulative integrals from the root: ``int eta^n / x^3`` (n = 0, 1, 2) and ``int 1 / x``.
    y_root, r_f, r_form, theta_f, r_int : float
        Root chord coordinate, root radius, form (fillet/involute) radius, root half angle (rad),
        bore radius, all in m except theta_f.
    """

    y_profile: FloatArray
    x_profile: FloatArray
    eta: FloatArray
    half: FloatArray
    j0: FloatArray
    j1: FloatArray
    j2: FloatArray
    k0: FloatArray
    y_root: float
    r_f: float
    r_form: float
    theta_f: float
    r_int: float


def _gear_params(pair: GearPair, gear: int) -> tuple[float, float, float, float, float]:
    if gear not in (1, 2):
        raise InputError(f"gear = {gear!r}: valid values are 1 (pinion) and 2 (gear)")
    if gear == 1:
        return pair.r1, pair.rb1, pair.ra1, pair.rf1, pair.x1
    return pair.r2, pair.rb2, pair.ra2, pair.rf2, pair.x2


def half_angle(pair: GearPair, gear: int, radius: FloatArray) -> FloatArray:
    """Half angular tooth thickness ``psi(r)`` (rad) of the involute flank at ``radius`` (m)."""
    r, rb, _, _, x = _gear_params(pair, gear)
    s_t = pair.transverse_module * (math.pi / 2 + 2 * x * math.tan(pair.pressure_angle))
    ar = np.arccos(np.clip(rb / np.asarray(radius, dtype=float), -1.0, 1.0))
    return s_t / (2 * r) + involute(pair.alpha_t) - (np.tan(ar) - ar)


def rounding_radius(pair: GearPair, options: ToothOptions = DEFAULT_OPTIONS) -> float:
    """Basic-rack tip rounding radius rho_fP in m (see module docstring)."""
    rho_max = pair.clearance_coef / (1 - math.sin(pair.pressure_angle))
    coef = rho_max if options.fillet_radius_coef is None else options.fillet_radius_coef
    if coef > rho_max * (1 + 1e-9):
        raise InputError(
            f"fillet_radius_coef = {coef:.6g}: the rounding does not fit the tip clearance; "
            f"valid range 0 .. {rho_max:.4f} for c* = {pair.clearance_coef:g}"
        )
    return coef * pair.module


def fillet_points(pair: GearPair, gear: int, n: int = 400,
                  options: ToothOptions = DEFAULT_OPTIONS) -> tuple[FloatArray, FloatArray]:
    """Points (x, y) in m of the trochoidal root fillet from the root circle to the form radius."""
    r, rb, ra, rf, xc = _gear_params(pair, gear)
    a = pair.alpha_t
    mt, mn = pair.transverse_module, pair.module
    y_d = r + xc * mn
    rho = rounding_radius(pair, options)
    y_c = rf + rho
    w_c = math.pi * mt / 4 - (y_c - y_d) * math.tan(a)
    x_c = w_c + rho / math.cos(a)
    phi0 = x_c / r
    phi1 = (x_c + (r - y_c) / math.tan(a)) / r
    phi = np.linspace(phi0, phi1, n)
    cx = x_c - r * phi
    cy = np.full_like(phi, y_c)
    dx, dy = cx, cy - r
    norm = np.hypot(dx, dy)
    if rho > 0:
        px, py = cx + rho * dx / norm, cy + rho * dy / norm
    else:
        px, py = cx, cy
    c, s = np.cos(phi), np.sin(phi)
    return px * c + py * s, -px * s + py * c


def beam_integrals(eta: FloatArray, half: FloatArray
                   ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Running integrals of a tooth beam from its clamp, by the trapezoid rule (0 at ``eta[0]``).

    Parameters
    ----------
    eta : ndarray
        Increasing centre-line coordinates from the clamp, in m.
    half : ndarray
        Half thickness ``h`` at ``eta``, in m (> 0).

    Returns
    -------
    (j0, j1, j2, k0) : tuple of ndarray
        The integrals of ``1/h^3`` (1/m^2), ``eta/h^3`` (1/m), ``eta^2/h^3`` (1) and ``1/h``
        (1) from ``eta[0]`` to each ``eta``: what the bending, shear and axial compliances are
        made of (:func:`gear_dyn.stiffness.potential_energy.beam_compliances`).
    """
    from scipy.integrate import cumulative_trapezoid  # on use: the ISO scenes never need it

    inv3 = 1.0 / half**3
    j0, j1, j2, k0 = (cumulative_trapezoid(f, eta, initial=0.0)
                      for f in (inv3, eta * inv3, eta**2 * inv3, 1.0 / half))
    return j0, j1, j2, k0


@lru_cache(maxsize=64)
def tooth_table(pair: GearPair, gear: int,
                options: ToothOptions = DEFAULT_OPTIONS) -> ToothTable:
    """Profile and cumulative section integrals of the pinion (1) or gear (2) tooth (cached).

    Raises
    ------
    InputError
        Undercut fillet (the profile does not rise monotonically) or bad options.
    """
    r, rb, ra, rf, xc = _gear_params(pair, gear)
    fx, fy = fillet_points(pair, gear, 600, options)
    r_form = float(math.hypot(fx[-1], fy[-1]))
    if r_form < rb * (1 - 1e-9):
        r_form = rb
    rr = np.linspace(max(r_form, rb), ra, 1200)
    psi = half_angle(pair, gear, rr)
    ix, iy = rr * np.sin(psi), rr * np.cos(psi)
    y = np.concatenate([fy, iy[1:]])
    x = np.concatenate([fx, ix[1:]])
    if np.any(np.diff(y) <= 0):
        raise InputError(
            f"z{gear} = {pair.z1 if gear == 1 else pair.z2}: the root fillet is undercut "
            "(profile not monotonic along the tooth); use a positive profile shift"
        )
    y_root = float(y[0])
    theta_f = float(math.atan2(x[0], y[0]))
    n = options.grid_points
    # grid denser near the root, where the fillet thickness changes fastest
    u = np.linspace(0.0, 1.0, n)
    eta = (y[-1] - y_root) * u**1.5
    half = np.interp(y_root + eta, y, x)
    r_int_opt = options.bore_radius1 if gear == 1 else options.bore_radius2
    r_int = 0.5 * rf if r_int_opt is None else r_int_opt
    if r_int >= rf:
        raise InputError(
            f"bore_radius{gear} = {r_int * 1e3:.6g} mm: valid range 0 < r_int < r_f = "
            f"{rf * 1e3:.6g} mm"
        )
    arrays = (y, x, eta, half, *beam_integrals(eta, half))
    for arr in arrays:
        arr.setflags(write=False)
    return ToothTable(*arrays, y_root=y_root, r_f=rf, r_form=r_form, theta_f=theta_f,
                      r_int=r_int)
