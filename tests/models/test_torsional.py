"""Two-DOF torsional model: SDOF equivalence, energy, rigid limit, momentum, switching, Jacobian."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from gear_dyn.analysis.study import simulate
from gear_dyn.eccentricity import Eccentricity
from gear_dyn.eccentricity.contact_lines import LineLayout, line_positions
from gear_dyn.errors import InputError
from gear_dyn.geometry import GearPair
from gear_dyn.models.sdof import sdof_from_pair
from gear_dyn.models.torsional import ContactLineStiffness, TorsionalModel, torsional_from_pair
from gear_dyn.solvers import SolverSettings, integrate, time_grid
from gear_dyn.stiffness.contact_line import contact_line_breakpoints
from gear_dyn.stiffness.periodic import FourierStiffness, rectangular_stiffness

W1 = 1500 * 2 * math.pi / 60
T1 = 10e3 / W1  # 10 kW at 1500 rpm
PAIR = GearPair(18, 70, 3e-3, math.radians(20), 0.04, math.radians(15))
K_L = 1.13e10  # N/m^2: ISO 6336 c_gamma cos(b_b) / eps_a of PAIR (mean ~7.5e8 N/m)
INERTIAS = (2e-3, 0.069)
ECC = Eccentricity(2e-4, 2e-4)


def constant(k: float) -> FourierStiffness:
    return FourierStiffness(k, np.zeros(1), np.zeros(1), name="constant")


def test_relative_coordinate_obeys_the_single_dof_model() -> None:
    """x = r_b1 q1 - r_b2 q2 satisfies m_e x'' + c x' + k(t) x = W exactly when T2 = T1 z2/z1
    (subtract the two equations): torsional DTE == the independent SDOF model's x. Both run with
    the exact propagator, so they agree to rounding (1e-9 of the static deflection)."""
    k = rectangular_stiffness(PAIR.contact_ratio, 5e8, 8.5e8)
    tors = TorsionalModel(PAIR, W1, T1, k, INERTIAS, damping_ratio=0.07)
    sdof = sdof_from_pair(PAIR, W1, T1, k, damping_ratio=0.07, inertias=INERTIAS)
    assert tors.linear_segments(0.0, 0.01) is not None
    settings = SolverSettings(method="exact")
    rt = simulate(tors, 60 / tors.mesh_frequency, settings)
    rs = simulate(sdof, 60 / sdof.mesh_frequency, settings)
    scale = sdof.static_deflection
    assert np.max(np.abs(rt.outputs["dte"] - rs.outputs["dte"])) < 1e-9 * scale
    assert np.max(np.abs(rt.outputs["mesh_force"] - rs.outputs["mesh_force"])) < 1e-6 * (
        sdof.static_load)


def test_exact_propagator_matches_dop853() -> None:
    """Second integrator on the same model (tolerance-limited: rtol 1e-9 per step, a few
    hundred steps: 1e-6 of the static deflection)."""
    k = rectangular_stiffness(PAIR.contact_ratio, 5e8, 8.5e8)
    tors = TorsionalModel(PAIR, W1, T1, k, INERTIAS, damping_ratio=0.05)
    t_end = 10 / tors.mesh_frequency
    a = simulate(tors, t_end, SolverSettings(method="exact"))
    b = simulate(tors, t_end, SolverSettings(method="DOP853", rtol=1e-9))
    scale = tors.static_deflection
    assert np.max(np.abs(a.outputs["delta"] - b.outputs["delta"])) < 1e-6 * scale


def _integrate_with_contact_events(model: TorsionalModel, y0: np.ndarray,
                                   t_end: float) -> tuple[np.ndarray, int]:
    """DOP853 restarted at every zero of model.contact_events() (the dead-zone kinks), so each
    step sees a smooth right-hand side; returns the states at the step ends and the count."""
    funcs = model.contact_events()
    events = []
    for fn in funcs:
        def ev(t: float, y: np.ndarray, fn=fn) -> float:
            return fn(t, y)
        ev.terminal = True  # type: ignore[attr-defined]
        events.append(ev)
    t, y, out, n = 0.0, y0, [y0[:, None]], 0
    while t < t_end and n < 1000:
        sol = solve_ivp(model.rhs, (t, t_end), y, method="DOP853", rtol=1e-11, atol=1e-16,
                        events=events)
        out.append(sol.y[:, 1:])
        t, y = float(sol.t[-1]), sol.y[:, -1]
        if sol.status == 1:
            n += 1
            t_step = 1e-12 / model.mesh_frequency  # step off the zero before restarting
            y = y + t_step * model.rhs(t, y)
            t += t_step
    return np.concatenate(out, axis=1), n


@pytest.mark.parametrize("backlash", [None, 2e-6])
def test_energy_is_conserved_without_damping_friction_and_excitation(
        backlash: float | None) -> None:
    """Constant stiffness, no damping, friction, eccentricity or TE: the system is conservative,
    E = I1 q1'^2/2 + I2 q2'^2/2 + V(delta) - T1 q1 + T2 q2 with V = k f(delta)^2 / 2 (dead zone
    with backlash). An unbalanced load tests the work terms too. rtol 1e-11 on the states keeps
    the drift of E near 1e-9 of the static strain energy; 1e-8 is asserted."""
    k0 = 8e8
    model = TorsionalModel(PAIR, W1, T1, constant(k0), INERTIAS, damping_ratio=0.0,
                           backlash=backlash, load_torque=1.1 * T1 * 70 / 18)
    kick = 2e-3 if backlash is None else 1.0  # with backlash: the teeth separate and impact
    y0 = model.initial_state() + np.array([0.0, 0.0, 0.0, kick])  # free vibration
    t_end = (15 if backlash is None else 4) / model.mesh_frequency
    if backlash is None:
        t = time_grid(model.mesh_frequency, t_end, 32)
        y, _ = integrate(model, t, SolverSettings(method="DOP853", rtol=1e-11, atol=1e-16), y0)
    else:
        y, n_events = _integrate_with_contact_events(model, y0, t_end)
        assert n_events > 2  # contact was lost and regained
    rb1, rb2 = PAIR.rb1, PAIR.rb2
    d = rb1 * y[0] - rb2 * y[1]
    if backlash is not None:
        d = np.where(d > backlash, d - backlash, np.where(d < -backlash, d + backlash, 0.0))
    i1, i2 = INERTIAS
    energy = (0.5 * i1 * y[2] ** 2 + 0.5 * i2 * y[3] ** 2 + 0.5 * k0 * d**2 - T1 * y[0]
              + model.load * y[1])
    scale = max(0.5 * k0 * model.static_deflection**2, 0.5 * i2 * kick**2)
    assert np.max(np.abs(energy - energy[0])) < 1e-8 * scale


def test_static_state_is_an_equilibrium() -> None:
    """Constant stiffness, no excitation: the initial state is static (rhs = 0 to rounding)."""
    model = TorsionalModel(PAIR, W1, T1, constant(8e8), INERTIAS)
    acc = model.rhs(0.0, model.initial_state())
    assert np.max(np.abs(acc)) < 1e-9 * T1 / INERTIAS[0]


def test_rigid_limit_driven_speed_converges_to_the_kinematic_speed() -> None:
    """As k grows the torsional w2(t) tends to the kinematic w2(t) of Liu et al. (2017), eq. 12,
    like 1/k.

    A heavy input (I1 = 50 kg m^2, a motor) holds w1 nearly constant, as the kinematics assume.
    Measured (the same run, DOP853 rtol 1e-8): max error 0.0178 rad/s at k_l = 1.13e10 N/m^2,
    0.0017 rad/s at 10x; the peak-to-peak of w2 is 0.60 rad/s. Assert a drop by > 5x."""
    errors = []
    for factor in (1.0, 10.0):
        model = TorsionalModel(PAIR, W1, T1, ContactLineStiffness(K_L * factor), (50.0, 0.069),
                               damping_ratio=0.1, eccentricity=ECC)
        r = simulate(model, 0.03, SolverSettings(method="DOP853", rtol=1e-8))
        sel = r.t > 0.012  # after the start-up transient (time constant 1 / (xi w_n) < 1 ms)
        w2, wk = r.outputs["w2"][sel], r.outputs["w2_kinematic"][sel]
        assert np.ptp(wk) > 0.3  # the eccentricity really modulates w2
        errors.append(float(np.max(np.abs(w2 - wk))))
    print("rigid-limit errors (rad/s):", errors)
    assert errors[1] < errors[0] / 5
    assert errors[1] < 1e-2 * 0.3


def test_rigid_body_momentum_is_conserved_so_nothing_drifts() -> None:
    """Without friction, I1 q1'' + (r_b1/r_b2) I2 q2'' = T1 - (r_b1/r_b2) T2 = 0 for the balanced
    load, and the initial state has zero momentum: it stays zero (tolerance-limited)."""
    model = TorsionalModel(PAIR, W1, T1, ContactLineStiffness(K_L), INERTIAS, damping_ratio=0.06,
                           eccentricity=ECC)
    r = simulate(model, 0.03, SolverSettings(method="DOP853", rtol=1e-9))
    i1, i2 = INERTIAS
    mom = i1 * r.y[2] + PAIR.rb1 / PAIR.rb2 * i2 * r.y[3]
    scale = i1 * np.max(np.abs(r.y[2]))
    assert np.max(np.abs(mom)) < 1e-5 * scale
    # the vibration angle stays bounded (no drift of the nominal rotation)
    assert np.max(np.abs(r.y[0])) < 1e-2


def test_switching_times_without_eccentricity_are_the_contact_line_breakpoints() -> None:
    """Error-free pair: kinks of k_l L(t) are the breakpoints of the independent contact-line
    module (issue 3) divided by f_m."""
    model = TorsionalModel(PAIR, W1, T1, ContactLineStiffness(K_L), INERTIAS)
    fm = model.mesh_frequency
    sw = model.switching_times(0.0, 5 / fm)
    expect = np.sort(np.concatenate([(c + contact_line_breakpoints(PAIR)) / fm
                                     for c in range(6)]))
    expect = expect[(expect > 1e-12) & (expect < 5 / fm - 1e-12)]
    np.testing.assert_allclose(sw, expect, rtol=0, atol=1e-14)


def test_switching_times_with_eccentricity_put_a_line_end_on_a_boundary() -> None:
    """At every reported instant some line end sits on C, D or the pitch line (1e-12 m)."""
    model = TorsionalModel(PAIR, W1, T1, ContactLineStiffness(K_L), INERTIAS, eccentricity=ECC,
                           friction=0.05)
    sw = model.switching_times(0.0, 0.02)
    assert sw.size > 4 * 0.02 * model.mesh_frequency  # >= 4 kinds of event per mesh period
    kin = model.mesh.kinematics(sw)
    lay = LineLayout.of(model.mesh)
    d = line_positions(lay, kin)
    bounds = [np.zeros_like(sw), np.asarray(kin.l_cd), np.asarray(kin.l_cp)]
    gap = np.full(sw.shape, np.inf)
    for b in bounds:
        for end in (d, d - lay.width):
            gap = np.minimum(gap, np.min(np.abs(end - b), axis=0))
    assert np.max(gap) < 1e-12


def test_jacobian_matches_finite_differences() -> None:
    model = TorsionalModel(PAIR, W1, T1, ContactLineStiffness(K_L), INERTIAS, damping_ratio=0.06,
                           eccentricity=ECC, friction=0.05, backlash=1e-6)
    y = model.initial_state()
    scale = model.state_scale
    for t in (0.0013, 0.0071, 0.0123):
        jac = model.jac(t, y)
        num = np.empty((4, 4))
        for j in range(4):
            dy = np.zeros(4)
            dy[j] = 1e-4 * scale[j]
            num[:, j] = (model.rhs(t, y + dy) - model.rhs(t, y - dy)) / (2 * dy[j])
        # central differences of a function linear in y (away from kinks): rounding only
        np.testing.assert_allclose(jac, num, rtol=1e-6, atol=1e-6 * np.max(np.abs(num)))


def test_friction_outputs_and_zero_coefficient() -> None:
    """Friction torques are the normal load times the kinematic factors; mu = 0 gives zero and
    the same motion as no friction at all (tolerance-limited)."""
    kw = dict(eccentricity=ECC, damping_ratio=0.06)
    a = torsional_from_pair(PAIR, W1, T1, ContactLineStiffness(K_L), inertias=INERTIAS,
                            friction=0.0, **kw)
    b = torsional_from_pair(PAIR, W1, T1, ContactLineStiffness(K_L), inertias=INERTIAS, **kw)
    settings = SolverSettings(method="DOP853", rtol=1e-9)
    ra, rb = simulate(a, 0.005, settings), simulate(b, 0.005, settings)
    assert not np.any(ra.outputs["friction_torque_pinion"])
    assert not np.any(ra.outputs["friction_torque_gear"])
    assert np.max(np.abs(ra.outputs["delta"] - rb.outputs["delta"])) < 1e-6 * b.static_deflection
    c = torsional_from_pair(PAIR, W1, T1, ContactLineStiffness(K_L), inertias=INERTIAS,
                            friction=0.05, **kw)
    rc = simulate(c, 0.005, settings)
    ex = c.excitations(rc.t)
    np.testing.assert_allclose(rc.outputs["friction_torque_pinion"],
                               np.maximum(rc.outputs["mesh_force"], 0) * ex["phi1"], rtol=1e-12)
    # friction brakes the pinion on average (mean arm negative): less torque is left for the
    # normal load, W < T1 / r_b1, and the balanced load torque is below T1 z2 / z1 (efficiency)
    assert c.mean_friction_arms[0] < 0 and c.static_load < T1 / PAIR.rb1
    assert 0.98 < c.load / (T1 * 70 / 18) < 1.0


def test_disabled_parts_build_nothing() -> None:
    model = TorsionalModel(PAIR, W1, T1, constant(8e8), INERTIAS)
    assert not model.eccentric and model.friction is None
    assert model._layout is None  # no contact-line machinery
    assert model.mean_friction_arms == (0.0, 0.0)
    assert model.load == pytest.approx(T1 * 70 / 18, rel=1e-13)


def test_unknown_option_and_bad_values_are_refused() -> None:
    with pytest.raises(InputError, match="unknown option"):
        torsional_from_pair(PAIR, W1, T1, constant(8e8), eccentrcity=ECC)
    with pytest.raises(InputError, match="friction.coefficient"):
        TorsionalModel(PAIR, W1, T1, constant(8e8), INERTIAS, friction=-0.1)
    with pytest.raises(InputError, match="stiffness.per_length"):
        ContactLineStiffness(-1.0)


def test_periodic_stiffness_follows_the_eccentric_mesh_phase() -> None:
    """Any stiffness method with eccentricity: k is evaluated at the eccentric mesh phase
    p = (tau + L_AC0 - L_AC) / p_bt, so its jumps happen where that phase crosses the switching
    phases (1e-9 cycles), not at f_m t; without eccentricity p = f_m t exactly."""
    k = rectangular_stiffness(PAIR.contact_ratio, 5e8, 8.5e8)
    model = TorsionalModel(PAIR, W1, T1, k, INERTIAS, eccentricity=ECC)
    sw = model.switching_times(0.0, 0.02)
    kin = model.mesh.kinematics(sw)
    phase = (kin.travel + model.mesh.l_ac0 - kin.l_ac) / PAIR.base_pitch
    frac = np.mod(phase, 1.0)
    dist = np.min(np.abs(frac[:, None] - np.append(k.switching_phases, 1.0)[None, :]), axis=1)
    assert np.max(dist) < 1e-9
    assert sw.size == pytest.approx(2 * 0.02 * model.mesh_frequency, abs=2)
    # the stiffness seen by the model jumps exactly there
    before = np.array([model.excitations(np.array([t - 1e-9]))["stiffness"][0] for t in sw[:6]])
    after = np.array([model.excitations(np.array([t + 1e-9]))["stiffness"][0] for t in sw[:6]])
    assert np.all(np.abs(after - before) == pytest.approx(3.5e8, rel=1e-12))
    plain = TorsionalModel(PAIR, W1, T1, k, INERTIAS)
    np.testing.assert_allclose(plain.switching_times(0.0, 0.02),
                               k.switching_times(0.0, 0.02, plain.mesh_frequency), rtol=0,
                               atol=1e-15)
    r = simulate(model, 0.004, SolverSettings(method="DOP853", rtol=1e-7))
    assert np.all(np.isfinite(r.outputs["mesh_force"]))


def test_mean_friction_arms_are_means_over_shaft_angles_at_any_speed() -> None:
    """The kept means serve another speed: computed afresh there they agree to rounding."""
    from gear_dyn.models import torsional

    def build(speed: float) -> TorsionalModel:
        return TorsionalModel(PAIR, speed, T1, ContactLineStiffness(K_L), INERTIAS,
                              eccentricity=ECC, friction=0.05)
    torsional._MEAN_ARMS.clear()
    fast = build(W1).mean_friction_arms
    torsional._MEAN_ARMS.clear()
    slow = build(W1 / 37).mean_friction_arms
    np.testing.assert_allclose(slow, fast, rtol=1e-12)
    assert build(W1 / 37).mean_friction_arms == slow  # kept: the same numbers


def test_outputs_on_a_repeated_grid_are_fresh_and_equal() -> None:
    """The kept excitations of the last grid: the same numbers, never the caller's arrays."""
    model = TorsionalModel(PAIR, W1, T1, ContactLineStiffness(K_L), INERTIAS, eccentricity=ECC,
                           friction=0.05)
    t = time_grid(model.mesh_frequency, 200 / model.mesh_frequency, 64)
    y = np.repeat(model.initial_state()[:, None], t.size, axis=1)
    first = model.outputs(t, y)
    first["stiffness"][:] = 0.0  # the caller's array, not the kept one
    again = model.outputs(t.copy(), y)
    ex = model.excitations(t)
    np.testing.assert_array_equal(again["stiffness"], ex["stiffness"])
    np.testing.assert_array_equal(again["e_ecc"], ex["e_ecc"])
    blocks = [model.excitations(t[i:i + 1000]) for i in range(0, t.size, 1000)]
    for name, value in ex.items():
        ref = np.concatenate([b[name] for b in blocks])
        # blocks of another size: the same formulas point by point (the kinematics' Newton
        # steps may stop one step apart, at rounding)
        np.testing.assert_allclose(value, ref, rtol=1e-12, atol=1e-12 * np.max(np.abs(ref)))
