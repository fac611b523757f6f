"""Pseudo-arclength continuation of periodic orbits (Keller 1977; Seydel 2010, ch. 4;
Doedel's AUTO notes): tangent predictor, Newton corrector on the shooting equations with the
arclength condition, adaptive steps, and bifurcations detected and located on every step.

Step control by the knobs of :class:`.settings.ContinuationSettings` (docs/response.md, "Step
control"): the turn limit takes the branch round a fold in several steps, so no step reaches
past a fold onto another part of the branch, and the sign change of the tangent's parameter
component shows between two neighbouring points (where :mod:`.detect` locates it). Contact
changes need no special treatment (docs/response.md, "Contact changes").
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import cast

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.continuation.branch import Bifurcation, Branch, OrbitPoint
from gear_dyn.analysis.continuation.detect import (
    StepCurve,
    fold_test,
    locate_pattern_change,
    locate_root,
    pd_test,
)
from gear_dyn.analysis.continuation.family import PARAMETERS
from gear_dyn.analysis.continuation.orbit import OrbitShape, map_only, resolve_route
from gear_dyn.analysis.continuation.points import make_point
from gear_dyn.analysis.continuation.settings import ContinuationSettings
from gear_dyn.analysis.continuation.shooting import Evaluation, Shooting, tangent
from gear_dyn.analysis.continuation.switch import switch_at_period_doubling
from gear_dyn.analysis.stability import shoot
from gear_dyn.analysis.threads import blas_limited
from gear_dyn.errors import InputError, SolverError, check_range
from gear_dyn.models.base import MeshModel, Model

FloatArray = NDArray[np.float64]
#: mesh periods integrated to settle onto an attracting orbit where shooting from the guess fails
SETTLE_PERIODS = 400
#: a period-2n point closer than this (scaled) to closing after n periods lies on the period-n
#: branch: the period-2n branch has reached it (it also stops where it passes through it)
MERGE_TOL = 1e-6


@blas_limited
def continue_orbits(family: Callable[[float], Model], start: float, stop: float, *,
                    periods: int = 1, y_guess: FloatArray | None = None,
                    parameter: str = "speed", route: str = "auto",
                    settings: ContinuationSettings | None = None,
                    doublings: int = 1) -> Branch:
    """Follow the branch of period-n orbits of ``family`` from ``start`` towards ``stop``.

    Parameters
    ----------
    family : callable
        ``value -> MeshModel`` (single-DOF mesh model, SI value of the parameter): e.g.
        :func:`~gear_dyn.analysis.continuation.family.sdof_family` or the scene layer's
        ``SceneModels.of(scene)`` (speed in rad/s).
    start, stop : float
        The parameter range, SI (rad/s, N m, -, m). The branch starts at ``start`` and ends
        where it leaves ``[min(start, stop), max(start, stop)]`` (after any folds).
    periods : int
        Mesh periods n of the orbits (period-n, 1..16).
    y_guess : ndarray or None
        State [m, m/s] to shoot from at ``start``; None: the static deflection. Where shooting
        from it fails, the response is integrated for :data:`.SETTLE_PERIODS` mesh periods
        first (the attracting orbit).
    parameter : str
        Name of the parameter (for the result; ``speed``, ``torque``, ``damping_ratio``,
        ``backlash`` carry their SI unit).
    route : str
        ``auto``, ``exact`` or ``variational`` (:func:`.orbit.resolve_route`).
    settings : ContinuationSettings or None
        Step control, tolerances, detection.
    doublings : int
        How many levels of period doubling to switch at (0: none; 1: period-2n branches from
        this branch's period doublings; 2: also period-4n ...), 0..4.

    Returns
    -------
    Branch
        With its located folds, period doublings, branch points and grazing points, and the
        switched period-2n branches as ``children``.

    Raises
    ------
    InputError
        Bad range, periods, route or doublings; a family whose models are not single-DOF
        mesh models.
    SolverError
        No periodic orbit found at ``start``.

    See Also
    --------
    :func:`~gear_dyn.analysis.continuation.family.sdof_family` : The family of a single-DOF model.
    :class:`~gear_dyn.analysis.continuation.settings.ContinuationSettings`
        Step control, tolerances, detection.
    :class:`~gear_dyn.analysis.continuation.branch.Branch` : The result.
    :func:`~gear_dyn.analysis.continuation.fold_curve.fold_map` : The folds followed over torque.

    Examples
    --------
    >>> from gear_dyn import SDOFModel, rectangular_stiffness, sdof_family
    >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
    ...               backlash=1e-3)
    >>> branch = continue_orbits(sdof_family(m, "speed", teeth=20), 43.0, 44.5)
    >>> [(b.kind, round(b.point.parameter, 2)) for b in branch.bifurcations]  # rad/s
    [('grazing', 43.69), ('fold', 43.96)]
    """
    check_range("start", start, PARAMETERS.get(parameter, ""))
    check_range("stop", stop, PARAMETERS.get(parameter, ""))
    if start == stop:
        raise InputError(f"start = stop = {start:.6g}: the range is empty")
    check_range("periods", periods, "", low=1, high=16)
    check_range("doublings", doublings, "", low=0, high=4)
    settings = settings or ContinuationSettings()
    model0 = family(start)
    if not (isinstance(model0, MeshModel) and model0.mesh_periodic):
        raise InputError(f"continuation needs the single-DOF mesh model (sdof); got "
                         f"{type(model0).__name__}")
    rroute = resolve_route(model0, route)
    p_ref = abs(start) if start != 0.0 else abs(stop)
    mesh_family = cast(Callable[[float], MeshModel], family)  # checked on model0 above
    sh = Shooting(mesh_family, periods, rroute, model0.state_scale, p_ref, settings.rtol,
                  settings.fd_step)
    y0 = start_orbit(model0, periods, rroute, settings, y_guess)
    e_p = np.array([0.0, 0.0, 1.0])
    out = sh.correct(sh.scaled(y0, start), e_p, start / p_ref, settings.newton)
    if out is None:
        raise SolverError(f"no period-{periods} orbit converged at {parameter} = {start:.6g}")
    ev0, _it = out
    t0 = tangent(ev0.jac)
    if t0[2] * (stop - start) < 0:
        t0 = -t0
    window = (min(start, stop), max(start, stop))
    return follow(sh, ev0, t0, window, settings, parameter, doublings)


def start_orbit(model: MeshModel, periods: int, route: str, settings: ContinuationSettings,
                y_guess: FloatArray | None) -> FloatArray:
    """A state on a period-n orbit of ``model``: shooting from the guess, else after settling.

    Raises
    ------
    SolverError
        No orbit found.
    """
    guess = model.initial_state() if y_guess is None else np.asarray(y_guess, dtype=float)
    sol = shoot(model, guess, settings.rtol, settings.start_newton.max_iter, periods, route,
                settings.start_newton.tolerance)
    if sol.converged:
        return np.asarray(sol.y0, dtype=float)
    y = guess
    for _ in range(SETTLE_PERIODS // periods):
        y = map_only(model, y, periods, route, settings.rtol)
    sol = shoot(model, y, settings.rtol, settings.start_newton.max_iter, periods, route,
                settings.start_newton.tolerance)
    if not sol.converged:
        raise SolverError(f"no period-{periods} orbit found (shooting from the guess and after "
                          f"{SETTLE_PERIODS} mesh periods); give y_guess or another start")
    return np.asarray(sol.y0, dtype=float)


def follow(sh: Shooting, ev0: Evaluation, t0: FloatArray, window: tuple[float, float],
           settings: ContinuationSettings, parameter: str, doublings: int,
           parent: Shooting | None = None) -> Branch:
    """The continuation loop from the converged ``ev0`` along the unit tangent ``t0``.

    ``parent``: the period-n problem of a period-2n branch (its merging back is a stop).
    """
    lo, hi = window
    ev, t = ev0, t0
    points = [make_point(sh, ev, settings, 0.0, float(t[2]), 0)]
    bifs: list[Bifurcation] = []
    ds, s_total = settings.step, 0.0
    z_first = ev0.z
    d_prev = parent.residual_only(ev0.z) if parent is not None else np.zeros(2)
    stop_reason = (f"max_points ({settings.max_points}) reached: raise it with --max-points "
                   "(gear-dyn response), ContinuationSettings(max_points=N) in Python")
    prev: tuple[FloatArray, FloatArray] | None = None  # the point before ev and its tangent
    while len(points) < settings.max_points:
        zp = predict(ev.z, t, prev, ds)
        out = sh.correct(zp, t, float(t @ zp), settings.newton,
                         dp_col=ev.jac[:, 2])
        t_b: FloatArray | None = None
        if out is not None:
            try:
                t_b = tangent(out[0].jac)
            except SolverError:
                t_b = None
        if out is not None and t_b is not None:
            if float(t_b @ t) < 0.0:
                t_b = -t_b
            turn = math.acos(min(1.0, abs(float(t_b @ t))))
        if out is None or t_b is None or turn > settings.max_turn:
            ds *= 0.5
            if ds < settings.step_min:
                stop_reason = (f"the step fell below step_min = {settings.step_min:g} at "
                               f"{parameter} = {sh.param(ev.z):.10g}")
                break
            continue
        ev_b, it = out
        p_b = sh.param(ev_b.z)
        point_b = make_point(sh, ev_b, settings, s_total + ds, float(t_b[2]), it)
        if settings.detect:
            bifs.extend(detect_step(sh, ev, t, ev_b, t_b, ds, points[-1], point_b, settings,
                                    s_total))
        if p_b < lo or p_b > hi:
            end = _end_point(sh, ev, ev_b, hi if p_b > hi else lo, settings)
            if end is not None:
                points.append(end)
            stop_reason = f"left the range at {parameter} = {hi if p_b > hi else lo:.10g}"
            break
        points.append(point_b)
        s_total += ds
        prev = (ev.z, t) if sh.exact_column else None
        ev, t = ev_b, t_b
        if float(np.linalg.norm(ev.z - z_first)) < 0.5 * ds and len(points) > 3:
            stop_reason = f"closed loop: back at its start after {len(points)} points"
            break
        if parent is not None:
            # on a period-2n branch, d = P_n(y) - y (scaled) is zero only on the period-n
            # orbit and flips sign where the branch passes through it (a period doubling of
            # the period-n branch; beyond it lie the same orbits shifted by n mesh periods)
            d = parent.residual_only(ev.z)
            if float(np.max(np.abs(d))) < MERGE_TOL or float(d @ d_prev) < 0.0:
                stop_reason = (f"reached the period-{parent.periods} branch at "
                               f"{parameter} = {sh.param(ev.z):.10g}")
                break
            d_prev = d
        if it <= settings.target_newton and turn < 0.5 * settings.max_turn:
            ds = min(ds * settings.grow, settings.step_max)
        elif it > settings.target_newton + 2:
            ds = max(ds / settings.grow, settings.step_min)
    # a point whose stated error reaches into the range is kept (a bracket that its trials
    # could not narrow is reported at an end, which may lie just outside)
    bifs = [b for b in bifs if lo - b.parameter_error <= b.parameter <= hi + b.parameter_error]
    children: list[Branch] = []
    if doublings > 0:
        for b in bifs:
            if b.kind != "period_doubling" or any(_ends_at(c, b) for c in children):
                continue  # a period-2n branch from an earlier doubling already ended here
            children.append(switch_at_period_doubling(sh, b, window, settings, parameter,
                                                       doublings - 1, follow))
    fn = ev0.model.natural_frequency
    return Branch(parameter, PARAMETERS.get(parameter, ""), tuple(points), tuple(bifs),
                  tuple(children), sh.route, stop_reason, sh.n_maps,
                  math.nan if fn is None else float(fn))


def predict(z: FloatArray, t: FloatArray, prev: tuple[FloatArray, FloatArray] | None,
            ds: float) -> FloatArray:
    """The predictor of the step ``ds`` from the point ``z`` with unit tangent ``t``.

    With ``prev`` (the point before and its unit tangent, both exact: the exact parameter
    column): the cubic Hermite interpolant through both points and tangents, the curve
    parametrised by the chord length ``h`` between them, extrapolated to ``ds`` past ``z``
    (error O(h^4) where ``ds ~ h``, against O(ds^2) for the tangent alone; Allgower & Georg
    2003, on higher-order predictors). Without: the tangent, ``z + ds t``.
    """
    if prev is None:
        return np.asarray(z + ds * t)
    z0, t0 = prev
    h = float(np.linalg.norm(z - z0))
    if h == 0.0 or not math.isfinite(h):
        return np.asarray(z + ds * t)
    u = 1.0 + ds / h  # Hermite basis on [0, 1] from z0 (u = 0) to z (u = 1), beyond it
    h00, h10 = 2 * u**3 - 3 * u**2 + 1, u**3 - 2 * u**2 + u
    h01, h11 = -2 * u**3 + 3 * u**2, u**3 - u**2
    return np.asarray(h00 * z0 + h10 * h * t0 + h01 * z + h11 * h * t)


def _ends_at(child: Branch, pd: Bifurcation) -> bool:
    """True when ``child`` stopped by passing through the period-n branch at ``pd``: the
    doubling's parameter lies between the child's last two points (1e-9 relative slack)."""
    if len(child.points) < 2 or not child.stop_reason.startswith("reached"):
        return False
    a, b = child.points[-2].parameter, child.points[-1].parameter
    slack = 1e-9 * abs(pd.parameter)
    return min(a, b) - slack <= pd.parameter <= max(a, b) + slack


def _end_point(sh: Shooting, ev_a: Evaluation, ev_b: Evaluation, bound: float,
               settings: ContinuationSettings) -> OrbitPoint | None:
    """The orbit at the range's end ``bound``, between the points ``a`` and ``b``."""
    p_a, p_b = sh.param(ev_a.z), sh.param(ev_b.z)
    frac = (bound - p_a) / (p_b - p_a)
    z = ev_a.z + frac * (ev_b.z - ev_a.z)
    out = sh.correct(z, np.array([0.0, 0.0, 1.0]), bound / sh.p_ref, settings.newton)
    if out is None:
        return None
    return make_point(sh, out[0], settings, float("nan"), float("nan"), out[1])


