"""Continuation of periodic orbits (gear_dyn.analysis.continuation) against independent checks:
the closed-form linear response and its grazing speed, Liouville's formula, folds from the
minimally extended system and from natural-parameter shooting, period doubling against the
linear model's Floquet boundary and the period-2 orbit's own multipliers.

The test model: backlash_oscillator.py (m = 1 kg, rectangular mesh stiffness, half gap 1 mm, 1 mm
static deflection, 20 pinion teeth); speeds as f_m / f_n.
"""

from __future__ import annotations

import json
import math
from functools import partial

import numpy as np
import pytest
from backlash_oscillator import TEETH, WN, B, oscillator
from extended_system import solve_extended
from scipy.optimize import brentq

from gear_dyn import FourierStiffness, InputError, SDOFModel
from gear_dyn.analysis.continuation import (
    ContinuationSettings,
    continue_orbits,
    fold_test,
    liouville_residual,
    sdof_family,
)
from gear_dyn.analysis.newton import NewtonSettings
from gear_dyn.analysis.stability import one_period_map, shoot
from gear_dyn.excitation import HarmonicSignal
from gear_dyn.solvers.contact_exact import DRIVE, flow, flow_with_sensitivity


def _kahraman_singh(k0: float, e1: float) -> SDOFModel:
    """Kahraman & Singh's (1990) oscillator: m = 1 kg, constant stiffness ``k0`` (N/m), damping
    ratio 0.05, W = 1000 N, half gap B, transmission error ``e1 cos(2 pi p)`` (m)."""
    return SDOFModel(1.0, FourierStiffness(k0, np.array([0.0]), np.array([0.0])), 0.05, 1000.0,
                     100.0, backlash=B,
                     transmission_error=HarmonicSignal(0.0, np.array([e1]), np.array([0.0])))


def _speed(ratio: float) -> float:
    """Pinion speed (rad/s) of f_m / f_n = ratio."""
    return ratio * WN / TEETH


def _linear_orbit_min(lin: SDOFModel) -> float:
    """Smallest x over the linear model's periodic orbit, in closed form: the orbit's start
    from the pieces' matrix exponentials, x(t) by the closed-form flow of each stiffness
    piece, and the minimum where v = 0 (brentq on the closed form, xtol 1e-15 s) or at a
    piece end."""
    phi, q, _ = one_period_map(lin)
    y = np.linalg.solve(np.eye(2) - phi, q)
    best = math.inf
    for ta, tb, a, _g in lin.linear_segments(0.0, 1.0 / lin.mesh_frequency):
        k = -a[1, 0] * lin.mass
        args = (DRIVE, k, lin.mass, lin.damping, lin.static_load, 0.0, y[0], y[1])
        s = np.linspace(0.0, tb - ta, 2001)
        xs, vs = flow(*args, s)
        best = min(best, float(xs[0]), float(xs[-1]))
        for j in np.flatnonzero((vs[:-1] < 0) & (vs[1:] >= 0)):
            sm = brentq(lambda u, a=args: float(flow(*a, np.array([u]))[1][0]),
                        s[j], s[j + 1], xtol=1e-15)
            best = min(best, float(flow(*args, np.array([sm]))[0][0]))
        y = np.array([xs[-1], vs[-1]])
    return best


def test_branch_in_full_contact_is_the_linear_response_and_grazes_where_it_separates() -> None:
    """Below the grazing speed the teeth never separate: the orbit is the linear model's,
    shifted by the half gap (f(x) = x - b in drive contact). The branch's first grazing point
    is where the linear orbit's smallest x reaches zero."""
    fam = sdof_family(oscillator(), "speed", teeth=TEETH)
    lin_fam = sdof_family(oscillator(backlash=None), "speed", teeth=TEETH)
    br = continue_orbits(fam, _speed(0.6), _speed(0.86))
    scale = oscillator().state_scale
    full = [p for p in br.points if p.pattern == "D"]
    assert len(full) >= 5
    for p in full:
        lin = lin_fam(p.parameter)
        phi, q, _ = one_period_map(lin)
        y_lin = np.linalg.solve(np.eye(2) - phi, q) + np.array([B, 0.0])
        # the corrector closes the orbit to newton.tolerance = 1e-10 (scaled); the state's error is
        # that over (1 - |mu|) <= 1 / 0.3 here: 1e-8 of the scale is a wide margin
        assert np.all(np.abs(p.state - y_lin) <= 1e-8 * scale)
    grazes = br.of_kind("grazing")
    assert [g.before + ">" + g.after for g in grazes][:1] == ["D>DGD"]
    w_graze = brentq(lambda w: _linear_orbit_min(lin_fam(w)), _speed(0.8), _speed(0.86),
                     xtol=1e-14)
    # located to locate_tol = 1e-10 relative (its stated error, with the corrector's); the
    # reference to brentq's 1e-14: agreement to 1e-9 is a wide margin
    assert grazes[0].parameter == pytest.approx(w_graze, rel=1e-9)
    assert grazes[0].parameter_error < 1e-9 * w_graze


