"""Kinematics of a gear pair with geometric eccentricity (Liu et al. 2017, eqs. 1-13).

Rotation centres O1 = (0, 0), O2 = (H, 0) (``H = GearPair.a_w``); the geometric centres orbit
them, ``O1' = O1 + e1 (cos(ph1 + th1), sin(ph1 + th1))``, ``O2' = O2 + e2 (cos(ph2 - th2),
sin(ph2 - th2))`` (eq. 1). From them, exactly for rigid involute teeth: the centre distance
``l = |O1'O2'|`` (eq. 2), the dynamic pressure angle ``alpha = arccos((r_b1 + r_b2) / l) - gamma``
(eqs. 3-5), the tangent points A, B and the pitch point ``P = (x_P, 0)`` (eqs. 6-11), the ratio
``i12 = (H - x_P) / x_P`` (eq. 12) and the flank's normal speed ``v = w1 x_P cos alpha`` (eq. 13;
the paper prints ``cos psi``).

Displacement form: unwinding the involutes gives ``r_b1 th1 - r_b2 th2 = |AB| - (r_b1 + r_b2)
alpha + const``, hence the rigid gear angle (Newton's method), the eccentricity's
displacement along the line of action ``e_ecc = r_b2 th2 - r_b1 th1`` (m) and the contact travel
from the moving tangent point ``tau = r_b1 (th1 + alpha - alpha_0)`` (m). With ``e1 = e2 = 0``
everything reduces to the error-free pair. The readings of the paper are listed in
docs/eccentricity.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from types import SimpleNamespace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gear_dyn.errors import InputError, check_range
from gear_dyn.geometry import GearPair, check_speed

FloatArray = NDArray[np.float64]
Scalar = float | FloatArray

#: math functions under numpy's names, so the same formulas run fast on Python floats
_MATH = SimpleNamespace(cos=math.cos, sin=math.sin, sqrt=math.sqrt, arccos=math.acos,
                        arctan2=math.atan2)

#: of (e1 + e2) / r_b2, the scale of u (rounding moves u by ~1e-15 rad); Newton's steps converge
#: quadratically, so the last iterate is far below the tolerance from the solution
_FIXED_POINT_TOL = 1e-12
_EPS = float(np.finfo(float).eps)
_FIXED_POINT_MAX = 60
#: factor on the predicted error of the next Newton step before it is skipped
_NEWTON_SAFETY = 100.0


@dataclass(frozen=True)
class Eccentricity:
    """Geometric eccentricity of pinion and gear.

    Parameters
    ----------
    e1, e2 : float
        Eccentricities of pinion and gear in m (>= 0, <= 0.01 m).
    phase1, phase2 : float
        Initial position angles ph1, ph2 of the geometric centres in rad (Liu et al. 2017,
        eq. 1).

    Raises
    ------
    InputError
        Negative, non-finite or absurdly large values.
    """

    e1: float = 0.0
    e2: float = 0.0
    phase1: float = 0.0
    phase2: float = 0.0

    def __post_init__(self) -> None:
        check_range("eccentricity.pinion", self.e1, "m", low=0.0, high=0.01)
        check_range("eccentricity.gear", self.e2, "m", low=0.0, high=0.01)
        check_range("eccentricity.phase_pinion", self.phase1, "rad", low=-1e3, high=1e3)
        check_range("eccentricity.phase_gear", self.phase2, "rad", low=-1e3, high=1e3)

    @property
    def active(self) -> bool:
        """True if either gear is eccentric."""
        return self.e1 > 0.0 or self.e2 > 0.0


@dataclass(slots=True)
class Kinematics:
    """Kinematic state of the eccentric pair at one or many instants (SI units).

    Every attribute is a float (one instant) or an array (same shape as the times).

    Attributes
    ----------
    t : time in s
    theta1, theta2 : pinion (CCW) and gear (CW) rotation angles in rad
    x1, y1, x2, y2 : geometric centres O1', O2' in m (eq. 1)
    l : actual centre distance in m (eq. 2)
    psi, gamma, alpha : eq. 3, eq. 4 and dynamic transverse pressure angle (eq. 5) in rad
    xa, ya, xb, yb : tangent points A, B in m (eq. 9)
    ab : tangent length ``|AB|`` in m
    xp : abscissa of the pitch point P in m (eq. 11); also the instantaneous pitch radius r1
    ratio : instantaneous ratio i12 = w1 / w2 (eq. 12)
    w1, w2 : pinion and gear speeds in rad/s
    v : normal speed of the pinion flank on the line of action in m/s (eq. 13, exact form)
    arm1, arm2 : distances from O1, O2 to the line of action in m (moment arms of the normal load)
    travel : contact travel tau from the moving tangent point A in m
    l_ac, l_ad, l_ap : distances from A to the start of contact C, end of contact D, pitch point P
    foot1, foot2 : positions (from A, along the line) of the feet of the perpendiculars from O1, O2
    e_ecc : displacement of the eccentricity along the line of action in m
    e_ecc_rate : its time derivative in m/s
    """

    t: Scalar
    theta1: Scalar
    theta2: Scalar
    x1: Scalar
    y1: Scalar
    x2: Scalar
    y2: Scalar
    l: Scalar
    psi: Scalar
    gamma: Scalar
    alpha: Scalar
    xa: Scalar
    ya: Scalar
    xb: Scalar
    yb: Scalar
    ab: Scalar
    xp: Scalar
    ratio: Scalar
    w1: float
    w2: Scalar
    v: Scalar
    arm1: Scalar
    arm2: Scalar
    travel: Scalar
    l_ac: Scalar
    l_ad: float
    l_ap: Scalar
    foot1: Scalar
    foot2: Scalar
    e_ecc: Scalar
    e_ecc_rate: Scalar

    @property
    def l_cd(self) -> Scalar:
        """Instantaneous transverse length of the path of contact C..D in m."""
        return self.l_ad - self.l_ac

    @property
    def l_cp(self) -> Scalar:
        """Distance from the start of contact C to the pitch point P in m (Liu et al. 2017,
        eq. 20)."""
        return self.l_ap - self.l_ac


@dataclass(frozen=True, eq=False)
class EccentricMesh:
    """A gear pair with geometric eccentricity, driven at constant pinion speed.

    Parameters
    ----------
    pair : GearPair
        The gear pair; its operating centre distance ``a_w`` is the mounting distance H.
    eccentricity : Eccentricity
        e1, e2 and their initial phases.
    speed : float
        Pinion speed w1 in rad/s (> 0).

    Raises
    ------
    InputError
        Eccentricity so large that the centre distance could reach the base circles, that the
        total contact ratio could fall below 1, or larger than half the module (the contact-line
        bookkeeping assumes the start of contact moves by less than a base pitch).

    Examples
    --------
    >>> import math
    >>> from gear_dyn.geometry import GearPair
    >>> pair = GearPair(18, 70, 3e-3, math.radians(20), 0.04, math.radians(15))
    >>> mesh = EccentricMesh(pair, Eccentricity(), 50 * math.pi)
    >>> round(float(mesh.kinematics(0.01).ratio), 12) == round(70 / 18, 12)
    True
    """

    pair: GearPair
    eccentricity: Eccentricity
    speed: float
    _c: dict[str, float] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        check_speed(self.speed)
        p, ec = self.pair, self.eccentricity
        rbs = p.rb1 + p.rb2
        h = p.a_w
        e_sum = ec.e1 + ec.e2
        if e_sum > 0.5 * p.module:
            raise InputError(
                f"eccentricity e1 + e2 = {e_sum * 1e3:.6g} mm: valid range <= half the module "
                f"({0.5 * p.module * 1e3:.6g} mm)"
            )
        l_max, l_min = h + e_sum, h - e_sum
        if l_min <= rbs * (1 + 1e-9):
            raise InputError(
                f"eccentricity e1 + e2 = {e_sum * 1e3:.6g} mm brings the centre distance to the "
                f"base circles; valid range < {(h - rbs) * 1e3:.6g} mm"
            )
        g_min = p.tip_reach1 + p.tip_reach2 - math.sqrt(l_max**2 - rbs**2)
        eps_min = g_min / p.base_pitch + p.overlap_ratio
        if eps_min < 1.0:
            raise InputError(
                f"eccentricity e1 + e2 = {e_sum * 1e3:.6g} mm: at the largest centre distance the "
                f"total contact ratio is {eps_min:.4f}; it must stay >= 1"
            )
        c: dict[str, float] = dict(
            e1=ec.e1, e2=ec.e2, p1=ec.phase1, p2=ec.phase2, h=h, rb1=p.rb1, rb2=p.rb2, rbs=rbs,
            tip2=p.tip_reach2, l_ad=p.tip_reach1, w1=self.speed,
            ab_min=math.sqrt(l_min**2 - rbs**2), ab_max=math.sqrt(l_max**2 - rbs**2),
        )
        g0 = _geometry(_MATH, c, _pinion(_MATH, c, 0.0), 0.0)
        c["ab0"] = g0["ab"]
        c["alpha0"] = g0["alpha"]
        c["l_ac0"] = g0["ab"] - c["tip2"]
        object.__setattr__(self, "_c", c)

    # ------------------------------------------------------------------ constants
    @property
    def l_ac0(self) -> float:
        """Distance A..C at t = 0 (``L_AC0`` of Liu et al. 2017) in m."""
        return self._c["l_ac0"]

    @property
    def angle_key(self) -> tuple[tuple[str, float], ...]:
        """The constants that fix the kinematics as functions of the pinion angle (all but the
        speed): meshes with equal keys differ only in their speed."""
        return tuple(sorted((k, v) for k, v in self._c.items() if k != "w1"))

    @property
    def l_ac_range(self) -> tuple[float, float]:
        """Bounds (min, max) of the distance A..C over all eccentric positions in m."""
        return self._c["ab_min"] - self._c["tip2"], self._c["ab_max"] - self._c["tip2"]

    @property
    def shaft_frequencies(self) -> tuple[float, float]:
        """Nominal rotation frequencies (f1, f2) of pinion and gear in Hz."""
        f1 = self.speed / (2 * math.pi)
        return f1, f1 * self.pair.z1 / self.pair.z2

    @property
    def mesh_frequency(self) -> float:
        """Mesh frequency z1 f1 in Hz."""
        return self.pair.z1 * self.speed / (2 * math.pi)

    @property
    def hunting_period(self) -> float:
        """Time after which pinion and gear both return to their start (s): z2 / (gcd f1)."""
        return self.pair.z2 / (math.gcd(self.pair.z1, self.pair.z2) * self.shaft_frequencies[0])

    # ------------------------------------------------------------------ evaluation
    def kinematics(self, t: ArrayLike | float) -> Kinematics:
        """Kinematic state at time(s) ``t`` (s) with th1 = w1 t and the rigid gear angle th2.

        A Python float gives floats (fast path used inside model right-hand sides); anything
        else gives arrays of the shape of ``t``.
        """
        c = self._c
        xp: Any
        tt: Any
        if isinstance(t, float | int):
            xp, tt = _MATH, float(t)
        else:
            xp, tt = np, np.asarray(t, dtype=float)
        th1 = c["w1"] * tt
        nominal = th1 * c["rb1"] / c["rb2"]
        # the gear angle as nominal + u, u = e_ecc / r_b2 small: iterating on u keeps it free of
        # the cancellation of r_b2 th2 - r_b1 th1 (th1 grows without bound, u does not)
        pin = _pinion(xp, c, th1)
        if c["e2"] > 0.0:
            # Newton's method on u = F(u) (F' ~ e2 / r_b2, so it converges quadratically from
            # u = 0: two or three steps to rounding), on the light evaluation of the gear's
            # part; the whole geometry once, at the last iterate. It stops when a step moves u
            # by less than the tolerance, or when the next step would: quadratic convergence,
            # e_next = K e^2 with K ~ c2 / c1^2 from two successive steps c1, c2, predicts the
            # error after c2 as c2^3 / c1^2 (Kelley 2003, on terminating Newton iterations), taken
            # _NEWTON_SAFETY times
            scalar = xp is _MATH
            # rounding of the angle p2 - th2 moves u by ~eps |th2| e2 / r_b2: never ask for less
            big = abs(nominal) if scalar else float(np.max(np.abs(nominal)))
            tol = (_FIXED_POINT_TOL * (c["e1"] + c["e2"]) + 8 * _EPS * big * c["e2"]) / c["rb2"]
            u = 0.0 * th1
            step: Any = None
            for _ in range(_FIXED_POINT_MAX):
                f, df = _rigid_u_newton(xp, c, pin, nominal + u)
                u_new = u - (u - f) / (1.0 - df)
                prev, step = step, abs(u_new - u) if scalar else np.abs(u_new - u)
                u = u_new
                change = step if scalar else float(np.max(step))
                if change <= tol:
                    break
                if prev is not None:
                    if scalar:
                        ahead = step**3 / prev**2 if prev > 0.0 else 0.0
                    else:
                        ahead = float(np.max(np.where(prev > 0.0, step**3 / np.where(
                            prev > 0.0, prev, 1.0)**2, 0.0)))
                    if _NEWTON_SAFETY * ahead <= tol:
                        break
            g = _geometry(xp, c, pin, nominal + u)
        else:
            g = _geometry(xp, c, pin, nominal)
            u = _rigid_u(c, g)
        return _assemble(c, tt, th1, nominal, u, g)


def _pinion(xp: Any, c: dict[str, float], th1: Any) -> tuple[Any, Any]:
    """The pinion's geometric centre O1' (eq. 1) at rotation angle th1 (CCW) in m."""
    return c["e1"] * xp.cos(c["p1"] + th1), c["e1"] * xp.sin(c["p1"] + th1)


def _geometry(xp: Any, c: dict[str, float], pin: tuple[Any, Any], th2: Any) -> dict[str, Any]:
    """Liu et al. (2017), eqs. 1-11, for the pinion centre ``pin`` = :func:`_pinion` and the
    gear's rotation angle th2 (CW); xp = numpy or math."""
    e2, h, rb1, rbs = c["e2"], c["h"], c["rb1"], c["rbs"]
    x1, y1 = pin
    x2 = h + e2 * xp.cos(c["p2"] - th2)
    y2 = e2 * xp.sin(c["p2"] - th2)
    dx, dy = x2 - x1, y2 - y1
    l2 = dx * dx + dy * dy
    l = xp.sqrt(l2)
    psi = xp.arccos(rbs / l)
    gamma = xp.arctan2(dy, dx)
    alpha = psi - gamma
    ca, sa = xp.cos(alpha), xp.sin(alpha)
    xa = x1 + rb1 * ca
    ya = y1 - rb1 * sa
    xb = x2 - c["rb2"] * ca
    yb = y2 + c["rb2"] * sa
    ab = xp.sqrt(l2 - rbs * rbs)
    xpp = xa - ya * sa / ca
    a_u = xa * sa + ya * ca
    return dict(x1=x1, y1=y1, x2=x2, y2=y2, l=l, psi=psi, gamma=gamma, alpha=alpha, ca=ca, sa=sa,
                xa=xa, ya=ya, xb=xb, yb=yb, ab=ab, xp=xpp, a_u=a_u)


