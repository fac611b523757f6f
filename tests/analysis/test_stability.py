"""Monodromy matrix, periodic steady state, shooting and Floquet multipliers
(gear_dyn.analysis.stability).

References: the steady state against long transient integrations (a second method); Floquet
multipliers of the constant-stiffness oscillator against exp(lambda T) from its closed-form
eigenvalues; instability tongues of the Mathieu equation against the first-order perturbation
result (Nayfeh & Mook 1979, Nonlinear Oscillations, section 5.2.1: for
x'' + w0^2 (1 + eps cos W t) x = 0 the principal tongue is W = 2 w0 (1 -+ eps/4) + O(eps^2)).
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from gear_dyn.analysis.chart import spectral_radius_grid, stability_chart, staircase
from gear_dyn.analysis.stability import (
    floquet_multipliers,
    flow_on_grid,
    one_period_map,
    periodic_steady_state,
    shoot,
)
from gear_dyn.errors import InputError
from gear_dyn.models.sdof import SDOFModel
from gear_dyn.scene import build_plan, load_scene
from gear_dyn.solvers import SolverSettings, integrate
from gear_dyn.stiffness.periodic import FourierStiffness, rectangular_stiffness

SCENES = Path(__file__).resolve().parents[2] / "gear_dyn" / "scenes"


@pytest.fixture(scope="module")
def tail() -> SDOFModel:
    model = build_plan(load_scene(SCENES / "helicopter_tail.toml")).model
    assert isinstance(model, SDOFModel)
    return model


def _last_period(model: SDOFModel, periods: int, settings: SolverSettings, spp: int = 32):
    """States over the last period of a transient from the static state (grid spp/period)."""
    t = np.arange(periods * spp + 1) / (model.mesh_frequency * spp)
    y, _ = integrate(model, t, settings)
    return y[:, -spp - 1:]


def _orbit(model: SDOFModel, y0: np.ndarray, spp: int = 32) -> np.ndarray:
    t = np.arange(spp + 1) / (model.mesh_frequency * spp)
    return flow_on_grid(model, y0, t, rtol=1e-12, atol=1e-16 * model.state_scale)


def test_steady_state_piecewise_constant_equals_long_transient(tail: SDOFModel) -> None:
    sol = periodic_steady_state(tail)
    assert sol.how == "expm" and sol.stable
    # the transient decays like rho^N; rho = 0.42 here, so 40 periods leave < 1e-14 of it
    assert sol.spectral_radius ** 40 < 1e-14
    orbit = _orbit(tail, sol.y0)
    exact = _last_period(tail, 40, SolverSettings(method="exact"))
    scale = tail.state_scale[:, None]
    # exact propagation vs expm product: both exact; the orbit sampled by DOP853 at rtol 1e-12
    assert np.max(np.abs(exact - orbit) / scale) < 1e-10
    dop = _last_period(tail, 40, SolverSettings(method="DOP853", rtol=1e-10))
    # DOP853 at rtol 1e-10 over 80 pieces; errors older than a few periods are damped away
    assert np.max(np.abs(dop - orbit) / scale) < 100 * 1e-10


def test_steady_state_smooth_stiffness_variational(tail: SDOFModel) -> None:
    model = dataclasses.replace(tail, stiffness=tail.stiffness.truncated(5))
    sol = periodic_steady_state(model, rtol=1e-11)
    assert sol.how == "variational" and sol.stable
    orbit = _orbit(model, sol.y0)
    assert sol.spectral_radius ** 40 < 1e-14
    dop = _last_period(model, 40, SolverSettings(method="DOP853", rtol=1e-11))
    # both solve_ivp at rtol 1e-11 (transient: errors older than a few periods damped away)
    assert np.max(np.abs(dop - orbit) / model.state_scale[:, None]) < 100 * 1e-11


def test_shooting_with_backlash_equals_long_transient(tail: SDOFModel) -> None:
    # light load and a backlash: at the scene speed the teeth do not separate, at 3700 rpm
    # (near the f_n / 2 superharmonic) they do; shooting must close the orbit in both
    for speed_rpm in (3319.0, 3900.0):
        fm = 23 * speed_rpm / 60
        model = dataclasses.replace(tail, backlash=50e-6, static_load=tail.static_load / 4,
                                    mesh_frequency=fm)
        sol = periodic_steady_state(model, rtol=1e-10)
        assert sol.converged and sol.how == "shooting" and sol.stable
        orbit = _orbit(model, sol.y0)
        # rho <= 0.6: 80 periods leave < 1e-17 of the transient
        assert sol.spectral_radius ** 80 < 1e-17
        n = 80 * 32
        t = np.arange(n + 1) / (fm * 32)
        tr = flow_on_grid(model, model.initial_state(), t, 1e-10)[:, -33:]
        # rtol 1e-10 per piece; the dead-zone kinks cost the integrator some accuracy
        assert np.max(np.abs(tr - orbit) / model.state_scale[:, None]) < 100 * 1e-10
        if speed_rpm == 3900.0:
            x = orbit[0]
            assert np.min(x) < model.backlash < np.max(x)  # separation really happens
        # the orbit's multipliers from the shooting Jacobian (variational equations, rtol
        # 1e-10) against central differences of the one-period map (second method). Both flows
        # restart at every contact change, so the map is smooth on each side of the kink and
        # the difference error is ~ rtol_fd / h + h^2 = 1e-12 / 1e-5 + 1e-10 ~ 1e-7; the
        # variational Jacobian is good to ~1e-9. Tolerance 1e-5: 100x the larger of the two.
        # (Measured: 7e-11 and 1e-10 at 3900 and 3319 rpm.)
        h = 1e-5 * model.state_scale
        t = np.array([0.0, 1 / fm])
        jac = np.empty((2, 2))
        for j in range(2):
            e = np.zeros(2)
            e[j] = h[j]
            yp = flow_on_grid(model, sol.y0 + e, t, 1e-12, 1e-17 * model.state_scale)[:, -1]
            ym = flow_on_grid(model, sol.y0 - e, t, 1e-12, 1e-17 * model.state_scale)[:, -1]
            jac[:, j] = (yp - ym) / (2 * h[j])
        mu_fd = np.sort(np.abs(np.linalg.eigvals(jac)))
        assert np.allclose(np.sort(np.abs(sol.multipliers)), mu_fd, rtol=1e-5, atol=0.0)


def test_floquet_constant_stiffness_closed_form() -> None:
    m, k, zeta, fm = 2.5, 4e8, 0.05, 1500.0
    wn = math.sqrt(k / m)
    lam = complex(-zeta * wn, wn * math.sqrt(1 - zeta**2))
    expected = np.sort_complex(np.exp(np.array([lam, lam.conjugate()]) / fm))
    for stiff, tol in ((rectangular_stiffness(1.6, k, k), 1e-12),
                       (FourierStiffness(k, np.array([0.0]), np.array([0.0])), 1e-8)):
        model = SDOFModel(m, stiff, zeta, 1e3, fm)
        mu = np.sort_complex(floquet_multipliers(model, rtol=1e-12))
        # expm product: rounding only; variational solve_ivp at rtol 1e-12: ~1e-10 relative
        assert np.allclose(mu, expected, rtol=0, atol=tol)


def _mathieu(eps: float, ratio: float) -> SDOFModel:
    """x'' + w0^2 (1 + eps cos W t) x = 0 with W = ratio * 2 w0 (undamped)."""
    w0 = 2 * math.pi * 1000.0
    k0 = w0**2  # mass 1 kg
    stiff = FourierStiffness(k0, np.array([eps * k0]), np.array([0.0]))
    return SDOFModel(1.0, stiff, 0.0, 0.0, ratio * 2 * w0 / (2 * math.pi))


@pytest.mark.parametrize("eps", [0.1, 0.2])
def test_mathieu_principal_tongue(eps: float) -> None:
    # Nayfeh & Mook: unstable for |W / (2 w0) - 1| < eps / 4 (first order). Points at half and
    # one and a half of the half-width: the O(eps^2) corrections (eps^2 / 32 < 0.0013) are far
    # smaller than the margins (eps / 8 >= 0.0125).
    half = eps / 4
    for offset, unstable in ((0.0, True), (0.5, True), (-0.5, True), (1.5, False),
                             (-1.5, False)):
        mu = floquet_multipliers(_mathieu(eps, 1 + offset * half), rtol=1e-11)
        rho = float(np.max(np.abs(mu)))
        if unstable:
            assert rho > 1 + 1e-3
        else:
            # undamped and stable: multipliers on the unit circle (conservative system)
            assert abs(rho - 1) < 1e-7
        # Liouville: det(monodromy) = exp(-trace of damping) = 1 without damping
        assert abs(np.prod(mu) - 1) < 1e-7


def test_rectangular_wave_tongue_from_first_harmonic() -> None:
    # rectangular wave k_double on [0, f), k_single after: first harmonic amplitude
    # (2 / pi) (k_double - k_single) sin(pi f); relative to the mean it plays eps
    f, ks = 0.6, 1e8
    kd = 1.08 * ks
    stiff = rectangular_stiffness(1 + f, ks, kd)
    k0 = stiff.mean
    eps = 2 / math.pi * (kd - ks) * math.sin(math.pi * f) / k0
    _, a, b = stiff.fourier_coefficients(1)
    assert math.hypot(a[0], b[0]) / k0 == pytest.approx(eps, rel=1e-12)
    w0 = math.sqrt(k0)  # mass 1 kg
    half = eps / 4
    for offset, unstable in ((0.0, True), (0.6, True), (-0.6, True), (1.6, False),
                             (-1.6, False)):
        model = SDOFModel(1.0, stiff, 0.0, 0.0, (1 + offset * half) * 2 * w0 / (2 * math.pi))
        sol = periodic_steady_state(model)
        assert sol.how == "expm"
        assert sol.stable is (not unstable)
        if unstable:
            assert sol.spectral_radius > 1 + 1e-3


def test_unstable_flag_matches_growth_of_the_transient() -> None:
    # inside the tongue the free response grows by rho per period: the exact propagator over
    # 40 periods must show rho^40 (independent check of the flag)
    model = _mathieu(0.2, 1.0)
    rho = float(np.max(np.abs(floquet_multipliers(model, rtol=1e-12))))
    y0 = np.array([1e-6, 0.0])
    t = np.array([0.0, 40 / model.mesh_frequency])
    y = flow_on_grid(model, y0, np.linspace(t[0], t[1], 40 * 16 + 1), 1e-12, 1e-20)
    amp = lambda s: np.max(np.abs(y[0, s]))  # noqa: E731
    growth = amp(slice(-16, None)) / amp(slice(16 * 20, 16 * 21))
    # over 19 periods the dominant multiplier takes over (the other decays like 1/rho^19)
    assert growth == pytest.approx(rho ** 19, rel=0.05)


def test_stability_chart_matches_monodromy(tail: SDOFModel) -> None:
    ratios = np.array([0.5, 1.0, 1.95, 2.1])
    chart = stability_chart(tail, ratios, np.array([0.1, 0.3]))
    edges, vals = staircase(tail)
    eps0 = (vals.max() - vals.min()) / (2 * tail.mean_stiffness)
    assert chart.scene_value == pytest.approx(eps0, rel=1e-12)
    for i, eps in enumerate(chart.parameter):
        scaled = tail.mean_stiffness + eps / eps0 * (vals - tail.mean_stiffness)
        stiff = rectangular_stiffness(1 + edges[1], scaled[1], scaled[0])
        for j, r in enumerate(ratios):
            model = dataclasses.replace(tail, stiffness=stiff,
                                        mesh_frequency=r * chart.natural_frequency)
            # the scaled wave keeps the mean, so damping and f_n are the scene's
            assert model.damping == pytest.approx(tail.damping, rel=1e-12)
            rho = np.max(np.abs(floquet_multipliers(model)))
            # closed-form 2x2 exponentials vs scipy expm of the augmented matrices
            assert chart.spectral_radius[i, j] == pytest.approx(rho, rel=1e-10)
    # the scene itself (eps0 ~ 0.27 > 4 zeta = 0.24) has a principal tongue near f_m = 2 f_n
    at_scene = stability_chart(tail, np.array([1.0, 1.98]), np.array([eps0]))
    assert at_scene.spectral_radius[0, 0] < 1 < at_scene.spectral_radius[0, 1]
    damp = stability_chart(tail, np.array([1.98]), np.array([0.0, 0.06, 0.2]),
                           parameter_name="damping_ratio")
    assert damp.spectral_radius[0, 0] > damp.spectral_radius[1, 0] > 1 > damp.spectral_radius[
        2, 0]


def test_spectral_radius_grid_broadcasts() -> None:
    edges = np.array([0.0, 0.4, 1.0])
    vals = np.array([1.2e8, 1.0e8])
    fm = np.linspace(500, 5000, 7)
    rho = spectral_radius_grid(1.0, edges, vals, np.asarray(50.0), fm)
    assert rho.shape == fm.shape
    for r, f in zip(rho, fm, strict=True):
        model = SDOFModel(1.0, rectangular_stiffness(1.4, 1.0e8, 1.2e8),
                          50.0 / (2 * math.sqrt(rectangular_stiffness(1.4, 1e8, 1.2e8).mean)),
                          0.0, f)
        assert r == pytest.approx(np.max(np.abs(floquet_multipliers(model))), rel=1e-10)


def test_errors(tail: SDOFModel) -> None:
    with pytest.raises(InputError, match="backlash"):
        one_period_map(dataclasses.replace(tail, backlash=1e-5))
    with pytest.raises(InputError, match="sdof"):
        periodic_steady_state(object())  # type: ignore[arg-type]
    with pytest.raises(InputError, match="rtol"):
        periodic_steady_state(tail, rtol=1.0)
    with pytest.raises(InputError, match="damping_ratio"):
        stability_chart(tail, np.array([1.0]), np.array([0.1]), parameter_name="damping")
    with pytest.raises(InputError, match="keeps the stiffness"):
        stability_chart(tail, np.array([1.0]), np.array([5.0]))
    # shooting from far away (a 1 mm deflection, 40x the static one) with two iterations cannot
    # close the orbit: it must say so (converged False, after its two iterations, with a
    # residual above its own convergence threshold 100 rtol)
    model = dataclasses.replace(tail, backlash=1e-5)
    sol = shoot(model, np.array([1e-3, 0.0]), max_iter=2)
    assert sol.converged is False
    assert sol.iterations == 2 and sol.residual > 100 * 1e-10


def test_stability_chart_staircase_of_smooth_stiffness(tail: SDOFModel) -> None:
    # a Fourier stiffness is charted on a 128-cell staircase; its multipliers converge like
    # cells^-2 (measured: 2e-4 where they are real, rounding where complex: their modulus is
    # exp(-zeta w_n T) whatever k(t)), against the variational monodromy at rtol 1e-11
    model = dataclasses.replace(tail, stiffness=tail.stiffness.truncated(5))
    edges, vals = staircase(model)
    assert edges.size == 129
    # Simpson cell means keep the mean stiffness to ~(1/128)^4
    assert abs(np.sum(vals * np.diff(edges)) / model.mean_stiffness - 1) < 1e-6
    eps0 = (vals.max() - vals.min()) / (2 * model.mean_stiffness)
    ratios = np.array([0.6, 1.0, 1.5, 1.97])
    chart = stability_chart(model, ratios, np.array([eps0]))
    for j, r in enumerate(ratios):
        m = dataclasses.replace(model, mesh_frequency=r * chart.natural_frequency)
        rho = np.max(np.abs(floquet_multipliers(m, rtol=1e-11)))
        assert chart.spectral_radius[0, j] == pytest.approx(rho, rel=1e-3)