#: test-function values below this are rounding, without a sign: a linear stretch of a branch
#: (full contact) at a period doubling is a whole line of period-2n orbits, on which
#: ``det(M^2 - I)`` is zero up to the corrector's tolerance
TEST_NOISE = 1e-8


def _sign_change(a: float, b: float) -> bool:
    if min(abs(a), abs(b)) <= TEST_NOISE:
        return False
    return (a < 0.0) != (b < 0.0)


def detect_step(sh: Shooting, ev_a: Evaluation, t_a: FloatArray, ev_b: Evaluation,
                t_b: FloatArray, ds: float, pt_a: OrbitPoint, pt_b: OrbitPoint,
                settings: ContinuationSettings, s0: float) -> list[Bifurcation]:
    """Folds, period doublings, branch points and grazing between two accepted points,
    located on the step (:mod:`.detect`), in order along the branch."""
    curve = StepCurve(sh, ev_a, ev_b, t_a, t_b, ds, settings)
    found: list[tuple[float, Bifurcation]] = []
    stab = {True: "stable", False: "unstable"}

    def point(ev: Evaluation, s: float, shape: OrbitShape | None = None) -> OrbitPoint:
        # the tangent from the point's own parameter column: interpolated between its
        # neighbours on the step and refined by the corrector's secant updates
        tt = tangent(ev.jac)
        return make_point(sh, ev, settings, s0 + s, float(tt[2] if tt @ t_a >= 0 else -tt[2]),
                          shape=shape)

    for test, kinds in ((fold_test, ("fold", "branch_point")),
                        (pd_test, ("period_doubling", "period_doubling"))):
        fa, fb = test(ev_a.monodromy), test(ev_b.monodromy)
        if not _sign_change(fa, fb):
            continue
        turns = t_a[2] * t_b[2] < 0.0
        # a fold (the speed turns back): trials at the stationary point of the Hermite
        # interpolant of the speed, from the exact tangents (with an exact speed column)
        guess = curve.fold_guess if turns and test is fold_test and sh.exact_column else None
        ev, s, err = locate_root(curve, test, fa, fb, guess)
        kind = kinds[0] if turns else kinds[1]
        found.append((s, Bifurcation(kind, point(ev, s), err, stab[pt_a.stable],
                                     stab[pt_b.stable])))
    if pt_a.pattern != pt_b.pattern:
        ev, s, err, shape = locate_pattern_change(curve, pt_a.pattern, pt_b.pattern)
        found.append((s, Bifurcation("grazing", point(ev, s, shape), err, pt_a.pattern,
                                     shape.pattern)))
    return [b for _s, b in sorted(found, key=lambda x: x[0])]
