"""The closed-form backlash propagator (method exact_contact) against an event-locating DOP853.

The reference (dop853_reference.py) is independent of gear_dyn's solvers: ``solve_ivp(DOP853)``
on the model's right-hand side, restarted at every stiffness switch and at every contact change it
locates with its own event finder (``x = +-b``), at rtol 1e-12 and 1e-13. Its own error is the
difference of the two; the tolerance of each comparison is the propagator's stated error plus
that measured reference error (times two for safety), never a hand-picked number.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from dop853_reference import dop853_events
from scipy.linalg import expm

from gear_dyn.analysis.accuracy import error_scale, estimate_error, relative_errors
from gear_dyn.models.sdof import SDOFModel
from gear_dyn.solvers import SolverSettings, integrate, time_grid
from gear_dyn.solvers.contact_exact import (
    DRIVE,
    _Piece,
    contact_exact_applies,
    find_root,
    flow,
    propagate_contact_exact,
)
from gear_dyn.stiffness.periodic import rectangular_stiffness

M_E, K1, FM0 = 3.0, 1.0e9, 1272.0  # helicopter-tail magnitudes (kg, N/m, Hz)


def backlash_model(f_ratio: float, load: float, xi: float = 0.06) -> SDOFModel:
    k = rectangular_stiffness(1.5, K1, 1.75 * K1)
    fn = math.sqrt(k.mean / M_E) / (2 * math.pi)
    return SDOFModel(mass=M_E, stiffness=k, damping_ratio=xi, static_load=load,
                     mesh_frequency=f_ratio * fn, backlash=10e-6)


@pytest.mark.parametrize("xi", [0.0, 0.06, 1.0, 3.0])
def test_flow_is_the_matrix_exponential(xi: float) -> None:
    """Each contact state's closed form equals expm of its augmented matrix (rounding level)."""
    m, k, w, b = 3.0, 1.2e9, 8.0e3, 1e-5
    c = 2 * xi * math.sqrt(m * k)
    s = np.linspace(0.0, 4e-4, 41)
    for state in (1, 0, -1):
        kk = k if state else 0.0
        mat = np.array([[0.0, 1.0, 0.0], [-kk / m, -c / m, (w + kk * state * b) / m],
                        [0.0, 0.0, 0.0]])
        z0 = np.array([1.3e-5 * (state or 0.5), 0.02, 1.0])
        ref = np.array([expm(mat * si) @ z0 for si in s])
        x, v = flow(state, k, m, c, w, b, z0[0], z0[1], s)
        assert np.max(np.abs(x - ref[:, 0])) <= 1e-12 * np.max(np.abs(ref[:, 0]))
        assert np.max(np.abs(v - ref[:, 1])) <= 1e-12 * np.max(np.abs(ref[:, 1]))


def test_find_root_is_safeguarded() -> None:
    """A flat-then-steep function (false position alone stalls) converges to a few ulps."""
    def f(x: float) -> float:
        return x**9 - 1e-9
    root = find_root(f, 0.0, 1.0, f(0.0), f(1.0), 1e-15)
    assert abs(root - 1e-1) < 1e-14


@pytest.mark.parametrize("root", [0.1, 0.3, 0.123456789, 0.7])
def test_find_root_survives_values_at_the_smallest_float(root: float) -> None:
    """End values of the smallest subnormal (5e-324): the Illinois halving underflows them to
    zero, which once made the secant divide by zero (the backlash scene at 1 rpm, where the
    settled velocity is rounding noise of that size) and, with zero read as negative, kept the
    wrong side of the bracket. The bracket must still close on the sign change."""
    def f(t: float) -> float:
        return math.copysign(5e-324, t - root)
    xtol = 1e-15
    assert abs(find_root(f, 0.0, 1.0, f(0.0), f(1.0), xtol) - root) <= 2 * xtol


def test_find_root_starting_on_zero_finds_the_sign_change() -> None:
    """A bracket whose low end is an exact zero (a piece that starts on the contact boundary)
    closes on the interior sign change, not on the start."""
    def f(t: float) -> float:
        return t * (0.25 - t)
    assert find_root(f, 0.0, 1.0, 0.0, f(1.0), 1e-15) == pytest.approx(0.25, abs=1e-14)


