"""Stiff and extreme cases: each test states what must happen and checks it.

All on the helicopter-tail single-DOF pair (Jiang et al. 2018; f_n = 2.9 kHz, f_m = 1272 Hz) with
one thing pushed to an extreme. The table in docs/solvers_cases.md summarises what each method does
here and what the toolkit does about it. Spans are a few mesh periods to keep CI short; the long
measurements are in benchmarks/bench_solvers.py.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm

from gear_dyn.analysis.accuracy import relative_errors, stiffness_check
from gear_dyn.analysis.stability import floquet_multipliers
from gear_dyn.analysis.study import simulate
from gear_dyn.excitation import HarmonicSignal
from gear_dyn.scene import load_scene
from gear_dyn.scene.build import build_plan
from gear_dyn.solvers import SolverSettings, integrate, resolve_auto, time_grid
from gear_dyn.stiffness.periodic import FourierStiffness, PiecewiseStiffness

SCENE = "examples/scenes/helicopter_tail.toml"


@pytest.fixture(scope="module")
def heli() -> Any:
    return build_plan(load_scene(SCENE)).model


def grid(model: Any, periods: float, samples: int = 64) -> np.ndarray:
    return time_grid(model.mesh_frequency, periods / model.mesh_frequency, samples)


# ------------------------------------------------------------------ heavy damping
def test_heavy_damping_explicit_slow_implicit_fine_toolkit_advises(heli: Any) -> None:
    """xi = 5 (over-damped, eigenvalues -0.1 w_n and -9.9 w_n: stiffness ratio ~100), smooth
    Fourier stiffness so no exact propagator. Must happen: at a loose rtol (1e-3) the explicit
    RK45 is held by stability, needing > 3x the evaluations of Radau and of LSODA (measured
    4.6x and 3.6x); the toolkit flags the stiffness and advises when an explicit method is
    chosen; the default path (auto: periodic step maps, this model being linear) is accurate
    (error < 1e-4 at rtol 1e-6), and so is LSODA, auto's choice for nonlinear models."""
    model = replace(heli, stiffness=heli.stiffness.truncated(5), damping_ratio=5.0)
    t = grid(model, 5)
    y_ref, _ = integrate(model, t, SolverSettings(method="DOP853", rtol=1e-12))
    nfev = {m: integrate(model, t, SolverSettings(method=m, rtol=1e-3))[1]["nfev"]
            for m in ("RK45", "Radau", "LSODA")}
    assert nfev["RK45"] > 3 * nfev["Radau"] and nfev["RK45"] > 3 * nfev["LSODA"], nfev
    chk = stiffness_check(model, "RK45")
    assert chk["stiff"] and chk["stiffness_ratio"] > 50 and "LSODA" in chk["advice"]
    assert not stiffness_check(heli, "RK45")["stiff"]  # xi = 0.06: no false alarm
    res = simulate(model, float(t[-1]), SolverSettings(method="RK45", rtol=1e-4,
                                                       estimate_error=False))
    assert res.extra["stiffness_check"]["advice"]
    assert resolve_auto(model) == "LSODA"
    for settings in (SolverSettings(rtol=1e-6), SolverSettings(method="LSODA", rtol=1e-6)):
        y, _ = integrate(model, t, settings)
        assert relative_errors(model, t, y, y_ref)[0] < 1e-4


# ------------------------------------------------------------------ very stiff, light mesh
def test_stiff_light_mesh(heli: Any) -> None:
    """k x1000, m_e x0.001: f_n = 2.9 MHz, 2300 natural periods per mesh period. Must happen:
    auto takes the exact propagator; LSODA restarted at each switching instant (the toolkit's
    path) agrees with it to 1e-5 of the static deflection (measured 2.5e-6 at rtol 1e-6);
    LSODA called once over the span steps over the stiffness jumps and is > 10 % wrong while
    reporting success (measured 62 %) - why the toolkit always restarts; an explicit method
    is flagged (>= 500 steps per mesh period for stability alone)."""
    k = heli.stiffness
    k2 = PiecewiseStiffness(k.edges, tuple((p, v * 1000) for p, v in k.samples), name="x1000")
    model = replace(heli, stiffness=k2, mass=heli.mass * 1e-3)
    assert model.natural_frequency == pytest.approx(1000 * heli.natural_frequency, rel=1e-12)
    assert resolve_auto(model) == "exact"
    t = grid(model, 3)
    y_ex, _ = integrate(model, t, SolverSettings())
    y_ls, _ = integrate(model, t, SolverSettings(method="LSODA", rtol=1e-6))
    assert relative_errors(model, t, y_ls, y_ex)[0] < 1e-5
    atol = 1e-6 * model.state_scale
    once = solve_ivp(model.rhs, (0.0, float(t[-1])), model.initial_state(), method="LSODA",
                     t_eval=t, rtol=1e-6, atol=atol)
    assert once.status == 0  # success reported ...
    assert relative_errors(model, t, once.y, y_ex)[0] > 0.1  # ... and the answer is wrong
    chk = stiffness_check(model, "DOP853")
    assert chk["explicit_steps_per_period"] > 500 and chk["advice"]


