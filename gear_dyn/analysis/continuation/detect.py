"""Test functions of the bifurcations of periodic orbits, and their location on a step of the
branch by bracketing (Seydel 2010, sec. 5.3 and 7.4; Kuznetsov 2004, sec. 10.2).

With the monodromy matrix M of the n-period map:

- ``fold_test = det(M - I)``: changes sign where a real multiplier passes +1 (a fold, where the
  branch turns back in the parameter and the tangent's parameter component changes sign too,
  or a branch point, where it does not);
- ``pd_test = det(M + I)``: changes sign where a multiplier passes -1 (period doubling);
- the grazing test (:mod:`.graze`): the signed distance of the orbit's extremum that touches a
  contact boundary where the contact pattern changes.

The single-DOF model has no Neimark-Sacker point: two complex multipliers have the modulus
``sqrt(det M) = exp(-c n T / (2 m_e)) < 1`` (Liouville), so they never reach the unit circle.

A step of the branch from ``z_a`` along the tangent ``t_a`` is the one-parameter curve
``s -> corrector(z_a + s t_a)`` with the hyperplane ``t_a . (z - z_a - s t_a) = 0``; the
accepted step is its value at ``s = ds``, so the bracket ``[0, ds]`` holds both end values.
Each trial point is a corrector solve started from the cubic Hermite interpolant between the
points already found on either side of it, with their tangents (from each point's own
Jacobian), so near the root it takes one or two maps; no point is computed twice.

The bracket is narrowed by :func:`bracket_root`: secant steps on the test function
(superlinear), regula falsi where the secant leaves the bracket, bisection where no test value
is known or the steps do not halve every second trial (Brent 1973, ch. 4, whose step "by at
least the tolerance" is kept: a trial next to an end is moved the tolerated width inside, so
the bracket itself collapses). It stops when the parameter is known to ``locate_tol``
relative: its largest change over the final bracket, from the quadratic through the bracket's
ends and the nearest third point. Near a fold the parameter is stationary along the branch, so
a bracket of width ``w`` in arclength fixes it to about ``p'' w^2 / 2``; at a period doubling
or a graze to about ``p' w``. A located point's stated ``parameter_error`` is that change plus
the parameter component of the Newton step its own residual would still take (the corrector
stops at ``newton.tolerance``). Which point of the final bracket is reported, and how the contact
pattern checks a graze: :func:`locate_root`, :func:`locate_pattern_change`.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.continuation.graze import graze_test
from gear_dyn.analysis.continuation.orbit import OrbitShape, orbit_shape
from gear_dyn.analysis.continuation.settings import ContinuationSettings
from gear_dyn.analysis.continuation.shooting import Evaluation, Shooting, solve3, tangent
from gear_dyn.errors import SolverError

FloatArray = NDArray[np.float64]
#: trial points of one location at most (bisection from a scaled step of 10 to 1e-14 needs 50)
MAX_TRIALS = 80
#: a trial next to a bracket end is moved this share of the tolerated width inside
NUDGE = 0.5
#: parameter values below this share of the start value count as this share in the
#: relative location tolerance
MIN_SCALE = 1e-3
#: a grazing test value within this share of the half gap is left to the contact pattern to
#: place on either side (the exact flow sees a spell down to rounding, ~1e-16 of it)
GRAZE_BAND = 1e-10


def fold_test(monodromy: FloatArray) -> float:
    """``det(M - I)``: zero where a multiplier is +1."""
    return float(np.linalg.det(monodromy - np.eye(monodromy.shape[0])))


def pd_test(monodromy: FloatArray) -> float:
    """``det(M + I)``: zero where a multiplier is -1."""
    return float(np.linalg.det(monodromy + np.eye(monodromy.shape[0])))


class StepCurve:
    """Points of one accepted step, ``s -> corrected point`` for ``0 <= s <= ds``.

    Parameters
    ----------
    sh : Shooting
    ev_a, ev_b : Evaluation
        The converged points at ``s = 0`` and ``s = ds``.
    t_a, t_b : ndarray (3,)
        Their unit tangents (``t_b`` oriented along ``t_a``).
    ds : float
        The step (scaled arclength along ``t_a``).
    settings : ContinuationSettings
    """

    def __init__(self, sh: Shooting, ev_a: Evaluation, ev_b: Evaluation, t_a: FloatArray,
                 t_b: FloatArray, ds: float, settings: ContinuationSettings) -> None:
        self.sh, self.t_a, self.ds, self.settings = sh, t_a, ds, settings
        self.z_a = ev_a.z
        self.cache: dict[float, Evaluation] = {0.0: ev_a, ds: ev_b}
        # dz/ds at the ends: s is the projection on t_a, so t / (t . t_a)
        self.slope = {0.0: t_a, ds: t_b / float(t_b @ t_a)}

    def _slope(self, x: float) -> FloatArray | None:
        """``dz/ds`` at the cached point ``x``: its tangent (from its own Jacobian at a trial
        point) over the tangent's component along ``t_a``; None where the Jacobian has no
        unique tangent (a branch point)."""
        if x not in self.slope:
            try:
                t = tangent(self.cache[x].jac)
            except SolverError:
                return None
            self.slope[x] = t / float(t @ self.t_a)
        return self.slope[x]

    def predict(self, s: float) -> FloatArray:
        """The cubic Hermite interpolant between the cached points on either side of ``s``
        (their values and slopes), at ``s``."""
        x0 = max(x for x in self.cache if x < s)
        x1 = min(x for x in self.cache if x > s)
        h = x1 - x0
        u = (s - x0) / h
        z0, z1 = self.cache[x0].z, self.cache[x1].z
        d0, d1 = self._slope(x0), self._slope(x1)
        if d0 is None or d1 is None:  # the chord: linear interpolation
            d0 = d1 = (z1 - z0) / h
        return np.asarray((2 * u**3 - 3 * u**2 + 1) * z0 + (u**3 - 2 * u**2 + u) * h * d0
                          + (-2 * u**3 + 3 * u**2) * z1 + (u**3 - u**2) * h * d1)

    def at(self, s: float) -> Evaluation | None:
        """The corrected point at arclength ``s`` along the step (None: no convergence).

        The corrector starts with the parameter column interpolated between the nearest
        points; where that fails, it is run again with the column by the central difference
        at every iterate (two more maps each)."""
        hit = self.cache.get(s)
        if hit is not None:
            return hit
        # the parameter column interpolated between the two nearest points (a chord, which
        # the corrector's secant updates refine)
        x0, x1 = sorted(self.cache, key=lambda x: abs(x - s))[:2]
        u = (s - x0) / (x1 - x0)
        col = (1 - u) * self.cache[x0].jac[:, 2] + u * self.cache[x1].jac[:, 2]
        out = self.sh.correct(self.predict(s), self.t_a, float(self.t_a @ self.z_a) + s,
                              self.settings.newton,
                              dp_col=col, fresh=False)
        if out is None:
            out = self.sh.correct(self.predict(s), self.t_a, float(self.t_a @ self.z_a) + s,
                                  self.settings.newton,
                                  fresh=False)
        if out is None:
            return None
        self.cache[s] = out[0]
        return out[0]

    def newton_error(self, s: float) -> float:
        """The parameter's first-order error (SI) at the cached point ``s``: the parameter
        component of the Newton step its residual would still take (the corrector stops
        once the residual is below ``newton.tolerance``)."""
        ev = self.cache[s]
        f = np.append(ev.g, float(self.t_a @ (ev.z - self.z_a)) - s)
        dz = solve3(np.vstack([ev.jac, self.t_a]), -f)
        if dz is None:
            return math.nan
        return self.sh.p_ref * abs(float(dz[2]))

    def located_error(self, lo: float, hi: float, r: float) -> float:
        """Stated error (SI) of the parameter of the point ``r`` located in ``[lo, hi]``:
        the bracket's (:meth:`parameter_error`) plus the corrector's (:meth:`newton_error`)."""
        return self.parameter_error(lo, hi, r) + self.newton_error(r)

    def p(self, s: float) -> float:
        """Scaled parameter of the cached point at ``s``."""
        return float(self.cache[s].z[2])

    def _quadratic(self, lo: float, hi: float) -> tuple[float, float, float, float]:
        """``(s0, q0, q1, q2)``: ``p(s) ~ q0 + q1 (s - s0) + q2 (s - s0)^2`` through the
        bracket ends and the nearest third point (with only the ends: their tangents)."""
        others = [x for x in self.cache if x not in (lo, hi)]
        pl, ph = self.p(lo), self.p(hi)
        d1 = (ph - pl) / (hi - lo)
        if others:
            x3 = min(others, key=lambda x: min(abs(x - lo), abs(x - hi)))
            d2 = ((self.p(x3) - pl) / (x3 - lo) - d1) / (x3 - hi)
        else:
            d2 = float(self.slope[hi][2] - self.slope[lo][2]) / (2 * (hi - lo))
        # Newton form p = pl + d1 (s - lo) + d2 (s - lo)(s - hi), about lo
        return lo, pl, d1 - d2 * (hi - lo), d2

    def parameter_error(self, lo: float, hi: float, r: float) -> float:
        """Largest change of the parameter (SI) over ``[lo, hi]`` from its value at ``r``,
        on the quadratic model of ``_quadratic()``."""
        s0, q0, q1, q2 = self._quadratic(lo, hi)

        def q(s: float) -> float:
            return q0 + q1 * (s - s0) + q2 * (s - s0) ** 2

        cands = [lo, hi]
        if q2 != 0.0:
            sv = s0 - q1 / (2 * q2)
            if lo < sv < hi:
                cands.append(sv)
        return self.sh.p_ref * max(abs(q(s) - q(r)) for s in cands)

    def target(self, r: float) -> float:
        """The tolerated parameter error at ``r`` (scaled): ``locate_tol`` relative, of at
        least a thousandth of the start value (a parameter through zero, e.g. a torque)."""
        return self.settings.locate_tol * max(abs(self.p(r)), MIN_SCALE)

    def tolerated_width(self, lo: float, hi: float, r: float) -> float:
        """Bracket width (scaled arclength) over which the parameter, on the quadratic model,
        changes by ``locate_tol`` relative at most, next to ``r``."""
        s0, _q0, q1, q2 = self._quadratic(lo, hi)
        d1 = abs(q1 + 2 * q2 * (r - s0))
        tol = self.target(r)
        return 2 * tol / (d1 + math.sqrt(d1 * d1 + 4 * abs(q2) * tol) + 1e-300)


    def fold_guess(self, lo: float, hi: float) -> float | None:
        """Where the parameter is stationary on ``[lo, hi]``: the root inside of the
        derivative of the cubic Hermite interpolant of ``p(s)`` through both ends' values and
        exact slopes (their tangents' ``dp/ds``; error O(w^3) in the bracket width w, against
        O(w^2) for a secant step on a test function). None where the slopes do not change
        sign (no fold: a branch point) or a tangent is undefined."""
        d_lo, d_hi = self._slope(lo), self._slope(hi)
        if d_lo is None or d_hi is None:
            return None
        h = hi - lo
        a0, a1 = float(d_lo[2]) * h, float(d_hi[2]) * h  # dp/du, u = (s - lo) / h
        if a0 == 0.0 or (a0 > 0.0) == (a1 > 0.0):
            return None
        dp = self.p(hi) - self.p(lo)
        # H'(u) = qa u^2 + qb u + qc (the Hermite basis' derivatives)
        qa, qb, qc = 3 * (a0 + a1) - 6 * dp, 6 * dp - 4 * a0 - 2 * a1, a0
        if qa == 0.0:
            roots = [-qc / qb] if qb != 0.0 else []
        else:
            disc = qb * qb - 4 * qa * qc
            if disc < 0.0:
                return None
            sq = math.copysign(math.sqrt(disc), qb)
            q = -0.5 * (qb + sq)  # the stable pair of roots (Press et al. 2007, sec. 5.6)
            roots = [q / qa] + ([qc / q] if q != 0.0 else [])
        inside = [u for u in roots if 0.0 < u < 1.0]
        return lo + h * inside[0] if len(inside) == 1 else None


Probe = Callable[[float], "tuple[bool, float | None] | None"]


def bracket_root(curve: StepCurve, probe: Probe, v_lo: float | None, v_hi: float | None,
                 report_hi: bool, guess: Callable[[float, float], float | None] | None = None
                 ) -> tuple[float, float, float]:
    """Narrow ``[0, ds]`` onto the point where ``probe`` changes side (module docstring).

    Parameters
    ----------
    curve : StepCurve
    probe : callable
        ``s -> (on_hi_side, test value or None)``, or None where the corrector fails.
    v_lo, v_hi : float or None
        Test values at the ends (opposite signs), or None (bisection).
    report_hi : bool
        Report the bracket's ``hi`` end (a graze: the first point with the new pattern);
        else the end with the smaller test value.
    guess : callable or None
        ``(lo, hi) -> s`` inside the bracket or None: the next trial where it gives one (a
        fold: :meth:`StepCurve.fold_guess`), in place of the secant step, with the same
        safeguards; None: the secant step.

    Returns
    -------
    (s, lo, hi)
        The reported point and the final bracket. Where a trial's corrector fails, the
        bracket reached so far (the point still lies in it: its stated error, from the
        bracket, is wider than ``locate_tol`` then, never a point dropped).
    """
    lo, hi = 0.0, curve.ds
    vals: dict[float, float | None] = {lo: v_lo, hi: v_hi}
    recent: list[float] = [lo, hi]
    steps: list[float] = []  # distance of each trial from the one before
    for _ in range(MAX_TRIALS):
        a, b = vals[lo], vals[hi]
        if report_hi or a is None or b is None:
            r = hi
        else:
            r = lo if abs(a) < abs(b) else hi
        if curve.parameter_error(lo, hi, r) <= curve.sh.p_ref * curve.target(r):
            return r, lo, hi
        w_ok = curve.tolerated_width(lo, hi, r)
        s = math.nan
        known = [x for x in recent if vals[x] is not None]
        g = guess(lo, hi) if guess is not None else None
        if g is not None:
            s = g
        elif len(known) >= 2:  # secant through the two latest values
            x0, x1 = known[-2], known[-1]
            f0, f1 = vals[x0], vals[x1]
            assert f0 is not None and f1 is not None
            if f1 != f0:
                s = x1 - f1 * (x1 - x0) / (f1 - f0)
        if not lo < s < hi and a is not None and b is not None and a != b:
            s = lo - a * (hi - lo) / (b - a)  # regula falsi on the bracket
        if not lo < s < hi or (len(steps) >= 2 and abs(s - recent[-1]) > 0.5 * steps[-2]):
            s = 0.5 * (lo + hi)  # no value, or the steps do not shrink fast enough: bisect
        if hi - lo <= 2 * w_ok:
            s = 0.5 * (lo + hi)
        else:  # at least NUDGE * w_ok from either end (Brent's step by the tolerance)
            s = min(max(s, lo + NUDGE * w_ok), hi - NUDGE * w_ok)
        res = probe(s)
        if res is None:
            return r, lo, hi
        side, val = res
        vals[s] = val
        steps.append(abs(s - recent[-1]))
        recent.append(s)
        if side:
            hi = s
        else:
            lo = s
    return (hi if report_hi else lo), lo, hi


def locate_root(curve: StepCurve, test: Callable[[FloatArray], float], f_a: float, f_b: float,
                guess: Callable[[float, float], float | None] | None = None
                ) -> tuple[Evaluation, float, float]:
    """The point of the step where ``test(M)`` changes sign: bracketed until the parameter
    is known to ``locate_tol`` relative, then the point at the secant root of the final
    bracket (near a fold the bracket is wide in arclength, and the multiplier at its ends
    still some way from +1; at the secant root the test is zero to second order in it).
    ``guess``: the trials' proposal in place of the secant step (:func:`bracket_root`; a fold:
    :meth:`StepCurve.fold_guess`), also for that final point.

    Returns
    -------
    (Evaluation, s, parameter_error)
        ``parameter_error``: the stated error (SI), the parameter's largest change over the
        final bracket and the corrector's error (:meth:`StepCurve.located_error`).
    """
    hi_positive = f_b > 0.0

    def probe(s: float) -> tuple[bool, float | None] | None:
        ev = curve.at(s)
        if ev is None:
            return None
        v = test(ev.monodromy)
        return (v > 0.0) == hi_positive, v

    s, lo, hi = bracket_root(curve, probe, f_a, f_b, report_hi=False, guess=guess)
    f_lo, f_hi = test(curve.cache[lo].monodromy), test(curve.cache[hi].monodromy)
    s_root = guess(lo, hi) if guess is not None else None
    if s_root is None and f_lo != f_hi:  # the point itself at the secant root inside
        s_root = lo - f_lo * (hi - lo) / (f_hi - f_lo)
    if s_root is not None and lo < s_root < hi and curve.at(s_root) is not None:
        s = s_root
    return curve.cache[s], s, curve.located_error(lo, hi, s)


def locate_pattern_change(curve: StepCurve, pattern_a: str, pattern_b: str
                          ) -> tuple[Evaluation, float, float, OrbitShape]:
    """The first point of the step where the contact pattern differs from ``pattern_a``.

    With the grazing test (:mod:`.graze`) of the step's ends, the bracket is narrowed on its
    sign (on the pattern where it is within :data:`GRAZE_BAND` of the half gap), and the
    final bracket's ends are checked on the contact pattern (``pattern_a`` at the lower end,
    another at the upper); where the test is not available, or the check fails (a second
    contact change inside the step, or a pattern sampled coarser than the test on the
    variational route), the bracket is bisected on the pattern.

    Returns
    -------
    (Evaluation, s, parameter_error, OrbitShape)
        The shape (with the new pattern) of the located point.
    """
    sh = curve.sh
    ends = {0.0: pattern_a, curve.ds: pattern_b}
    shapes: dict[float, OrbitShape] = {}

    def shape(s: float) -> OrbitShape:
        if s not in shapes:
            ev = curve.cache[s]
            shapes[s] = orbit_shape(ev.model, sh.state(ev.z), sh.periods, sh.route, sh.rtol,
                                    ev.walked)
        return shapes[s]

    def pattern(s: float) -> str:
        return ends[s] if s in ends else shape(s).pattern

    def on_pattern(s: float) -> tuple[bool, float | None] | None:
        if curve.at(s) is None:
            return None
        return pattern(s) != pattern_a, None

    hit: tuple[float, float, float] | None = None
    ev_a, ev_b = curve.cache[0.0], curve.cache[curve.ds]
    made = graze_test(ev_a.model, sh.state(ev_a.z), ev_b.model, sh.state(ev_b.z), sh.periods,
                      sh.route, sh.rtol, ev_a.walked, ev_b.walked)
    if made is not None:
        test, v_a, v_b = made
        band = abs(test.level)

        def on_test(s: float) -> tuple[bool, float | None] | None:
            nonlocal test
            ev = curve.at(s)
            if ev is None:
                return None
            got = test.margin(ev.model, sh.state(ev.z), sh.periods, sh.route, sh.rtol,
                              ev.walked)
            if got is None:
                return pattern(s) != pattern_a, None
            val, test = got
            if abs(val) <= GRAZE_BAND * band:  # the pattern's own resolution: it decides
                return pattern(s) != pattern_a, val
            return (val > 0.0) == (v_b > 0.0), val

        hit = bracket_root(curve, on_test, v_a, v_b, report_hi=True)
        if pattern(hit[1]) != pattern_a or pattern(hit[2]) == pattern_a:
            hit = None
    if hit is None:
        hit = bracket_root(curve, on_pattern, None, None, report_hi=True)
    s, lo, hi = hit
    return curve.cache[s], s, curve.located_error(lo, hi, s), shape(s)