def _rigid_u(c: dict[str, float], g: dict[str, Any]) -> Any:
    """Gear angle minus its nominal value r_b1 th1 / r_b2, from the displacement relation of
    rigid involute teeth (rad)."""
    return (c["rbs"] * (g["alpha"] - c["alpha0"]) - (g["ab"] - c["ab0"])) / c["rb2"]


def _rigid_u_newton(xp: Any, c: dict[str, float], pin: tuple[Any, Any], th2: Any
                    ) -> tuple[Any, Any]:
    """:func:`_rigid_u` at the gear angle th2 and its derivative with respect to th2, from the
    gear's part of :func:`_geometry` only (what Newton's method on u needs)."""
    e2, rbs = c["e2"], c["rbs"]
    x1, y1 = pin
    ca2, sa2 = xp.cos(c["p2"] - th2), xp.sin(c["p2"] - th2)
    dx, dy = c["h"] + e2 * ca2 - x1, e2 * sa2 - y1
    l2 = dx * dx + dy * dy
    ab = xp.sqrt(l2 - rbs * rbs)
    alpha = xp.arccos(rbs / xp.sqrt(l2)) - xp.arctan2(dy, dx)
    # d(dx)/d th2 = e2 sin(p2 - th2), d(dy)/d th2 = -e2 cos(p2 - th2)
    dl2 = 2.0 * e2 * (dx * sa2 - dy * ca2)
    dalpha = rbs * dl2 / (2.0 * l2 * ab) + e2 * (dx * ca2 + dy * sa2) / l2
    f = (rbs * (alpha - c["alpha0"]) - (ab - c["ab0"])) / c["rb2"]
    return f, (rbs * dalpha - 0.5 * dl2 / ab) / c["rb2"]