@pytest.mark.parametrize("upper", [0.9, 0.86])
def test_a_graze_whose_bracket_trials_fail_is_still_reported_within_its_stated_error(
        monkeypatch: pytest.MonkeyPatch, upper: float) -> None:
    """Every trial point inside a step failing to converge (the located points' corrector,
    ``fresh=False``): the grazing point is still reported, at a bracket end, with the
    parameter's change over the bracket as its stated error, and that error covers the
    closed-form grazing speed (the linear orbit's smallest x at zero, as above). With the
    range ending at 0.86 the graze (0.857) lies on the step that leaves the range: the end
    reported lies outside it, within its stated error."""
    from gear_dyn.analysis.continuation.shooting import Shooting

    correct = Shooting.correct

    def failing(self, *args, **kwargs):
        return None if kwargs.get("fresh", True) is False else correct(self, *args, **kwargs)

    monkeypatch.setattr(Shooting, "correct", failing)
    fam = sdof_family(oscillator(), "speed", teeth=TEETH)
    lin_fam = sdof_family(oscillator(backlash=None), "speed", teeth=TEETH)
    br = continue_orbits(fam, _speed(0.78), _speed(upper))
    grazes = br.of_kind("grazing")
    assert [g.before + ">" + g.after for g in grazes][:1] == ["D>DGD"]
    w_graze = brentq(lambda w: _linear_orbit_min(lin_fam(w)), _speed(0.8), _speed(0.86),
                     xtol=1e-14)
    g = grazes[0]
    assert 1e-9 * w_graze < g.parameter_error  # the whole step: far wider than locate_tol
    assert abs(g.parameter - w_graze) <= g.parameter_error


def test_liouville_identity_on_every_point_and_a_point_that_fails_says_so() -> None:
    """det M = exp(-c n T / m_e) (Liouville's formula: tr A = -c/m in every contact state):
    to rounding on the exact route, to the integration tolerance on the variational one; a
    check tighter than the integration's accuracy flags the points."""
    fam = sdof_family(oscillator(), "speed", teeth=TEETH)
    st = ContinuationSettings(max_points=12)
    exact = continue_orbits(fam, _speed(0.84), _speed(0.9), settings=st)
    assert exact.route == "exact"
    assert max(p.liouville for p in exact.points) < 1e-12
    assert all(p.liouville_ok for p in exact.points)
    varl = continue_orbits(fam, _speed(0.84), _speed(0.9), route="variational",
                           settings=ContinuationSettings(max_points=3, rtol=1e-10))
    assert varl.route == "variational"
    assert max(p.liouville for p in varl.points) < 1e-7
    loose = continue_orbits(fam, _speed(0.84), _speed(0.9), route="variational",
                            settings=ContinuationSettings(max_points=2, rtol=1e-6,
                                                          liouville_tol=1e-14))
    assert not any(p.liouville_ok for p in loose.points)
    assert loose.liouville_failures == len(loose.points)
    assert loose.rows()[0]["liouville_ok"] is False
    # the residual itself: a monodromy matrix off by 1 % in one entry fails by about 1 %
    p0 = exact.points[0]
    model = fam(p0.parameter)
    _y, mono = flow_with_sensitivity(model, p0.state, 1.0 / model.mesh_frequency)
    assert liouville_residual(model, mono, 1) < 1e-12
    assert liouville_residual(model, mono * np.array([[1.01, 1.0], [1.0, 1.0]]), 1) > 1e-3


