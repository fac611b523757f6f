"""Single-DOF model and its integration against closed forms (Jiang et al. 2018)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gear_dyn.analysis.report import dominant_peak
from gear_dyn.analysis.study import simulate
from gear_dyn.excitation import HarmonicSignal
from gear_dyn.geometry import GearPair
from gear_dyn.models.sdof import SDOFModel, effective_mass, sdof_from_pair
from gear_dyn.solvers import SolverSettings, integrate, time_grid
from gear_dyn.stiffness import iso6336_stiffness, rectangular_stiffness

M, K, W, XI, FM = 0.5, 4e8, 1e4, 0.05, 1000.0


def constant_model(xi: float = XI) -> SDOFModel:
    k = rectangular_stiffness(1.6, K, K)  # equal values: constant stiffness, one piece
    return SDOFModel(mass=M, stiffness=k, damping_ratio=xi, static_load=W, mesh_frequency=FM)


def closed_form_step(t: np.ndarray, xi: float = XI) -> np.ndarray:
    """Under-damped step response from rest: x = W/k (1 - e^{-xi wn t}(cos wd t + xi/sqrt(1-xi^2)
    sin wd t)) (any vibration text, e.g. Rao, Mechanical Vibrations, eq. 4.xx)."""
    wn = math.sqrt(K / M)
    wd = wn * math.sqrt(1 - xi**2)
    return W / K * (1 - np.exp(-xi * wn * t) * (np.cos(wd * t) + xi / math.sqrt(1 - xi**2)
                                                 * np.sin(wd * t)))


@pytest.mark.parametrize(("method", "rtol"), [("DOP853", 1e-9), ("LSODA", 1e-9), ("Radau", 1e-7),
                                              ("RK45", 1e-7), ("exact", 1e-8)])
def test_constant_stiffness_matches_closed_form(method: str, rtol: float) -> None:
    """Step response from rest against the closed form.

    Error scaled as in scipy's own tests: |x - x_true| / (atol + rtol |x_true|) with atol =
    rtol * W/k; a global error of a few tens of local tolerances is what a well-behaved
    integrator delivers over ~60 oscillations (bound 200). The exact propagator has only
    rounding: bound 1e-11 of W/k.
    """
    model = constant_model()
    t = time_grid(FM, 0.01, 64)
    y, stats = integrate(model, t, SolverSettings(method=method, rtol=rtol), y0=np.zeros(2))
    x_true = closed_form_step(t)
    if method == "exact":
        assert np.max(np.abs(y[0] - x_true)) < 1e-11 * W / K
    else:
        scaled = np.abs(y[0] - x_true) / (rtol * W / K + rtol * np.abs(x_true))
        assert scaled.max() < 200
        assert stats["nfev"] < 200_000


def test_mean_dte_equals_static_deflection_for_constant_stiffness() -> None:
    """With constant k the steady mean DTE is W/k (static equilibrium), to the solver tolerance."""
    model = constant_model()
    res = simulate(model, 0.05, SolverSettings(method="DOP853", rtol=1e-10))
    assert res.mean_dte == pytest.approx(W / K, rel=1e-8)
    # started from the static deflection, nothing moves: the DTE fluctuation is rounding only
    assert res.rms_dte < 1e-9 * W / K
    assert res.dynamic_factor == pytest.approx(1.0, rel=1e-8)


def test_effective_mass_formula() -> None:
    """m_e = I1 I2 / (rb1^2 I2 + rb2^2 I1): equal gears give I / (2 rb^2)."""
    assert effective_mass(2.0, 2.0, 0.1, 0.1) == pytest.approx(2.0 / (2 * 0.01), rel=1e-14)


def test_piecewise_integration_agrees_with_exact_on_rectangular_wave(heli_pair: GearPair) -> None:
    """Helicopter tail, rectangular ISO wave: DOP853 (restarted at every jump) vs the exact
    propagator over 15 mesh periods. Error relative to the static deflection must be below
    1e-6 at rtol 1e-10 (global error ~ tens of local tolerances)."""
    iso = iso6336_stiffness(heli_pair)
    k = rectangular_stiffness(heli_pair.contact_ratio, iso.k_single, 1.75 * iso.k_single)
    model = sdof_from_pair(heli_pair, 3319 * math.pi / 30, 1474.4, k)
    t_end = 15 / model.mesh_frequency
    ex = simulate(model, t_end, SolverSettings(method="exact"))
    ode = simulate(model, t_end, SolverSettings(method="DOP853", rtol=1e-10))
    err = np.max(np.abs(ex.y[0] - ode.y[0])) / model.static_deflection
    assert err < 1e-6
    assert ode.stats.n_segments == ex.stats.n_segments


def test_helicopter_tail_spectrum_peaks_at_mesh_harmonic(heli_pair: GearPair) -> None:
    """The largest non-DC peak of the DTE spectrum sits at f_m or a harmonic (within one bin)."""
    iso = iso6336_stiffness(heli_pair)
    k = rectangular_stiffness(heli_pair.contact_ratio, iso.k_single, 1.75 * iso.k_single)
    model = sdof_from_pair(heli_pair, 3319 * math.pi / 30, 1474.4, k)
    res = simulate(model, 200 / model.mesh_frequency, SolverSettings(method="exact"))
    f, _ = dominant_peak(res)
    n = round(f / model.mesh_frequency)
    bin_width = 1 / (res.t[res.steady][-1] - res.t[res.steady][0])
    assert n >= 1
    assert abs(f - n * model.mesh_frequency) < bin_width


def test_backlash_off_is_bit_for_bit_linear() -> None:
    """A model built without backlash runs the linear right-hand side exactly; with a backlash
    whose gap is never reached in the negative direction, the response is the linear one
    shifted by the half gap (to the solver tolerance)."""
    k = rectangular_stiffness(1.6, 3e8, 5e8)
    lin = SDOFModel(mass=M, stiffness=k, damping_ratio=XI, static_load=W, mesh_frequency=FM)
    lin2 = SDOFModel(mass=M, stiffness=k, damping_ratio=XI, static_load=W, mesh_frequency=FM,
                     backlash=None)
    s = SolverSettings(method="DOP853", rtol=1e-10)
    a = simulate(lin, 0.006, s)
    b = simulate(lin2, 0.006, s)
    assert np.array_equal(a.y, b.y)
    gap = 1e-7
    bl = SDOFModel(mass=M, stiffness=k, damping_ratio=XI, static_load=W, mesh_frequency=FM,
                   backlash=gap)
    c = simulate(bl, 0.006, s)
    assert np.all(c.y[0] > gap)  # always in contact
    assert np.max(np.abs(c.y[0] - gap - a.y[0])) < 1e-7 * lin.static_deflection


def test_transmission_error_shifts_mean_and_excites_mesh_frequency() -> None:
    """Constant stiffness + e(t) = e1 cos(2 pi f_m t): the linear response is the harmonic
    transfer of the excitation. x'' + 2 xi wn x' + wn^2 x = W/m + wn^2 e + 2 xi wn e', so the
    steady amplitude at f_m is e1 |wn^2 + 2i xi wn w| / |wn^2 - w^2 + 2i xi wn w| (closed form),
    tolerance 1e-3 (Hann window on an integer number of periods: amplitude exact to rounding,
    solver 1e-10)."""
    e1 = 2e-6
    k = rectangular_stiffness(1.6, K, K)
    model = SDOFModel(mass=M, stiffness=k, damping_ratio=XI, static_load=W, mesh_frequency=FM,
                      transmission_error=HarmonicSignal(0.0, np.array([e1]), np.array([0.0])))
    res = simulate(model, 0.05, SolverSettings(method="DOP853", rtol=1e-10), steady_start=0.025)
    from gear_dyn.analysis.spectrum import amplitude_spectrum

    f, amp = amplitude_spectrum(res.t[res.steady][:-1], res.outputs["dte"][res.steady][:-1])
    i = int(np.argmin(np.abs(f - FM)))
    wn = math.sqrt(K / M)
    w = 2 * math.pi * FM
    expect = e1 * abs(complex(wn**2, 2 * XI * wn * w)) / abs(complex(wn**2 - w**2, 2 * XI * wn * w))
    assert amp[i] == pytest.approx(expect, rel=1e-3)
    # mean over whole periods (drop the closing sample): W/k to the solver tolerance
    assert np.mean(res.outputs["dte"][res.steady][:-1]) == pytest.approx(W / K, rel=1e-7)