@pytest.mark.parametrize("xi", [0.01, 0.06, 0.5])
def test_amplitude_bound_never_skips_a_crossing(xi: float) -> None:
    """Where :meth:`_Piece.stays_inside` says the drive-flank oscillation never reaches the
    boundary, the closed form sampled at 200 points per damped period over 20 periods stays
    above it; just beyond the bound (amplitude 1.001 of the distance) the check declines."""
    model = backlash_model(1.0, 2000.0, xi)
    pc = _Piece(model, K1, DRIVE)
    b, dist = float(model.backlash or 0.0), model.static_load / K1
    x_eq = b + dist
    s = np.linspace(0.0, 20 * 4 * pc.h, 16001)
    rng = np.random.default_rng(1)
    for ratio in (*rng.uniform(0.5, 0.999, 20), 0.999998):
        angle = rng.uniform(0.0, 2 * math.pi)
        # a start (u0, v0) with hypot(u0, (v0 + a u0 / 2) / q) = ratio * dist
        u0 = ratio * dist * math.cos(angle)
        v0 = ratio * dist * math.sin(angle) * pc.q - 0.5 * (pc.c / pc.m) * u0
        assert pc.stays_inside(x_eq + u0, v0)
        x, _v = pc.at(x_eq + u0, v0, s)
        assert np.min(x) > b
    assert not pc.stays_inside(x_eq - 1.001 * dist, 0.0)


def test_quasi_static_speed_equals_the_linear_model_shifted_by_the_gap() -> None:
    """At f_m = 1e-4 f_n (a mesh period spans 10 000 natural periods; the scene at 1 rpm) the
    teeth stay in contact: the backlash propagator's trajectory is the linear model's (the
    matrix-exponential propagator, method exact) shifted by the half gap, to rounding."""
    model = backlash_model(1e-4, 2000.0)
    linear = SDOFModel(mass=model.mass, stiffness=model.stiffness, damping_ratio=0.06,
                       static_load=model.static_load, mesh_frequency=model.mesh_frequency)
    t = time_grid(model.mesh_frequency, 3 / model.mesh_frequency, 64)
    y0_lin = linear.initial_state()
    b = float(model.backlash or 0.0)
    y, st = propagate_contact_exact(model, t, y0=y0_lin + np.array([b, 0.0]))
    y_lin, _ = integrate(linear, t, SolverSettings(method="exact"), y0=y0_lin)
    assert st["n_contact_events"] == 0
    scale = float(np.max(np.abs(y_lin[0])))
    assert np.max(np.abs(y[0] - b - y_lin[0])) <= 1e-12 * scale


@pytest.mark.parametrize(("f_ratio", "load", "kick"),
                         [(1.0, 2000.0, 0.0), (0.5, 2000.0, 0.0), (0.7, 500.0, -4.0)])
def test_events_and_trajectory_match_dop853(f_ratio: float, load: float, kick: float) -> None:
    """``kick``: initial velocity in units of the velocity scale (-4: hits the back flank)."""
    model = backlash_model(f_ratio, load)
    assert contact_exact_applies(model)  # auto picks the kernel first (test_kernel_method.py)
    t = time_grid(model.mesh_frequency, 30 / model.mesh_frequency, 64)
    y0 = model.initial_state() + np.array([0.0, kick * model.state_scale[1]])
    y, st = propagate_contact_exact(model, t, y0=y0)
    y12, ev12 = dop853_events(model, t, 1e-12, y0)
    y13, ev13 = dop853_events(model, t, 1e-13, y0)
    if kick:
        assert np.min(y13[0]) < -float(model.backlash or 0.0), "must reach the back flank"
    assert ev13.size > 10, "the case must separate the teeth"
    ours = np.asarray(st["event_times"])
    assert ours.size == ev13.size
    ev_own = float(np.max(np.abs(ev12 - ev13)))
    period = 1 / model.mesh_frequency
    assert np.max(np.abs(ours - ev13)) <= 10 * ev_own + 1e-12 * period
    ref_own = relative_errors(model, t, y12, y13)[0]
    est = estimate_error(model, t, y, SolverSettings(method="exact_contact"), st)["max_rel"]
    err = relative_errors(model, t, y, y13)[0]
    assert err <= 2 * (est + ref_own), (err, est, ref_own)
    assert error_scale(model) > 0


def test_integrate_runs_it_and_states_its_error() -> None:
    model = backlash_model(1.0, 2000.0)
    t = time_grid(model.mesh_frequency, 20 / model.mesh_frequency, 64)
    y, st = integrate(model, t, SolverSettings(method="exact_contact"))
    assert st["method"] == "exact_contact"
    y_d, _ = integrate(model, t, SolverSettings(method="DOP853", rtol=1e-10))
    assert relative_errors(model, t, y, y_d)[0] < 1e-6