def _extended_fold(fam, y: np.ndarray, w: float, scale: np.ndarray) -> tuple[np.ndarray, float]:
    """The fold from the minimally extended system ``P(y, w) - y = 0, det(M - I) = 0`` on the
    exact flow (extended_system.py)."""
    sol = solve_extended(fam, fold_test, flow_with_sensitivity, scale, w,
                         np.append(y / scale, 1.0), 1e-13)
    # MINPACK may stop with "xtol too small" once the residual is at rounding: judge that
    assert np.max(np.abs(sol.fun)) < 1e-12, sol.message
    return sol.x[:2] * scale, float(sol.x[2] * w)


def test_folds_agree_with_the_extended_system_and_natural_parameter_shooting() -> None:
    fam = sdof_family(oscillator(), "speed", teeth=TEETH)
    br = continue_orbits(fam, _speed(0.84), _speed(0.9))
    folds = br.of_kind("fold")
    assert len(folds) >= 1
    f = folds[0]  # the upper fold of the resonance: the lower branch's end
    assert f.before == "stable" and f.after == "unstable"
    mu = np.sort(np.abs(f.point.multipliers))
    assert mu[1] == pytest.approx(1.0, abs=1e-7)
    scale = oscillator().state_scale
    # start the second method 1e-3 away from the located fold
    y_x, w_x = _extended_fold(fam, f.point.state * (1 + 1e-3), f.parameter * (1 + 1e-3), scale)
    assert f.parameter == pytest.approx(w_x, rel=1e-8)
    assert np.all(np.abs(f.point.state - y_x) < 1e-3 * scale)  # x ~ sqrt(w error) at a fold
    # natural-parameter shooting: below the fold the orbit is there next to the fold orbit,
    # above it Newton from the same state finds no nearby orbit (the sweep jumps)
    below = shoot(fam(f.parameter * (1 - 1e-6)), f.point.state, periods=1)
    assert below.converged and np.all(np.abs(below.y0 - f.point.state) < 0.05 * scale)
    above = shoot(fam(f.parameter * (1 + 1e-6)), f.point.state, periods=1)
    assert not above.converged or np.any(np.abs(above.y0 - f.point.state) > 0.05 * scale)


def test_period_doubling_at_the_floquet_boundary_and_period2_multipliers() -> None:
    """In full contact the period-1 orbit is the linear model's: it doubles its period where
    the linear model's multiplier passes -1 (the parametric instability boundary, found by
    brentq on det(Phi + I) of the matrix-exponential product). The period-2 branch switched
    to there has the multiplier +1 at the period-doubling point (M2 = M1^2)."""
    fam = sdof_family(oscillator(load=300.0), "speed", teeth=TEETH)
    lin_fam = sdof_family(oscillator(load=300.0, backlash=None), "speed", teeth=TEETH)
    br = continue_orbits(fam, _speed(1.8), _speed(2.0), doublings=1,
                         settings=ContinuationSettings(max_points=60))
    pds = br.of_kind("period_doubling")
    assert len(pds) == 1
    pd = pds[0]
    assert pd.before == "stable" and pd.after == "unstable"
    assert np.min(np.abs(pd.point.multipliers + 1.0)) < 1e-7

    def det_plus(w: float) -> float:
        phi, _q, _ = one_period_map(lin_fam(w))
        return float(np.linalg.det(phi + np.eye(2)))

    w_lin = brentq(det_plus, _speed(1.85), _speed(1.95), xtol=1e-14)
    assert pd.parameter == pytest.approx(w_lin, rel=1e-8)
    (child,) = br.children
    assert child.periods == 2 and len(child.points) >= 5
    first = child.points[0]
    assert first.parameter == pytest.approx(pd.parameter, rel=1e-8)
    mu1 = pd.point.multipliers
    mu2 = np.sort_complex(first.multipliers)
    # one multiplier at +1; the other is the square of the period-1 orbit's other multiplier
    assert np.min(np.abs(mu2 - 1.0)) < 1e-6
    other = mu1[np.argmax(np.abs(mu1 + 1.0))]
    assert np.min(np.abs(mu2 - other**2)) < 1e-6
    # genuinely period-2: the orbits do not close after one mesh period
    for p in child.points[1:]:
        model = fam(p.parameter)
        y1, _ = flow_with_sensitivity(model, p.state, 1.0 / model.mesh_frequency)
        assert np.max(np.abs(y1 - p.state) / model.state_scale) > 1e-4


