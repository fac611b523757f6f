"""Test functions of the bifurcations of periodic orbits, and their location on a step of the
branch by bracketing (Seydel 2010, sec. 5.3 and 7.4; Kuznetsov 2004, sec. 10.2).

With the monodromy matrix M of the n-period map:

- ``fold_test = det(M - I)``: changes sign where a real multiplier passes +1 (a fold, where the
  branch turns back in the parameter and the tangent's parameter component changes sign too,
  or a branch point, where it does not);
- ``pd_test = det(M + I)``: changes sign where a multiplier passes -1 (period doubling).

The single-DOF model has no Neimark-Sacker point: two complex multipliers have the modulus
``sqrt(det M) = exp(-c n T / (2 m_e)) < 1`` (Liouville), so they never reach the unit circle.

A step of the branch from ``z_a`` along the tangent ``t_a`` is the one-parameter curve
``s -> corrector(z_a + s t_a)`` with the hyperplane ``t_a . (z - z_a - s t_a) = 0``; the
accepted step is its value at ``s = ds``, so the bracket ``[0, ds]`` holds both end values, and
a root finder on the test function along ``s`` (:func:`gear_dyn.solvers.contact_exact.
find_root`, Illinois false position with bisection safeguards) locates the point. Contact
pattern changes (grazing) are located by bisection on the pattern.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.continuation.orbit import orbit_shape
from gear_dyn.analysis.continuation.settings import ContinuationSettings
from gear_dyn.analysis.continuation.shooting import Evaluation, Shooting
from gear_dyn.solvers.contact_exact import find_root

FloatArray = NDArray[np.float64]


def fold_test(monodromy: FloatArray) -> float:
    """``det(M - I)``: zero where a multiplier is +1."""
    return float(np.linalg.det(monodromy - np.eye(monodromy.shape[0])))


def pd_test(monodromy: FloatArray) -> float:
    """``det(M + I)``: zero where a multiplier is -1."""
    return float(np.linalg.det(monodromy + np.eye(monodromy.shape[0])))


class StepCurve:
    """Points of one accepted step, ``s -> corrected point`` for ``0 <= s <= ds``."""

    def __init__(self, sh: Shooting, z_a: FloatArray, t_a: FloatArray,
                 settings: ContinuationSettings) -> None:
        self.sh, self.z_a, self.t_a, self.settings = sh, z_a, t_a, settings
        self.cache: dict[float, Evaluation] = {}
        self.dp_col: FloatArray | None = None  #: chord for the parameter column

    def at(self, s: float) -> Evaluation | None:
        """The corrected point at arclength ``s`` along the step (None: no convergence)."""
        hit = self.cache.get(s)
        if hit is not None:
            return hit
        zp = self.z_a + s * self.t_a
        out = self.sh.correct(zp, self.t_a, float(self.t_a @ zp), self.settings.newton_tol,
                              self.settings.max_newton, dp_col=self.dp_col, fresh=False)
        if out is None:
            return None
        self.cache[s] = out[0]
        return out[0]


def locate_root(curve: StepCurve, test: Callable[[FloatArray], float], ds: float,
                f_a: float, f_b: float) -> tuple[Evaluation, float, float] | None:
    """The point of the step where ``test(M)`` changes sign.

    Returns
    -------
    (Evaluation, s, parameter_error) or None
        ``parameter_error``: the parameter's change (SI) between the points at ``s`` and at
        ``s + locate_tol`` (the root finder's final bracket width). None when the corrector
        fails inside the bracket.
    """
    failed = False

    def f(s: float) -> float:
        nonlocal failed
        ev = curve.at(s)
        if ev is None:
            failed = True
            return 0.0  # ends the root finder; the result is discarded
        return test(ev.monodromy)

    s = find_root(f, 0.0, ds, f_a, f_b, curve.settings.locate_tol)
    ev = curve.at(s)
    if failed or ev is None:
        return None
    s2 = min(s + curve.settings.locate_tol, ds)
    ev2 = curve.at(s2)
    err = abs(curve.sh.param(ev2.z) - curve.sh.param(ev.z)) if ev2 is not None else np.nan
    return ev, s, float(err)


def locate_pattern_change(curve: StepCurve, ds: float, pattern_a: str
                          ) -> tuple[Evaluation, float, float, str] | None:
    """The first point of the step where the contact pattern differs from ``pattern_a``, by
    bisection on ``s`` to ``locate_tol``.

    Returns
    -------
    (Evaluation, s, parameter_error, new pattern) or None (the corrector failed)
    """
    sh = curve.sh

    def pattern(s: float) -> str | None:
        ev = curve.at(s)
        if ev is None:
            return None
        return orbit_shape(ev.model, sh.state(ev.z), sh.periods, sh.route, sh.rtol).pattern

    lo, hi = 0.0, ds
    new = pattern(hi)
    if new is None:
        return None
    while hi - lo > curve.settings.locate_tol:
        mid = 0.5 * (lo + hi)
        pm = pattern(mid)
        if pm is None:
            return None
        if pm == pattern_a:
            lo = mid
        else:
            hi, new = mid, pm
    ev_hi, ev_lo = curve.at(hi), curve.at(lo)
    if ev_hi is None or ev_lo is None:
        return None
    err = abs(sh.param(ev_hi.z) - sh.param(ev_lo.z))
    return ev_hi, hi, err, new