# ------------------------------------------------------------------ zero damping, long run
def test_zero_damping_no_spurious_energy_growth(heli: Any) -> None:
    """Undamped, constant stiffness, started one static deflection off equilibrium, 100 mesh
    periods (230 natural periods). Must happen: the energy E = m v^2/2 + k (x - x_s)^2/2 stays
    at E0 to 1e-10 with the exact propagator; for the ODE path (smooth form of the same
    stiffness: auto = LSODA) any energy change stays within what the run's estimated error
    states, |dE|/E0 <= 2 (1 + est) est - 2 est is the amplitude error, energy goes as its
    square; DOP853 gains no energy beyond one step's local error and loses some net."""
    k0 = heli.mean_stiffness
    const_pw = PiecewiseStiffness(np.array([0.0, 1.0]),
                                  ((np.array([0.0, 1.0]), np.array([k0, k0])),))
    const_f = FourierStiffness(k0, np.array([0.0]), np.array([0.0]))
    xs = heli.static_load / k0

    def energy(m: Any, y: np.ndarray) -> np.ndarray:
        return 0.5 * m.mass * y[1] ** 2 + 0.5 * k0 * (y[0] - xs) ** 2

    t = grid(heli, 100, 16)
    m_ex = replace(heli, stiffness=const_pw, damping_ratio=0.0)
    y0 = m_ex.initial_state() + np.array([xs, 0.0])
    e0 = float(energy(m_ex, y0))
    y, _ = integrate(m_ex, t, SolverSettings(), y0)
    assert np.max(np.abs(energy(m_ex, y) - e0)) / e0 < 1e-10

    m_ode = replace(heli, stiffness=const_f, damping_ratio=0.0)

    class Shifted:  # the same model started off equilibrium, for simulate()
        def __getattr__(self, name: str) -> Any:
            return getattr(m_ode, name)

        def initial_state(self) -> np.ndarray:
            return y0

    res = simulate(Shifted(), float(t[-1]),
                   SolverSettings(method="LSODA", rtol=1e-7, samples_per_period=16))  # type: ignore[arg-type]
    assert res.stats.method == "LSODA"
    est = res.extra["estimated_error"]["max_rel"]
    drift = np.max(np.abs(energy(m_ode, res.y) - e0)) / e0
    assert drift <= 2 * est * (1 + est), (drift, est)
    y_d, _ = integrate(m_ode, t, SolverSettings(method="DOP853", rtol=1e-7), y0)
    e_d = energy(m_ode, y_d)
    # no growth beyond the local error of one step (~10 rtol), and a net loss by the end
    assert np.max(e_d) <= e0 * (1 + 10 * 1e-7) and e_d[-1] < e0


# ------------------------------------------------------------------ parametric resonance
def exact_monodromy(model: Any) -> np.ndarray:
    """Independent monodromy: product of expm(A_j dt_j) over one mesh period's pieces."""
    phi = np.eye(2)
    for ta, tb, a, _g in model.linear_segments(0.0, 1.0 / model.mesh_frequency):
        phi = expm(a * (tb - ta)) @ phi
    return phi


def test_parametric_resonance_flagged_then_confirmed(heli: Any) -> None:
    """f_m = 2 f_n (mass raised so 2 f_n / f_m = 1), xi = 0.01. Must happen: the Floquet
    multipliers (gear_dyn.analysis.stability, checked against an independent expm product) flag the
    instability before any integration (|mu| > 1; every run summary of a linear single-DOF
    model carries that check and a warning); integration confirms it: the response grows
    by |mu|^N over N periods (exact and LSODA agree with that rate to 2 %) although every
    solver reports success. The helicopter as built (2 f_n / f_m = 4.6) is stable."""
    ratio = 2 * heli.natural_frequency / heli.mesh_frequency
    model = replace(heli, mass=heli.mass * ratio**2, damping_ratio=0.01)
    assert 2 * model.natural_frequency / model.mesh_frequency == pytest.approx(1.0, rel=1e-9)
    mu = np.max(np.abs(floquet_multipliers(model)))
    mu_indep = np.max(np.abs(np.linalg.eigvals(exact_monodromy(model))))
    assert mu == pytest.approx(mu_indep, rel=1e-8)
    assert mu > 1.1  # flagged before integration
    assert np.max(np.abs(floquet_multipliers(heli))) < 1.0
    # every run summary of a linear single-DOF model carries the check and its warning
    short = 4 / model.mesh_frequency
    flag = simulate(model, short, SolverSettings(estimate_error=False)).extra["floquet"]
    assert flag["unstable"] and flag["max_multiplier_modulus"] == pytest.approx(mu, rel=1e-8)
    assert "unstable" in flag["advice"]
    assert not simulate(heli, short, SolverSettings()).extra["floquet"]["unstable"]

    n = 60
    t = grid(model, n, 16)
    per = model.mesh_frequency
    for method in ("exact", "LSODA"):
        y, _ = integrate(model, t, SolverSettings(method=method, rtol=1e-9))
        dev = np.abs(y[0] - model.static_load / model.mean_stiffness)
        # growth over the last 20 periods from the envelope (max over one period at each end);
        # by period 40 the growing mode exceeds the forced periodic response by mu^40 ~ 1e3
        first = np.max(dev[(t >= 39 / per) & (t < 40 / per)])
        last = np.max(dev[(t >= (n - 1) / per)])
        rate = (last / first) ** (1 / (n - 40))
        assert rate == pytest.approx(mu, rel=0.02), (method, rate, mu)