def test_torque_branch_points_are_orbits_found_by_plain_shooting() -> None:
    """A branch in torque (parameter by name): every point is the orbit that shooting at that
    torque alone finds from it."""
    rb1 = 0.05
    base = oscillator()
    fam = sdof_family(base.at_mesh_frequency(0.85 * WN / (2 * math.pi)), "torque",
                      base_radius=rb1)
    br = continue_orbits(fam, 1040.0 * rb1, 900.0 * rb1, parameter="torque",
                         settings=ContinuationSettings(max_points=15))
    assert br.unit == "N*m" and len(br.points) >= 5
    for p in br.points[::3]:
        sol = shoot(fam(p.parameter), p.state, rtol=1e-12, periods=1)
        assert sol.converged
        assert np.all(np.abs(sol.y0 - p.state) <= 1e-8 * base.state_scale)


@pytest.mark.parametrize(("load", "ratio"), [(1040.0, 0.8), (1040.0, 0.87), (1040.0, 0.95),
                                           (300.0, 1.9)])
def test_corrector_run_to_rounding_keeps_its_parameter_column(load: float, ratio: float
                                                              ) -> None:
    """The corrector's secant-updated parameter column (a step along the tangent, the start
    point's column as the chord, ``newton.tolerance`` 1e-14: the last Newton steps move the
    parameter by ~1e-17, at the residual's rounding) against the central difference at the
    converged point. A secant update from such a step is noise over noise (it made the
    located points of a tight continuation lose their columns, and a graze its bracket);
    the kept column's error is the secant's truncation, below 2e-4 relative on these
    steps, within the 1e-3 the branch's columns are held to (test_branch_rows_json_and_repr)."""
    from gear_dyn.analysis.continuation.arclength import start_orbit
    from gear_dyn.analysis.continuation.shooting import Shooting, tangent

    fam = sdof_family(oscillator(load), "speed", teeth=TEETH)
    w = ratio * WN / TEETH
    model = fam(w)
    sh = Shooting(fam, 1, "exact", model.state_scale, w, 1e-10, 1e-5)
    y0 = start_orbit(model, 1, "exact", ContinuationSettings(), None)
    out = sh.correct(sh.scaled(y0, w), np.array([0.0, 0.0, 1.0]), 1.0,
                     NewtonSettings(max_iter=8, tolerance=1e-12))
    assert out is not None
    ev0 = out[0]
    t = tangent(ev0.jac)
    for ds in (1e-3, 3e-3, 1e-2, 2e-2):
        zp = ev0.z + ds * t
        got = sh.correct(zp, t, float(t @ zp), NewtonSettings(max_iter=12, tolerance=1e-14),
                         dp_col=ev0.jac[:, 2], fresh=False)
        assert got is not None
        col, ref = got[0].jac[:, 2], sh.refresh(got[0]).jac[:, 2]
        assert np.max(np.abs(col - ref)) <= 1e-3 * np.max(np.abs(ref)), (ds, col, ref)


@pytest.mark.parametrize("ratio", [0.8, 0.87, 0.95])
def test_forward_difference_column_states_an_upper_error(ratio: float) -> None:
    """The one-map forward difference of the exact route's parameter column, checked against
    a secant-like column (the central difference 1e-4 relative away, first order off as the
    corrector's secants are): its stated error bounds its distance from the Richardson
    extrapolation of two central differences (error O(h^4), below 1e-10 relative here), it
    costs one map, and it agrees with the two-map central difference to 1e-5."""
    from gear_dyn.analysis.continuation.arclength import start_orbit
    from gear_dyn.analysis.continuation.orbit import map_only
    from gear_dyn.analysis.continuation.shooting import Evaluation, Shooting

    fam = sdof_family(oscillator(1040.0), "speed", teeth=TEETH)
    w = ratio * WN / TEETH
    model = fam(w)
    sh = Shooting(fam, 1, "exact", model.state_scale, w, 1e-10, 1e-5)
    y0 = start_orbit(model, 1, "exact", ContinuationSettings(), None)
    out = sh.correct(sh.scaled(y0, w), np.array([0.0, 0.0, 1.0]), 1.0,
                     NewtonSettings(max_iter=8, tolerance=1e-12), fresh=False)
    assert out is not None
    ev = out[0]
    y = sh.state(ev.z)

    def central(p: float, h: float) -> np.ndarray:
        plus, minus = (map_only(fam(p + d), y, 1, "exact", 1e-10) for d in (h, -h))
        return (plus - minus) / (2 * h) * sh.p_ref / sh.scale

    exact = (4 * central(w, 5e-5 * w) - central(w, 1e-4 * w)) / 3
    chord = central(w * (1 + 1e-4), 1e-5 * w)
    bare = Evaluation(ev.z, ev.g, ev.jac.copy(), ev.monodromy, math.nan, ev.model, ev.walked)
    n0 = sh.n_maps
    fwd = sh.refresh(bare, chord)
    assert sh.n_maps == n0 + 1
    col = fwd.jac[:, 2]
    size = float(np.max(np.abs(exact)))
    assert float(np.max(np.abs(col - exact))) / size <= fwd.dp_error < 1e-3
    ctr = sh.refresh(bare)
    assert sh.n_maps == n0 + 3
    assert float(np.max(np.abs(col - ctr.jac[:, 2]))) <= 1e-5 * size


