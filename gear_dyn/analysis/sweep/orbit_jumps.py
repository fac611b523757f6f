"""Jumps of a sweep found from its periodic orbits, not from a threshold on RMS.

Between two neighbouring speeds of one sweep direction the response jumps where the periodic
orbit at the first speed does not continue to the second one: the orbit the sweep found at speed
``i`` is followed towards speed ``i + 1`` by pseudo-arclength continuation
(:func:`gear_dyn.analysis.continuation.continue_orbits`), for the candidate pairs of
:func:`candidates` only; where either speed has no orbit, the RMS DTE test stays as a labelled
fallback (``rms_fallback``, :data:`FALLBACK_REL`). docs/sweep.md, "How jumps are found", gives
the rules and the kinds of jump (:class:`~gear_dyn.analysis.sweep.jump.Jump`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from typing import cast

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.continuation import (
    Branch,
    ContinuationSettings,
    OrbitPoint,
    continue_orbits,
)
from gear_dyn.analysis.continuation.orbit import map_only, orbit_shape, resolve_route
from gear_dyn.analysis.sweep.jump import Jump
from gear_dyn.analysis.sweep.types import SweepCurve
from gear_dyn.errors import SolverError
from gear_dyn.models.base import MeshModel, Model

FloatArray = NDArray[np.float64]

#: a pair is continued when its orbit change exceeds this multiple of the smaller neighbouring one
SCREEN_RATIO = 2.0
#: relative RMS DTE change reported as a jump where no orbit exists (the former threshold)
FALLBACK_REL = 0.3
#: two orbits at one speed are the same when their states agree to this share of the state
#: scale (the sweep closes its orbits to 100 rtol = 1e-6 of the scale at its default rtol 1e-8,
#: the continuation to 1e-10; distinct coexisting orbits differ by a sizeable share of it)
SAME_ORBIT = 1e-4
#: relative error to which a fold's speed is located (the continuation's default, 1e-10,
#: costs a trial or two more for digits no jump needs)
LOCATE_TOL = 1e-9
#: most continuation points spent on one pair (a fold is met within a few)
MAX_POINTS = 60


def spell_counts(pattern: str) -> tuple[int, int]:
    """Separations and back-flank contacts per period in a contact pattern (``DGBGD``: one
    of each; the pattern is cyclic, so a spell running over the period's end counts once)."""
    if len(pattern) > 1 and pattern[0] == pattern[-1]:
        pattern = pattern[:-1]
    return pattern.count("G"), pattern.count("B")


def _features(curve: SweepCurve, scale: FloatArray) -> FloatArray:
    """Per speed: the orbit state in units of the state scale and the contact shares."""
    x = curve.state / scale
    return np.column_stack([x, np.nan_to_num(curve.separation), np.nan_to_num(curve.backside)])


def candidates(curve: SweepCurve, scale: FloatArray) -> list[int]:
    """Indices ``i`` of the pairs (i, i + 1) with an orbit at both speeds that need the
    continuation check: an orbit change (``_features()``) above :data:`SCREEN_RATIO` times
    the smaller neighbouring one, status ``settled``, separation or back contact starting or
    ending, or a change of the orbit's mesh periods."""
    n = curve.speed.size
    orbit = curve.orbit_periods > 0
    f = _features(curve, scale)
    d = np.full(max(n - 1, 0), np.nan)
    both = orbit[:-1] & orbit[1:]
    d[both] = np.linalg.norm(f[1:][both] - f[:-1][both], axis=1)
    sep = np.nan_to_num(curve.separation) > 0
    back = np.nan_to_num(curve.backside) > 0
    out = []
    for i in np.flatnonzero(both):
        near = [d[j] for j in (i - 1, i + 1) if 0 <= j < d.size and np.isfinite(d[j])]
        if (curve.status[i + 1] == "settled" or sep[i] != sep[i + 1] or back[i] != back[i + 1]
                or curve.orbit_periods[i] != curve.orbit_periods[i + 1] or not near
                or d[i] > SCREEN_RATIO * min(near)):
            out.append(int(i))
    return out


def _reached(branch: Branch, speed: float) -> int | None:
    """Index of the branch point at ``speed`` (its end point there), or None."""
    at = np.flatnonzero(np.abs(branch.array("parameter") - speed) <= 1e-9 * abs(speed))
    return int(at[-1]) if at.size else None


def check_pair(curve: SweepCurve, i: int, factory: Callable[[float], Model], rtol: float
               ) -> Jump | None:
    """The jump between speeds ``i`` and ``i + 1`` of ``curve`` (both with an orbit), or None
    where the orbit at ``i`` continues to the one the sweep found at ``i + 1``.

    ``factory`` is the sweep's ``speed -> model``; ``rtol`` the sweep's solver tolerance (for
    the contact pattern of the sweep's orbit on the variational route).
    """
    s0, s1 = float(curve.speed[i]), float(curve.speed[i + 1])
    n0, n1 = int(curve.orbit_periods[i]), int(curve.orbit_periods[i + 1])
    span = abs(s1 - s0) / s0
    model1 = cast(MeshModel, factory(s1))
    route = resolve_route(model1, "auto")
    settings = ContinuationSettings(step=min(0.02, span / 4), step_max=2.0,
                                    max_points=MAX_POINTS, locate_tol=LOCATE_TOL)
    if route == "variational":
        # the sweep's accuracy, not more: the maps are integrated to rtol, so the corrector
        # closes the orbits to 100 rtol (as the sweep's shooting does) and a fold is known to
        # about as much
        tol = min(max(rtol, 1e-13), 1e-6)
        settings = replace(settings, rtol=tol,
                           newton=replace(settings.newton, tolerance=min(100 * tol, 1e-4)),
                           locate_tol=min(100 * tol, 1e-4))

    def jump(kind: str, fold: float = math.nan, before: str = "", after: str = "") -> Jump:
        return Jump(kind, s0, s1, fold, float(curve.rms_dte[i]), float(curve.rms_dte[i + 1]),
                    float(curve.separation[i]), float(curve.separation[i + 1]), before, after)

    def pattern_at_1() -> str:
        return orbit_shape(model1, curve.state[i + 1], n1, route, rtol).pattern

    def follow(start: float, y: FloatArray, detect: bool) -> Branch:
        return continue_orbits(factory, start, s1, periods=n0, y_guess=y,
                               settings=replace(settings, detect=detect), doublings=0)

    try:
        br = follow(s0, curve.state[i], detect=False)  # cheap: no bifurcation located
    except SolverError:
        return jump("unresolved", after=pattern_at_1())
    before = br.points[0].pattern
    tp = br.array("tangent_p")
    k = _reached(br, s1)
    turn = np.flatnonzero(tp[1:] * tp[0] < 0.0)
    if k is not None and (turn.size == 0 or turn[0] + 1 >= k):
        return _arrival(curve, i, br.points[k], model1, n0, n1, jump, before, pattern_at_1,
                        lambda y: map_only(model1, y, 1, route, rtol))
    p = br.array("parameter")
    far = float(np.max(p) if s1 > s0 else np.min(p))  # the branch's turning point
    if turn.size == 0 and abs(p[-1] - s0) > 1e-9 * s0:
        return jump("unresolved", before=before, after=pattern_at_1())
    # the branch turns back before s1: locate the fold from the last point before the turn
    j = int(turn[0]) if turn.size else int(np.argmax(p) if s1 > s0 else np.argmin(p))
    a = br.points[max(j - 1, 0)]
    try:
        folds = follow(a.parameter, a.state, detect=True).of_kind("fold") if a.parameter != s1 \
            else []
    except SolverError:
        folds = []
    # no smooth fold located: the branch turned at a corner (a grazing point)
    return jump("fold", folds[0].parameter if folds else far, before, pattern_at_1())


def same_orbit(a: FloatArray, b: FloatArray, periods: int, one_period: Callable[[FloatArray],
               FloatArray], scale: FloatArray) -> bool:
    """Whether the period-``periods`` orbits through the states ``a`` and ``b`` (at t = 0) are
    one orbit: ``a`` agrees to :data:`SAME_ORBIT` of ``scale`` with ``b`` or with one of its
    images after 1..n-1 mesh periods (``one_period``: the one-mesh-period map). A period-n
    orbit passes t = 0 (mod T) at n states; a continuation and a sweep may meet it at
    different ones of them (its phase modulo n mesh periods)."""
    y = np.asarray(b, dtype=float)
    for k in range(periods):
        if k:
            y = one_period(y)
        if float(np.max(np.abs(a - y) / scale)) <= SAME_ORBIT:
            return True
    return False


def _arrival(curve: SweepCurve, i: int, end: OrbitPoint, model1: MeshModel, n0: int, n1: int,
             jump: Callable[..., Jump], before: str, pattern_at_1: Callable[[], str],
             one_period: Callable[[FloatArray], FloatArray]) -> Jump | None:
    """The orbit at ``i`` continued to ``end`` at speed ``i + 1`` without turning back: a jump
    only where the sweep found another orbit there (compared modulo its phase,
    :func:`same_orbit`; ``one_period`` is the one-mesh-period map at ``i + 1``)."""
    if n0 != n1:
        # the period-n orbit reached i + 1: the sweep left it only where it lost stability
        # (a period doubling: the response follows the new orbit continuously)
        return jump("branch", before=before, after=pattern_at_1()) if end.stable else None
    scale = np.asarray(model1.state_scale, dtype=float)
    try:
        if same_orbit(end.state, curve.state[i + 1], n1, one_period, scale):
            return None
    except SolverError:
        pass  # the other phases not computed: compared at t = 0 only (above, k = 0)
    after = pattern_at_1()
    kind = "contact_pattern" if spell_counts(end.pattern) != spell_counts(after) else "branch"
    return jump(kind, before=before, after=after)


def _fallback(curve: SweepCurve, i: int) -> Jump | None:
    a, b = float(curve.rms_dte[i]), float(curve.rms_dte[i + 1])
    if math.isfinite(a) and math.isfinite(b) and abs(b - a) > FALLBACK_REL * max(abs(a), abs(b)):
        return Jump("rms_fallback", float(curve.speed[i]), float(curve.speed[i + 1]), math.nan,
                    a, b, float(curve.separation[i]), float(curve.separation[i + 1]))
    return None


def find_jumps(curve: SweepCurve, factory: Callable[[float], Model] | None,
               rtol: float = 1e-8, *, orbits: bool = True) -> tuple[Jump, ...]:
    """The jumps of one sweep direction, in sweep order.

    A linear model (``is_linear``: no backlash, no friction) has none, and nothing is continued
    or compared for it: its equation of motion is affine in the state, so at each speed where
    it is Floquet-stable its periodic response is unique (the fixed point of an affine
    one-period map whose multipliers lie inside the unit circle) and depends continuously on
    the speed; where it is unstable there is no steady response to jump to.

    Parameters
    ----------
    curve : SweepCurve
        One direction of a sweep.
    factory : callable or None
        The sweep's ``speed -> Model`` (speed in rad/s). None, or a model that is not the
        single-DOF mesh model: only the RMS fallback (no orbits to continue).
    rtol : float
        The sweep's solver tolerance.
    orbits : bool
        False: the curve has no orbits to continue (the transient method); only the RMS
        fallback, for a nonlinear model.

    Returns
    -------
    tuple of Jump

    Raises
    ------
    SolverError
        An integration failed while sampling an orbit's contact pattern.
    """
    n = curve.speed.size
    if n < 2:
        return ()
    orbit = curve.orbit_periods > 0
    model0 = factory(float(curve.speed[0])) if factory is not None else None
    if model0 is not None and model0.is_linear:
        return ()  # one periodic response per speed: no jump to look for
    mesh = orbits and isinstance(model0, MeshModel) and model0.mesh_periodic
    found: dict[int, Jump | None] = {}
    if mesh:
        assert model0 is not None and factory is not None
        scale = np.asarray(model0.state_scale, dtype=float)
        for i in candidates(curve, scale):
            found[i] = check_pair(curve, i, factory, rtol)
    for i in range(n - 1):
        if not (orbit[i] and orbit[i + 1]) or not mesh:
            found[i] = _fallback(curve, i)
    return tuple(j for _i, j in sorted(found.items()) if j is not None)
