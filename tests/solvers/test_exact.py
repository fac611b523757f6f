"""The exact piecewise propagator against closed forms and an independent step-by-step expm.

Tolerances: the propagator has no truncation error, so every comparison is at rounding level,
1e-12 relative to the static deflection (a few hundred pieces of 1e-16 each, plus the
eigen-decomposition's condition number, which the propagator caps at 1e3).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.linalg import expm

import gear_dyn.solvers.exact as exact
from gear_dyn.analysis.study import simulate
from gear_dyn.errors import InputError
from gear_dyn.models.sdof import SDOFModel
from gear_dyn.solvers import SolverSettings, resolve_auto, time_grid
from gear_dyn.solvers.exact import exact_applies, propagate_exact, propagate_pieces
from gear_dyn.stiffness.periodic import PiecewiseStiffness, rectangular_stiffness

M_E, K, W, FM = 3.0, 1.0e9, 2.0e4, 1272.0  # helicopter-tail magnitudes (kg, N/m, N, Hz)


def constant_model(xi: float) -> SDOFModel:
    """Constant stiffness split into two equal pieces, so the propagator still switches."""
    k = PiecewiseStiffness(np.array([0.0, 0.4, 1.0]),
                           ((np.array([0.0, 0.4]), np.array([K, K])),
                            (np.array([0.4, 1.0]), np.array([K, K]))))
    return SDOFModel(mass=M_E, stiffness=k, damping_ratio=xi, static_load=W, mesh_frequency=FM)


def closed_form(t: np.ndarray, xi: float, x0: float, v0: float) -> np.ndarray:
    """x(t) of m x'' + c x' + k x = W (under-, critically and over-damped)."""
    wn = math.sqrt(K / M_E)
    xs = W / K
    u0 = x0 - xs
    if xi < 1:
        wd = wn * math.sqrt(1 - xi**2)
        u = np.exp(-xi * wn * t) * (u0 * np.cos(wd * t) + (v0 + xi * wn * u0) / wd * np.sin(wd * t))
    elif xi == 1:
        u = np.exp(-wn * t) * (u0 + (v0 + wn * u0) * t)
    else:
        s = wn * math.sqrt(xi**2 - 1)
        r1, r2 = -xi * wn + s, -xi * wn - s
        a = (v0 - r2 * u0) / (r1 - r2)
        b = u0 - a
        u = a * np.exp(r1 * t) + b * np.exp(r2 * t)
    return xs + u


@pytest.mark.parametrize("xi", [0.0, 0.06, 1.0, 5.0])
def test_constant_stiffness_matches_closed_form(xi: float) -> None:
    """From rest at x = 0 (the full step load): exact vs closed form to 1e-12 of W/k over 50
    periods, for undamped, light, critical (defective matrix: Pade route) and heavy damping."""
    model = constant_model(xi)
    t = time_grid(FM, 50 / FM, 64)
    y, st = propagate_exact(model, t, None, np.array([0.0, 0.0]))
    xs = W / K
    err = np.max(np.abs(y[0] - closed_form(t, xi, 0.0, 0.0))) / xs
    assert err < 1e-12, err
    assert st["n_segments"] == 100  # two pieces per period: the switching path is exercised
    if xi == 1.0:
        assert not st["eigen"]  # critical damping is defective: the Pade expm route is taken


def stepwise_reference(pieces: list, t: np.ndarray, y0: np.ndarray) -> np.ndarray:
    """Independent: state carried piece by piece with scipy expm, each grid point from the
    state at its piece start (plain loops, no grouping, no eigen-decomposition)."""
    n = y0.size
    out = np.empty((n, t.size))
    z = np.append(y0, 1.0)
    i = 0
    for ta, tb, a, g in pieces:
        m = np.zeros((n + 1, n + 1))
        m[:n, :n], m[:n, n] = a, g
        last = tb == pieces[-1][1]
        while i < t.size and (t[i] < tb or (last and t[i] <= tb)):
            out[:, i] = (expm(m * (t[i] - ta)) @ z)[:n]
            i += 1
        z = expm(m * (tb - ta)) @ z
    return out


def test_rectangular_stiffness_matches_stepwise_expm() -> None:
    """Helicopter-tail-like rectangular wave (eps = 1.58): exact vs the step-by-step expm
    reference to 1e-12 of the static deflection over 20 periods."""
    k = rectangular_stiffness(1.58, 0.7e9, 1.24e9)
    model = SDOFModel(mass=M_E, stiffness=k, damping_ratio=0.06, static_load=W,
                      mesh_frequency=FM)
    t = time_grid(FM, 20 / FM, 32)
    pieces = model.linear_segments(float(t[0]), float(t[-1]))
    assert pieces is not None
    ref = stepwise_reference(pieces, t, model.initial_state())
    y, _ = propagate_exact(model, t)
    xs = W / model.mean_stiffness
    assert np.max(np.abs(y[0] - ref[0])) / xs < 1e-12