def test_branch_rows_json_and_repr() -> None:
    fam = sdof_family(oscillator(), "speed", teeth=TEETH)
    br = continue_orbits(fam, _speed(0.84), _speed(0.9),
                         settings=ContinuationSettings(max_points=8))
    rows = br.rows()
    assert len(rows) == len(br.points)
    assert {"parameter", "mu1_re", "mu1_im", "mu2_re", "mu2_im", "stable",
            "liouville_residual", "pattern"} <= set(rows[0])
    data = json.loads(json.dumps(br.to_dict()))
    assert data["parameter"] == "speed" and data["branches"][0]["n_points"] == len(br.points)
    # the parameter derivative behind each tangent states its error: secant columns agree to
    # SECANT_AGREEMENT = 1e-4, the central difference's one-sided quotients to O(fd_step)
    errs = np.array([r["dp_error"] for r in rows[1:]], dtype=float)
    assert np.all(np.isfinite(errs)) and np.all(errs < 1e-3)
    assert repr(br).startswith("Branch(period-1, speed ")
    assert "route exact" in repr(br)


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"route": "fast"}, "route = 'fast'"),
    ({"periods": 0}, "periods = 0"),
    ({"doublings": 9}, "doublings = 9"),
])
def test_bad_input_is_refused_naming_the_field(kwargs: dict, match: str) -> None:
    fam = sdof_family(oscillator(), "speed", teeth=TEETH)
    with pytest.raises(InputError, match=match):
        continue_orbits(fam, _speed(0.84), _speed(0.9), **kwargs)


def test_bad_settings_and_family_are_refused() -> None:
    with pytest.raises(InputError, match="step_min = 1 is out of range"):
        ContinuationSettings(step_min=1.0)
    with pytest.raises(InputError, match="parameter = 'load'"):
        sdof_family(oscillator(), "load")
    with pytest.raises(InputError, match="needs teeth"):
        sdof_family(oscillator(), "speed")
    with pytest.raises(InputError, match="start = stop"):
        continue_orbits(sdof_family(oscillator(), "speed", teeth=TEETH), 10.0, 10.0)


def test_variational_route_constant_stiffness_with_transmission_error_is_the_closed_form(
        ) -> None:
    """Kahraman & Singh's (1990) oscillator: constant stiffness, harmonic static transmission
    error e = e1 cos(2 pi p), backlash. The exact route does not apply (a transmission error),
    so the orbits come from the variational equations with located contacts. In full contact
    ``m u'' + c u' + k u = c e' + k e`` with ``u = x - b - W/k``: the steady state is
    ``u = Re[H e1 exp(i W t)]``, ``H = (k + i c W) / (k - m W^2 + i c W)``."""
    k0, e1 = 1e6, 2e-4
    model = _kahraman_singh(k0, e1)
    fam = sdof_family(model, "speed", teeth=TEETH)
    wn = math.sqrt(k0)
    br = continue_orbits(fam, 0.5 * wn / TEETH, 0.7 * wn / TEETH,
                         settings=ContinuationSettings(max_points=5, step=0.05, step_max=0.1))
    assert br.route == "variational" and len(br.points) == 5
    for p in br.points:
        m = fam(p.parameter)
        om = 2 * math.pi * m.mesh_frequency
        h = (k0 + 1j * m.damping * om) / (k0 - om**2 + 1j * m.damping * om)
        closed = np.array([B + 1000.0 / k0 + (h * e1).real, (1j * om * h * e1).real])
        assert p.pattern == "D"
        # DOP853 at rtol 1e-10 over one mesh period, shooting to newton.tolerance 1e-10 (scaled):
        # 1e-7 of the state scale is a wide margin
        assert np.all(np.abs(p.state - closed) <= 1e-7 * m.state_scale)
        assert p.liouville < 1e-7


