"""Tip relief: curves, amounts and lengths (Wang et al. 2024, eqs. 1-3; Han n.d.).

At distance ``x`` (m, along the line of action) from the start of a relief of amount ``C_a`` and
length ``L`` the depth removed is ``D(x) = C_a f(x / L)``, ``f(0) = 0``, ``f(1) = 1``: the power
curves ``f(u) = u^k`` of Wang et al. (2024), eq. 2, and the quarter-wave sine (decision: the
paper's eq. 3 lacks the factor 1/2). A length can also be given as a radial height ``h`` below
the tip circle: ``L = sqrt(r_a^2 - r_b^2) - sqrt((r_a - h)^2 - r_b^2)``. Recommended amounts:
:func:`recommended_relief`. docs/modification.md gives the derivations and decisions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gear_dyn.choices import RELIEF_CURVES
from gear_dyn.errors import InputError, check_range, current_name
from gear_dyn.geometry import GearPair, check_torque

FloatArray = NDArray[np.float64]

#: Exponent k of the power relief curves of Wang et al. (2024), eq. 2.
CURVE_EXPONENTS: dict[str, float] = {
    "linear": 1.0,
    "yoshio": 1.2,
    "walker": 1.5,
    "parabolic": 2.0,
}
#: All relief curve names.
CURVES = RELIEF_CURVES

#: Relief rules of :func:`recommended_relief`.
RULES: tuple[str, ...] = ("handbook", "dudley", "niemann", "wang2024", "kisssoft")
#: Old rule names -> their names now: still accepted, with a FutureWarning.
RENAMED_RULES: dict[str, str] = {"seed001": "wang2024"}


def current_rule(rule: str, where: str = "relief rule") -> str:
    """``rule``, or the name an old rule name (:data:`.RENAMED_RULES`) now has, with a
    :class:`FutureWarning` that names ``where`` (e.g. a scene's key path)."""
    return current_name(rule, RENAMED_RULES, where, "rule", "Wang et al. 2024")


def _check_curve(curve: str) -> str:
    if curve not in CURVES:
        raise InputError(f"relief curve = {curve!r}: valid values are {', '.join(CURVES)}")
    return curve


def relief_shape(u: ArrayLike, curve: str) -> tuple[FloatArray, FloatArray]:
    """Normalised relief curve ``f(u)`` and its slope ``df/du``.

    Parameters
    ----------
    u : array_like
        Position along the relief as a fraction of its length (dimensionless); values are clipped
        to [0, 1] (no relief before the start, the full amount beyond the tip).
    curve : str
        One of :data:`.CURVES`.

    Returns
    -------
    f, df : ndarray
        Value (0 at u = 0, 1 at u = 1) and slope. The slope is 0 outside (0, 1] (at the tip,
        u = 1, it is the curve's end slope).

    Raises
    ------
    InputError
        Unknown curve name.

    Examples
    --------
    >>> f, _ = relief_shape([0.0, 0.5, 1.0], "parabolic")
    >>> [round(float(v), 6) for v in f]
    [0.0, 0.25, 1.0]
    """
    _check_curve(curve)
    uu = np.asarray(u, dtype=float)
    inside = (uu > 0.0) & (uu <= 1.0 + 1e-9)  # the tip itself, with rounding
    uc = np.clip(uu, 0.0, 1.0)
    if curve == "sine":
        f = np.sin(0.5 * np.pi * uc)
        df = 0.5 * np.pi * np.cos(0.5 * np.pi * uc)
    else:
        k = CURVE_EXPONENTS[curve]
        f = uc**k
        with np.errstate(divide="ignore", invalid="ignore"):
            df = np.where(uc > 0.0, k * uc ** (k - 1.0), 0.0 if k > 1.0 else 1.0)
    return f, np.where(inside, df, 0.0)


@dataclass(frozen=True)
class TipRelief:
    """Tip relief of one gear.

    Parameters
    ----------
    amount : float
        Relief amount C_a at the tip in m (0 .. 1 mm).
    length : float
        Relief length L along the line of action, from the start of the modification to the tip,
        in m (> 0, <= 1 m; checked against the tooth in :meth:`ProfileModification.check`).
    curve : str
        Relief curve, one of :data:`.CURVES` (default ``"linear"``).

    Raises
    ------
    InputError
        Amount or length out of range, unknown curve.
    """

    amount: float
    length: float
    curve: str = "linear"

    def __post_init__(self) -> None:
        check_range("relief amount", self.amount, "m", low=0.0, high=1e-3)
        check_range("relief length", self.length, "m", low=0.0, high=1.0, low_open=True)
        _check_curve(self.curve)

    def depth(self, x: ArrayLike) -> FloatArray:
        """Relief D(x) in m at distance ``x`` (m) from the start of the modification."""
        f, _ = relief_shape(np.asarray(x, dtype=float) / self.length, self.curve)
        return self.amount * f

    def slope(self, x: ArrayLike) -> FloatArray:
        """dD/dx (dimensionless) at distance ``x`` (m) from the start of the modification."""
        _, df = relief_shape(np.asarray(x, dtype=float) / self.length, self.curve)
        return self.amount * df / self.length


def _gear_radii(pair: GearPair, gear: int) -> tuple[float, float, float]:
    if gear not in (1, 2):
        raise InputError(f"gear = {gear!r}: valid values are 1 (pinion) and 2 (gear)")
    if gear == 1:
        return pair.ra1, pair.rb1, pair.tip_reach1
    return pair.ra2, pair.rb2, pair.tip_reach2


def length_from_height(pair: GearPair, gear: int, height: float) -> float:
    """Relief length along the line of action (m) for a relief height on the tooth.

    Parameters
    ----------
    pair : GearPair
    gear : int
        1 for the pinion, 2 for the gear.
    height : float
        Radial distance from the tip circle to the start of the modification in m
        (0 < h <= r_a - r_b).

    Returns
    -------
    float
        ``sqrt(r_a^2 - r_b^2) - sqrt((r_a - h)^2 - r_b^2)`` in m.

    Raises
    ------
    InputError
        Height not positive or reaching below the base circle.
    """
    ra, rb, reach = _gear_radii(pair, gear)
    check_range(f"relief height (gear {gear})", height, "m", low=0.0, high=ra - rb, low_open=True)
    return reach - math.sqrt(max((ra - height) ** 2 - rb**2, 0.0))


def height_from_length(pair: GearPair, gear: int, length: float) -> float:
    """Relief height on the tooth (m) for a relief length along the line of action (m).

    Inverse of :func:`length_from_height`: ``h = r_a - sqrt((sqrt(r_a^2 - r_b^2) - L)^2 + r_b^2)``.

    Raises
    ------
    InputError
        Length not positive or longer than the roll length from the base circle to the tip.
    """
    ra, rb, reach = _gear_radii(pair, gear)
    check_range(f"relief length (gear {gear})", length, "m", low=0.0, high=reach, low_open=True)
    return ra - math.sqrt((reach - length) ** 2 + rb**2)


@dataclass(frozen=True)
class ProfileModification:
    """Tip reliefs of a pair: on the pinion, the gear, both or neither.

    Parameters
    ----------
    pinion, gear : TipRelief or None
        Tip relief of the pinion (acts near the end of contact E) and of the gear (acts near the
        start of contact A); None for an unmodified tooth.
    """

    pinion: TipRelief | None = None
    gear: TipRelief | None = None

    @property
    def is_zero(self) -> bool:
        """True if neither gear removes any material."""
        return all(r is None or r.amount == 0.0 for r in (self.pinion, self.gear))

    def check(self, pair: GearPair) -> None:
        """Check that each relief starts above its base circle.

        Raises
        ------
        InputError
            A relief length longer than the roll length from the base circle to the tip.
        """
        for gear, relief in ((1, self.pinion), (2, self.gear)):
            if relief is not None:
                _, _, reach = _gear_radii(pair, gear)
                check_range(f"relief length ({'pinion' if gear == 1 else 'gear'})",
                            relief.length, "m", low=0.0, high=reach, low_open=True)

    def roll_depth(self, pair: GearPair, gear: int, rho: ArrayLike) -> tuple[FloatArray,
                                                                            FloatArray]:
        """Relief of one gear and its slope as functions of that gear's roll distance.

        Parameters
        ----------
        pair : GearPair
        gear : int
            1 (pinion) or 2 (gear).
        rho : array_like
            Roll distance from the gear's base-circle tangent point along the line of action in m
            (the involute's radius of curvature at the contact point).

        Returns
        -------
        depth, slope : ndarray
            Relief in m and dD/drho (dimensionless); zeros for an unmodified gear.
        """
        r = np.asarray(rho, dtype=float)
        relief = self.pinion if gear == 1 else self.gear
        if relief is None:
            return np.zeros_like(r), np.zeros_like(r)
        _, _, reach = _gear_radii(pair, gear)
        x = r - (reach - relief.length)
        return relief.depth(x), relief.slope(x)

    def separation(self, pair: GearPair, s: ArrayLike) -> FloatArray:
        """Unloaded gap (m) the reliefs open at contact position ``s`` (m from T1 along the LoA).

        The sum of the pinion relief (roll distance ``s``) and the gear relief (roll distance
        ``T1T2 - s``).
        """
        s = np.asarray(s, dtype=float)
        d1, _ = self.roll_depth(pair, 1, s)
        d2, _ = self.roll_depth(pair, 2, pair.line_of_action_length - s)
        return d1 + d2


# ---------------------------------------------------------------------------- recommended amounts
@dataclass(frozen=True)
class ReliefRecommendation:
    """A recommended tip relief for both gears of a pair.

    Attributes
    ----------
    rule : str
        Rule name (one of :data:`.RULES`).
    source : str
        Where the rule comes from, with its formula.
    amount_pinion, amount_gear : float
        Relief amounts C_a1, C_a2 in m.
    height_pinion, height_gear : float
        Relief heights on the teeth (radial, from the tip) in m.
    length_pinion, length_gear : float
        Relief lengths along the line of action in m.
    """

    rule: str
    source: str
    amount_pinion: float
    amount_gear: float
    height_pinion: float
    height_gear: float
    length_pinion: float
    length_gear: float

    def modification(self, curve: str = "linear") -> ProfileModification:
        """The :class:`ProfileModification` with this rule's amounts and lengths."""
        return ProfileModification(
            pinion=TipRelief(self.amount_pinion, self.length_pinion, curve),
            gear=TipRelief(self.amount_gear, self.length_gear, curve),
        )


def tangential_load_per_width(pair: GearPair, torque: float) -> float:
    """``w_t = F_t / B`` in N/mm with ``F_t = T1 / r1`` at the pinion reference circle (Han n.d.).

    Parameters
    ----------
    pair : GearPair
    torque : float
        Pinion torque T1 in N m (> 0).
    """
    check_torque(torque, positive=True)
    return torque / pair.r1 / (pair.face_width * 1e3)


def long_relief_length(pair: GearPair) -> float:
    """Length (m) of a *long* relief (tip to single-contact point): ``(eps_a - 1) p_bt``.

    Raises
    ------
    InputError
        Contact ratio >= 2 (no single-contact zone, so no long relief).
    """
    eps = pair.contact_ratio
    if eps >= 2.0:
        raise InputError(
            f"contact_ratio = {eps:.4f}: a long relief (tip to single-contact point) needs "
            "1 <= contact ratio < 2"
        )
    return (eps - 1.0) * pair.base_pitch


def recommended_relief(
    pair: GearPair,
    torque: float,
    rule: str,
    *,
    handbook_a: float = 9.0,
    handbook_b: float = 4.0,
    face_load_factor: float = 1.0,
) -> ReliefRecommendation:
    """Recommended tip relief of a pair by one of the published rules.

    ``"handbook"`` (the gear handbook of 1993), ``"dudley"`` (Dudley 1984) and ``"niemann"``
    (Niemann & Winter 1983), as Han (n.d.) quotes them, ``"wang2024"`` (Wang et al. 2024,
    eq. 1; its old name ``"seed001"`` still works, with a FutureWarning), and ``"kisssoft"``,
    the short relief of KISSsoft that Han (n.d.) compares without printing it, as defined here
    (decision, docs/modification.md): the amount is the tooth deflection under the line load,
    ``C_a1 = C_a2 = F_t / (B c')`` with the single stiffness c' of ISO 6336-1 method B, over a
    short relief, half the long one, ``(eps_a - 1) p_bt / 2``. Amounts from
    ``w_t = F_t / B`` in N/mm (:func:`tangential_load_per_width`) or from m_n, and a relief height
    or a long relief (tip to single-contact point, :func:`long_relief_length`), as tabulated in
    docs/modification.md, "Recommended amounts"; the result's ``source`` states the formula used.

    Parameters
    ----------
    pair : GearPair
    torque : float
        Pinion torque T1 in N m (> 0).
    rule : str
        One of :data:`.RULES` (or an old name of one, :data:`.RENAMED_RULES`: FutureWarning).
    handbook_a, handbook_b : float
        Constants a (5..13) and b (0..8) of the handbook rule, micrometres.
    face_load_factor : float
        C_m of Dudley's rule (1..3).

    Returns
    -------
    ReliefRecommendation

    Raises
    ------
    InputError
        Unknown rule, constants out of range, a height below the base circle, or a long relief
        for a contact ratio >= 2.

    Examples
    --------
    >>> from gear_dyn.geometry import GearPair
    >>> import math
    >>> p = GearPair(23, 64, 6e-3, math.radians(22.5), 50e-3)
    >>> r = recommended_relief(p, 1474.4, "niemann")
    >>> round(r.amount_pinion * 1e6, 3), round(r.height_pinion * 1e3, 3)
    (54.0, 2.958)
    """
    rule = current_rule(rule)
    check_range("handbook_a", handbook_a, "um", low=5.0, high=13.0)
    check_range("handbook_b", handbook_b, "um", low=0.0, high=8.0)
    check_range("face_load_factor", face_load_factor, "", low=1.0, high=3.0)
    w_t = tangential_load_per_width(pair, torque)
    mn_mm = pair.module * 1e3
    um = 1e-6
    if rule in ("handbook", "wang2024"):
        a, b = (handbook_a, handbook_b) if rule == "handbook" else (9.0, 4.0)
        c1, c2 = (a + 0.04 * w_t) * um, (b + 0.04 * w_t) * um
        if rule == "handbook":
            source = (f"gear handbook: C_a1 = {a:g} + 0.04 w_t, C_a2 = {b:g} + 0.04 w_t um, "
                      "h = 0.4 m_n")
            h1 = h2 = 0.4 * pair.module
            l1, l2 = length_from_height(pair, 1, h1), length_from_height(pair, 2, h2)
        else:
            source = ("Wang et al. (2024) eq. 1: C_a,i = c_i + 0.04 F_t/B um (c1 = 9, c2 = 4), "
                      "long relief")
            l1 = l2 = long_relief_length(pair)
            h1, h2 = height_from_length(pair, 1, l1), height_from_length(pair, 2, l2)
    elif rule == "dudley":
        c1 = 4.1 * face_load_factor * w_t / 1e5 * 1e-3
        c2 = 6.5 * face_load_factor * w_t / 1e5 * 1e-3
        source = (f"Dudley: C_a1 = 4.1 C_m F_t/(1e5 B), C_a2 = 6.5 C_m F_t/(1e5 B) mm "
                  f"(F_t N, B mm, C_m = {face_load_factor:g}), long relief (assumed)")
        l1 = l2 = long_relief_length(pair)
        h1, h2 = height_from_length(pair, 1, l1), height_from_length(pair, 2, l2)
    elif rule == "kisssoft":
        from gear_dyn.stiffness.iso6336 import iso6336_stiffness

        # the tooth deflection under the line load, F_t / (B c'), on both gears
        c1 = c2 = torque / pair.r1 / pair.face_width / iso6336_stiffness(pair).c_single
        source = ("KISSsoft short relief (as defined here): C_a = F_t / (B c'), c' of ISO 6336-1 "
                  "method B, over half the long relief, (eps_a - 1) p_bt / 2")
        l1 = l2 = 0.5 * long_relief_length(pair)
        h1, h2 = height_from_length(pair, 1, l1), height_from_length(pair, 2, l2)
    elif rule == "niemann":
        c1 = c2 = 0.009 * mn_mm * 1e-3
        source = "Niemann: C_a = 0.009 m_n, h = 0.493 m_n"
        h1 = h2 = 0.493 * pair.module
        l1, l2 = length_from_height(pair, 1, h1), length_from_height(pair, 2, h2)
    else:
        raise InputError(f"relief rule = {rule!r}: valid values are {', '.join(RULES)}")
    return ReliefRecommendation(rule, source, c1, c2, h1, h2, l1, l2)


def recommended_reliefs(pair: GearPair, torque: float, **kwargs: float) -> tuple[
        ReliefRecommendation, ...]:
    """All rules of :data:`~gear_dyn.modification.relief.RULES` for one pair and torque
    (keywords: :func:`recommended_relief`)."""
    return tuple(recommended_relief(pair, torque, rule, **kwargs) for rule in RULES)