def test_eigen_and_pade_routes_agree(monkeypatch: pytest.MonkeyPatch) -> None:
    """The eigen route and the Pade route (forced by a zero condition cap) agree to 1e-12."""
    k = rectangular_stiffness(1.58, 0.7e9, 1.24e9)
    model = SDOFModel(mass=M_E, stiffness=k, damping_ratio=0.06, static_load=W,
                      mesh_frequency=FM)
    t = time_grid(FM, 30 / FM, 64)
    y_eig, st_eig = propagate_exact(model, t)
    monkeypatch.setattr(exact, "MAX_EIGEN_CONDITION", 0.0)
    y_pade, st_pade = propagate_exact(model, t)
    assert st_eig["eigen"] and not st_pade["eigen"]
    # on a commensurate grid the offsets recur every cycle: few distinct exponentials
    assert st_pade["nfev"] < 3 * 64
    xs = W / model.mean_stiffness
    assert np.max(np.abs(y_eig[0] - y_pade[0])) / xs < 1e-12


def test_singular_matrix_rigid_body_mode() -> None:
    """A free rigid body under constant force (A singular, augmented matrix defective):
    x = x0 + v0 t + a t^2 / 2 to 1e-12 relative."""
    a_mat = np.array([[0.0, 1.0], [0.0, 0.0]])
    acc = 3.0
    g = np.array([0.0, acc])
    t = np.linspace(0.0, 2.0, 101)
    pieces = [(0.0, 0.7, a_mat, g), (0.7, 1.3, a_mat, g), (1.3, 2.0, a_mat, g)]
    y, _ = propagate_pieces(pieces, t, np.array([1.0, -2.0]))
    x = 1.0 - 2.0 * t + 0.5 * acc * t**2
    assert np.max(np.abs(y[0] - x)) / np.max(np.abs(x)) < 1e-12
    assert np.max(np.abs(y[1] - (-2.0 + acc * t))) / 4.0 < 1e-12


def test_auto_uses_exact_and_rejects_nonlinear() -> None:
    """auto picks exact for the linear piecewise-constant model; exact refuses backlash
    (auto then takes the compiled kernel, tests/solvers/test_kernel_method.py)."""
    k = rectangular_stiffness(1.58, 0.7e9, 1.24e9)
    model = SDOFModel(mass=M_E, stiffness=k, damping_ratio=0.06, static_load=W,
                      mesh_frequency=FM)
    assert exact_applies(model) and resolve_auto(model) == "exact"
    bl = replace(model, backlash=1e-5)
    assert not exact_applies(bl) and resolve_auto(bl) == "kernel"  # closed form + events, in C
    with pytest.raises(InputError, match="piecewise-constant"):
        propagate_exact(bl, time_grid(FM, 2 / FM, 16))


def test_run_summary_states_rounding_level_estimate() -> None:
    """An exact run's estimated error is at rounding level and bounds its measured error
    against the closed form (constant stiffness, from the static deflection at rest: x = x_s)."""
    model = constant_model(0.06)
    res = simulate(model, 20 / FM, SolverSettings())
    est = res.extra["estimated_error"]
    assert res.stats.method == "exact"
    err = np.max(np.abs(res.y[0] - W / K)) / (W / K)
    assert err <= est["max_rel"] < 1e-11


def test_torsional_linear_model_exact_vs_dop853() -> None:
    """The linear two-DOF torsional model (rectangular stiffness, no eccentricity, friction or
    backlash: A is singular, a free rigid-body rotation) through the exact propagator agrees
    with DOP853 at rtol 1e-11 (restarted at every jump) to 1e-8 of the static deflection on the
    DTE (measured 2.8e-10: DOP853's own global error), and auto picks exact for it. The
    defective augmented matrix takes the Pade route."""
    from gear_dyn.analysis.accuracy import relative_errors
    from gear_dyn.geometry import GearPair
    from gear_dyn.models.torsional import TorsionalModel
    from gear_dyn.solvers import integrate

    pair = GearPair(z1=23, z2=64, module=6e-3, pressure_angle=math.radians(22.5),
                    face_width=0.05)
    k = rectangular_stiffness(pair.contact_ratio, 7.1e8, 1.24e9)
    model = TorsionalModel(pair=pair, speed=347.6, torque=1474.4, stiffness=k,
                           inertias=(0.05, 0.4))
    assert resolve_auto(model) == "exact"
    a = model.linear_segments(0.0, 1.0 / model.mesh_frequency)[0][2]
    assert abs(np.linalg.det(a)) < 1e-12 * np.max(np.abs(a)) ** 4  # singular: rigid-body mode
    t = time_grid(model.mesh_frequency, 10 / model.mesh_frequency, 64)
    y_ex, st = integrate(model, t, SolverSettings(method="exact"))
    assert not st["eigen"]
    y_ode, _ = integrate(model, t, SolverSettings(method="DOP853", rtol=1e-11))
    assert relative_errors(model, t, y_ex, y_ode)[0] < 1e-8