def test_a_period1_orbit_continued_as_period2_has_the_squared_multipliers() -> None:
    """Shooting over n = 2 mesh periods: a period-1 orbit is also a period-2 orbit, with the
    period-1 orbit's multipliers squared (M2 = M1^2) and the same state."""
    fam = sdof_family(oscillator(), "speed", teeth=TEETH)
    st = ContinuationSettings(max_points=4)
    one = continue_orbits(fam, _speed(0.6), _speed(0.7), settings=st)
    two = continue_orbits(fam, _speed(0.6), _speed(0.7), periods=2, settings=st)
    assert two.periods == 2 and two.points[0].periods == 2
    p1, p2 = one.points[0], two.points[0]
    assert p2.parameter == p1.parameter
    assert np.all(np.abs(p2.state - p1.state) <= 1e-8 * oscillator().state_scale)
    mu1 = np.sort_complex(p1.multipliers**2)
    mu2 = np.sort_complex(p2.multipliers)
    assert np.all(np.abs(mu2 - mu1) < 1e-9)


def test_period2_bubble_between_two_doublings_is_followed_once() -> None:
    """The packaged backlash scene near f_m = 2 f_n: the period-1 orbit doubles its period at
    two speeds (the parametric instability zone); the period-2 branch born at the first bends
    far towards lower speeds (softening) and returns to the period-1 branch at the second. It
    is followed once, and stops where it passes through the period-1 branch."""
    from gear_dyn.scene import load_scene
    from gear_dyn.scene.sweep import SceneModels

    rpm = 2 * math.pi / 60
    br = continue_orbits(SceneModels.of(load_scene("helicopter_tail_backlash")), 9500 * rpm,
                         17000 * rpm, doublings=1)
    pd = br.of_kind("period_doubling")
    assert len(pd) == 2
    (child,) = br.children
    assert child.stop_reason.startswith("reached the period-1 branch")
    assert child.points[0].parameter == pytest.approx(pd[0].parameter, rel=1e-8)
    assert child.points[-1].parameter == pytest.approx(pd[1].parameter, rel=1e-8)
    assert len(child.of_kind("fold")) >= 2  # the bent subharmonic resonance


@pytest.mark.slow
def test_fold_on_the_variational_route_agrees_with_the_extended_system() -> None:
    """Kahraman & Singh's oscillator (constant stiffness, harmonic transmission error) in
    separation: the fold located by continuation on the variational route (DOP853 with
    located contacts) against the minimally extended system solved by MINPACK on the same
    route. Both use the map at rtol 1e-10, whose step-size selection makes it smooth only to
    about that; 1e-7 relative in speed is the margin for it."""
    from gear_dyn.solvers.sensitivity import integrate_with_sensitivity

    k0, e1 = 1e6, 6e-4
    model = _kahraman_singh(k0, e1)
    fam = sdof_family(model, "speed", teeth=TEETH)
    wn = math.sqrt(k0)
    br = continue_orbits(fam, 0.8 * wn / TEETH, 0.81 * wn / TEETH,
                         settings=ContinuationSettings(max_points=40))
    assert br.route == "variational"
    (fold,) = br.of_kind("fold")
    scale = model.state_scale
    variational = partial(integrate_with_sensitivity, rtol=1e-10, route="variational")
    sol = solve_extended(fam, fold_test, variational, scale, fold.parameter,
                         np.append(fold.point.state / scale * (1 + 1e-3), 1.0 + 1e-3), 1e-12)
    assert np.max(np.abs(sol.fun)) < 1e-9, sol.message
    assert fold.parameter == pytest.approx(sol.x[2] * fold.parameter, rel=1e-7)
