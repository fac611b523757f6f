"""ISO 6336-1 method B dynamic factor K_v (the standard's figure beside a simulated one).

Clause 6.5 of ISO 6336-1 (equation numbers of the 2006 edition), for a single external pair::

    m_red = m1* m2* / (m1* + m2*),  m_i* = J_i* / r_bi^2       (6.5.9, eq. 30 ff.; J* per unit
                                                                face width: kg/m)
    n_E1  = 30 000 / (pi z1) sqrt(c_gamma_alpha / m_red)       (eq. 6, min^-1; c in N/(mm um),
                                                                m_red in kg/mm)
    N     = n1 / n_E1                                          (eq. 9)
    N_S   = 0.5 + 0.35 sqrt(K_A F_t / (b 100 N/mm))  if K_A F_t/b < 100 N/mm, else 0.85
                                                               (eqs. 11, 12)
    B_p   = c' f_pb,eff / (K_A F_t / b)                        (eq. 15)
    B_f   = c' f_f,eff  / (K_A F_t / b)                        (eq. 16)
    B_k   = |1 - c' C_a / (K_A F_t / b)|                       (eq. 17)
    f_pb,eff = f_pb - y_p,  f_f,eff = f_falpha - y_f           (eqs. 18, 19)

and, by the speed range of N (Table 8 gives C_v1..C_v7 from eps_gamma = eps_a + eps_b)::

    subcritical     N <= N_S          K_v = N (C_v1 B_p + C_v2 B_f + C_v3 B_k) + 1   (eqs. 13, 14)
    main resonance  N_S < N <= 1.15   K_v = C_v1 B_p + C_v2 B_f + C_v4 B_k + 1       (eq. 20)
    intermediate    1.15 < N < 1.5    K_v = K_v(1.5) + (K_v(1.15) - K_v(1.5)) (1.5 - N) / 0.35
                                                                                    (eq. 22)
    supercritical   N >= 1.5          K_v = C_v5 B_p + C_v6 B_f + C_v7               (eq. 21)

K_v is continuous at N = 1.15 and 1.5 (the intermediate range interpolates linearly) and jumps
at N = N_S (the standard's choice: the subcritical line and the resonance plateau do not meet).

In SI units eq. 6 reads n_E1 = 60 / (2 pi z1) sqrt(c_gamma_alpha / m_red): the pinion speed at
which the mesh frequency z1 n1 / 60 equals the natural frequency of a single-DOF mesh oscillator
of stiffness c_gamma_alpha b and mass m_red b.

Deviations (ISO 1328-1) and running-in (ISO 6336-1, y_alpha and C_ay):
:func:`iso1328_deviations`, :func:`running_in_allowance`, :func:`running_in_tip_relief`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gear_dyn.errors import InputError, check_range
from gear_dyn.geometry import GearPair
from gear_dyn.stiffness.iso6336 import iso6336_stiffness

FloatArray = NDArray[np.float64]
UM = 1e-6

#: the speed ranges of method B, in order of N
RANGES = ("subcritical", "main resonance", "intermediate", "supercritical")
#: the formula used in each range (what a summary prints beside K_v)
FORMULAS = {
    "subcritical": "K_v = N (C_v1 B_p + C_v2 B_f + C_v3 B_k) + 1 (ISO 6336-1 eqs. 13-14)",
    "main resonance": "K_v = C_v1 B_p + C_v2 B_f + C_v4 B_k + 1 (ISO 6336-1 eq. 20)",
    "intermediate": "K_v = K_v(N=1.5) + (K_v(N=1.15) - K_v(N=1.5)) (1.5 - N)/0.35 "
                    "(ISO 6336-1 eq. 22)",
    "supercritical": "K_v = C_v5 B_p + C_v6 B_f + C_v7 (ISO 6336-1 eq. 21)",
}
RUNNING_IN = ("none", "case_hardened", "through_hardened")


@dataclass(frozen=True)
class CvCoefficients:
    """C_v1..C_v7 of ISO 6336-1 Table 8 for a total contact ratio eps_gamma."""

    cv1: float
    cv2: float
    cv3: float
    cv4: float
    cv5: float
    cv6: float
    cv7: float


def cv_coefficients(eps_gamma: float) -> CvCoefficients:
    """ISO 6336-1 Table 8: constants for 1 < eps_gamma <= 2, functions of eps_gamma above 2.

    C_v7 is 0.75 up to eps_gamma = 1.5, 0.125 sin(pi (eps_gamma - 2)) + 0.875 up to 2.5, then 1.
    """
    e = check_range("eps_gamma", eps_gamma, "", low=1.0, high=20.0, low_open=True)
    if e <= 2.0:
        cv2, cv3, cv4, cv6 = 0.34, 0.23, 0.90, 0.47
    else:
        cv2 = 0.57 / (e - 0.3)
        cv3 = 0.096 / (e - 1.56)
        cv4 = (0.57 - 0.05 * e) / (e - 1.44)
        cv6 = 0.12 / (e - 1.74)
    cv7 = 0.75 if e <= 1.5 else 0.125 * math.sin(math.pi * (e - 2.0)) + 0.875 if e <= 2.5 else 1.0
    return CvCoefficients(0.32, cv2, cv3, cv4, 0.47, cv6, cv7)


def lower_resonance_limit(line_load: float) -> float:
    """N_S (eqs. 11, 12): 0.85, or 0.5 + 0.35 sqrt(w / 100 N/mm) below w = K_A F_t/b = 100 N/mm.

    ``line_load`` w in N/m (1e5 N/m = 100 N/mm).
    """
    w = check_range("line_load", line_load, "N/m", low=0.0, low_open=True)
    return 0.5 + 0.35 * math.sqrt(w / 1e5) if w < 1e5 else 0.85


def reduced_mass(i1: float, i2: float, rb1: float, rb2: float, face_width: float) -> float:
    """m_red per unit face width in kg/m (6.5.9): m1* m2* / (m1* + m2*), m_i* = I_i / (b r_bi^2).

    The same mass as the single-DOF model's m_e = I1 I2 / (r_b1^2 I2 + r_b2^2 I1), divided by b.
    """
    for name, v, unit in (("inertia_pinion", i1, "kg*m^2"), ("inertia_gear", i2, "kg*m^2"),
                          ("face_width", face_width, "m")):
        check_range(name, v, unit, low=0.0, low_open=True)
    m1, m2 = i1 / (face_width * rb1**2), i2 / (face_width * rb2**2)
    return m1 * m2 / (m1 + m2)


def reduced_mass_solid_wheels(pair: GearPair) -> float:
    """m_red in kg/m by ISO 6336-1's approximation for solid wheels (6.5.9, eq. 30):
    pi/8 (d_m1/d_b1)^2 d_m1^2 / (1/rho1 + 1/(rho2 u^2)), d_m1 = (d_a1 + d_f1)/2, u = z2/z1.

    For comparison with :func:`reduced_mass` of the model's inertias (the model's default blanks
    are solid cylinders at the pitch radii, not at d_m).
    """
    d_m1 = pair.ra1 + pair.rf1
    u = pair.z2 / pair.z1
    return (math.pi / 8 * (d_m1 / (2 * pair.rb1)) ** 2 * d_m1**2
            / (1 / pair.density1 + 1 / (pair.density2 * u**2)))


def resonance_speed(z1: int, c_gamma_alpha: float, m_red: float) -> float:
    """n_E1 in rpm (eq. 6 in SI units): 60 / (2 pi z1) sqrt(c_gamma_alpha / m_red).

    ``c_gamma_alpha`` in N/m^2 (N/m per m of face width), ``m_red`` in kg/m.
    """
    return 60.0 / (2 * math.pi * z1) * math.sqrt(c_gamma_alpha / m_red)


def kv_method_b(ratio: ArrayLike, cv: CvCoefficients, b_p: ArrayLike, b_f: ArrayLike,
                b_k: ArrayLike, n_s: float) -> tuple[FloatArray, NDArray[np.str_]]:
    """K_v and the name of the speed range for resonance ratios N (vectorised; eqs. 13-22).

    Parameters
    ----------
    ratio : array_like
        N = n1 / n_E1 (>= 0).
    cv : CvCoefficients
    b_p, b_f, b_k : array_like
        The B factors (eqs. 15-17), scalars or of the shape of ``ratio``.
    n_s : float
        N_S, the lower limit of the main resonance range.

    Returns
    -------
    k_v : ndarray
    speed_range : ndarray of str
        One of :data:`RANGES` per N.
    """
    n = np.asarray(ratio, dtype=float)
    bp, bf, bk = (np.broadcast_to(np.asarray(b, dtype=float), n.shape) for b in (b_p, b_f, b_k))
    sub = n * (cv.cv1 * bp + cv.cv2 * bf + cv.cv3 * bk) + 1.0
    main = cv.cv1 * bp + cv.cv2 * bf + cv.cv4 * bk + 1.0
    sup = cv.cv5 * bp + cv.cv6 * bf + cv.cv7
    inter = sup + (main - sup) * (1.5 - n) / 0.35
    masks = [n <= n_s, n <= 1.15, n < 1.5]
    k_v = np.select(masks, [sub, main, inter], default=sup)
    names = np.select(masks, list(RANGES[:3]), default=RANGES[3])
    return k_v.astype(float), names


def iso1328_deviations(grade: int, module: float, diameter: float) -> tuple[float, float]:
    """(f_pt, f_falpha) in m: ISO 1328-1:1995 tolerances of accuracy grade ``grade`` (0..12).

    Grade 5: f_pt = 0.3 (m_n + 0.4 sqrt d) + 4, f_falpha = 2.5 sqrt m_n + 0.17 sqrt d + 0.5 um
    (m_n, d in mm), times sqrt(2)^(grade - 5); unrounded (the standard rounds its tables).
    Valid for 0.5 <= m_n <= 70 mm and 5 <= d <= 10 000 mm; applied as is outside.
    """
    q = check_range("accuracy_grade", grade, "", low=0, high=12)
    m = check_range("module", module, "m", low=0.0, low_open=True) * 1e3
    d = check_range("diameter", diameter, "m", low=0.0, low_open=True) * 1e3
    step = math.sqrt(2.0) ** (q - 5)
    f_pt = (0.3 * (m + 0.4 * math.sqrt(d)) + 4.0) * step
    f_fa = (2.5 * math.sqrt(m) + 0.17 * math.sqrt(d) + 0.5) * step
    return f_pt * UM, f_fa * UM


def running_in_allowance(deviation: float, material: str, sigma_hlim: float | None = None,
                         velocity: ArrayLike = 0.0) -> FloatArray:
    """Running-in allowance y in m for a deviation f in m (the y_alpha rule of ISO 6336-1).

    Parameters
    ----------
    deviation : float
        f_pb (gives y_p) or f_falpha (gives y_f), m.
    material : {"none", "case_hardened", "through_hardened"}
        "none": no running-in credit (y = 0).
    sigma_hlim : float or None
        Allowable contact stress number in Pa (through_hardened only).
    velocity : array_like
        Pitch-line velocity in m/s (through_hardened: caps the allowance above 5 m/s).
    """
    f_um = deviation / UM
    v = np.asarray(velocity, dtype=float)
    if material == "none":
        return np.zeros_like(v)
    if material == "case_hardened":
        return np.full_like(v, min(0.075 * f_um, 3.0) * UM)
    if material != "through_hardened":
        raise InputError(f"running_in = {material!r}: valid choices are {', '.join(RUNNING_IN)}")
    if sigma_hlim is None:
        raise InputError("running_in = 'through_hardened' needs sigma_hlim (sigma_Hlim, e.g. "
                         "'900 MPa')")
    s = sigma_hlim / 1e6  # N/mm^2
    cap = np.where(v <= 5.0, np.inf, np.where(v <= 10.0, 12800.0 / s, 6400.0 / s))
    return np.minimum(160.0 / s * f_um, cap) * UM


def running_in_tip_relief(sigma_hlim: float) -> float:
    """C_ay in m: (sigma_Hlim/97 - 18.45)^2 / 18 + 1.5 um (sigma_Hlim in N/mm^2; here Pa)."""
    s = check_range("sigma_hlim", sigma_hlim, "Pa", low=0.0, low_open=True) / 1e6
    return ((s / 97.0 - 18.45) ** 2 / 18.0 + 1.5) * UM


@dataclass(frozen=True)
class IsoKv:
    """K_v by ISO 6336-1 method B at a set of pinion speeds, with the inputs it used.

    Arrays have the shape of the speeds; lengths in m, stiffness per face width in N/m^2.
    """

    speed_rpm: FloatArray
    k_v: FloatArray
    ratio: FloatArray
    speed_range: NDArray[np.str_]
    resonance_speed_rpm: float
    lower_limit: float
    b_p: FloatArray
    b_f: FloatArray
    b_k: float
    cv: CvCoefficients
    eps_gamma: float
    c_single: float
    c_gamma_alpha: float
    m_red: float
    line_load: float
    f_pb_eff: FloatArray
    f_f_eff: FloatArray
    tip_relief: float


def iso_dynamic_factor(pair: GearPair, speed: ArrayLike, torque: float,
                       inertias: tuple[float, float], *, f_pb: float, f_falpha: float,
                       tip_relief: float = 0.0, application_factor: float = 1.0,
                       running_in: str = "none", sigma_hlim: float | None = None) -> IsoKv:
    """ISO 6336-1 method B K_v of ``pair`` at pinion speeds ``speed`` (rad/s).

    c' and c_gamma_alpha come from :func:`~gear_dyn.stiffness.iso6336.iso6336_stiffness` at the
    line load K_A F_t / b (F_t = T1 / r1 at the reference circle), m_red from ``inertias``
    (:func:`reduced_mass`, the single-DOF model's mass per face width).

    Parameters
    ----------
    pair : GearPair
    speed : array_like
        Pinion speeds in rad/s (> 0).
    torque : float
        Pinion torque T1 in N m (> 0: K_v is not defined without load).
    inertias : (float, float)
        Polar inertias I1, I2 in kg m^2.
    f_pb, f_falpha : float
        Base pitch and profile form deviations in m (before running-in).
    tip_relief : float
        C_a in m (0: no relief, B_k = 1).
    application_factor : float
        K_A (>= 1).
    running_in, sigma_hlim
        See :func:`running_in_allowance`.
    """
    torque = check_range("torque", torque, "N*m", low=0.0, low_open=True)
    k_a = check_range("application_factor", application_factor, "", low=1.0, high=10.0)
    w = k_a * torque / pair.r1 / pair.face_width  # K_A F_t / b in N/m
    n1 = np.asarray(speed, dtype=float) * 60 / (2 * math.pi)
    if not np.all(np.isfinite(n1) & (n1 > 0)):
        raise InputError("speed: K_v needs pinion speeds > 0 rad/s")
    iso = iso6336_stiffness(pair, line_load=w)
    m_red = reduced_mass(*inertias, pair.rb1, pair.rb2, pair.face_width)
    n_e1 = resonance_speed(pair.z1, iso.c_mesh, m_red)
    v = np.abs(n1) * 2 * math.pi / 60 * pair.r1
    f_pb_eff = f_pb - running_in_allowance(f_pb, running_in, sigma_hlim, v)
    f_f_eff = f_falpha - running_in_allowance(f_falpha, running_in, sigma_hlim, v)
    b_p = iso.c_single * f_pb_eff / w
    b_f = iso.c_single * f_f_eff / w
    b_k = abs(1.0 - iso.c_single * tip_relief / w)
    eps_g = pair.total_contact_ratio
    cv = cv_coefficients(eps_g)
    n_s = lower_resonance_limit(w)
    ratio = n1 / n_e1
    k_v, names = kv_method_b(ratio, cv, b_p, b_f, b_k, n_s)
    return IsoKv(n1, k_v, ratio, names, n_e1, n_s, b_p, b_f, b_k, cv, eps_g, iso.c_single,
                 iso.c_mesh, m_red, w, f_pb_eff, f_f_eff, tip_relief)