def _assemble(c: dict[str, float], t: Any, th1: Any, nominal: Any, u: Any, g: dict[str, Any]
              ) -> Kinematics:
    h, w1 = c["h"], c["w1"]
    th2 = nominal + u
    xpp, ca = g["xp"], g["ca"]
    w2 = w1 * xpp / (h - xpp)
    a_u = g["a_u"]
    return Kinematics(
        t=t, theta1=th1, theta2=th2, x1=g["x1"], y1=g["y1"], x2=g["x2"], y2=g["y2"], l=g["l"],
        psi=g["psi"], gamma=g["gamma"], alpha=g["alpha"], xa=g["xa"], ya=g["ya"], xb=g["xb"],
        yb=g["yb"], ab=g["ab"], xp=xpp, ratio=(h - xpp) / xpp, w1=w1, w2=w2, v=w1 * xpp * ca,
        arm1=xpp * ca, arm2=(h - xpp) * ca, travel=c["rb1"] * (th1 + g["alpha"] - c["alpha0"]),
        l_ac=g["ab"] - c["tip2"], l_ad=c["l_ad"], l_ap=-g["ya"] / ca, foot1=-a_u,
        foot2=h * g["sa"] - a_u, e_ecc=c["rb2"] * u,
        e_ecc_rate=c["rb2"] * w2 - c["rb1"] * w1,
    )