# ------------------------------------------------------------------ backlash, light load
def test_backlash_light_load_events_no_chattering(heli: Any,
                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    """Light load (50 N m, x_s = 0.8 um) with a 50 um half gap and a 5 um transmission error:
    the teeth separate and re-engage every cycle. Must happen: every contact change is located
    (two per mesh cycle) and the solver restarted there, with no step-size collapse (LSODA's
    evaluations per period stay under 3x those of the same run without backlash; measured
    ~1.5x); locating the contact changes makes DOP853 at rtol 1e-9 more accurate than
    stepping over them (measured 7.8e-6 against 4.6e-5 of the static deflection)."""
    te = HarmonicSignal(0.0, np.array([5e-6]), np.array([0.0]))
    # W = T1 / r_b1 with r_b1 = 63.7 mm for the helicopter pinion
    light = replace(heli, static_load=50.0 / 0.0637, backlash=5e-5, transmission_error=te)
    t = grid(light, 10)
    y_ref, st_ref = integrate(light, t, SolverSettings(method="DOP853", rtol=1e-12))
    assert st_ref["n_contact_events"] >= 2 * 10 - 2
    _, st = integrate(light, t, SolverSettings(method="LSODA", rtol=1e-8))
    no_bl = replace(light, backlash=None)
    _, st0 = integrate(no_bl, t, SolverSettings(method="LSODA", rtol=1e-8))
    assert st["nfev"] < 3 * st0["nfev"], (st["nfev"], st0["nfev"])
    y_ev, _ = integrate(light, t, SolverSettings(method="DOP853", rtol=1e-9))
    e_ev = relative_errors(light, t, y_ev, y_ref)[0]
    from gear_dyn.models.sdof import SDOFModel

    monkeypatch.setattr(SDOFModel, "contact_events", lambda self: [])  # step over the kinks
    y_no, st_no = integrate(light, t, SolverSettings(method="DOP853", rtol=1e-9))
    assert "n_contact_events" not in st_no
    e_no = relative_errors(light, t, y_no, y_ref)[0]
    assert e_ev < e_no / 2, (e_ev, e_no)


# ------------------------------------------------------------------ eccentricity ~ backlash
def test_eccentricity_comparable_to_backlash(tmp_path: Any) -> None:
    """The eccentric helical scene (Liu et al. 2017; torsional model, e1 = e2 = 0.2 mm: eccentric
    displacement along the line of action -0.07..+0.26 mm) with a 0.1 mm half gap and a light
    0.2 N m load, one pinion turn (18 mesh periods). Must happen: the teeth separate (the deflection
    falls to ~0.34 b_g) and every contact change is located by the model's contact events (>= 2;
    measured 5); no chattering (LSODA's evaluations stay under 3x those without backlash); the run's
    estimated error bounds its error against a DOP853 rtol-1e-11 reference."""
    text = Path("examples/scenes/eccentric_helical.toml").read_text(encoding="utf-8")
    text = text.replace('torque = "63.662 N*m"', 'torque = "0.2 N*m"')
    text = text.replace("[friction]", '[backlash]\nhalf_gap = "0.1 mm"\n\n[friction]')
    path = tmp_path / "ecc_backlash.toml"
    path.write_text(text, encoding="utf-8")
    model = build_plan(load_scene(path)).model
    assert model.backlash == pytest.approx(1e-4)
    # its rigid-body mode (zero eigenvalues) must not read as stiffness
    assert not stiffness_check(model, "DOP853")["stiff"]
    t = grid(model, 18)
    y_ref, _ = integrate(model, t, SolverSettings(method="DOP853", rtol=1e-11))
    delta = model.outputs(t, y_ref)["delta"]
    assert np.min(delta) < 0.6 * model.backlash  # the teeth really separate
    res = simulate(model, float(t[-1]), SolverSettings(method="LSODA", rtol=1e-7))
    assert res.extra["n_contact_events"] >= 2
    measured = relative_errors(model, t, res.y, y_ref)[0]
    assert measured <= res.extra["estimated_error"]["max_rel"]
    _, st0 = integrate(replace(model, backlash=None), t, SolverSettings(method="LSODA",
                                                                        rtol=1e-7))
    assert res.stats.nfev < 3 * st0["nfev"]
