"""The deviations as excitation and the tolerance study, against closed forms, a time
integration and the Monte-Carlo error it states."""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any, cast

import numpy as np
import pytest

from gear_dyn.analysis.tolerance import (
    Coefficients,
    quantile_stderr,
    sample_figures,
    tolerance_study,
    unit_responses,
)
from gear_dyn.errors import InputError
from gear_dyn.excitation import HarmonicSignal
from gear_dyn.models.base import MeshModel
from gear_dyn.modification.deviations import PairDeviations, pair_tolerances, sample_deviations
from gear_dyn.scene import build_pair
from gear_dyn.scene.sweep import SceneModels
from gear_dyn.scene.tolerance import tolerance_scene
from gear_dyn.solvers import SolverSettings, integrate
from tests.scene_cases import edited_scene

RPM = 2 * math.pi / 60
K_CONST = 1.2e9  # N/m, a constant mesh stiffness (rectangular wave with single = double)


def constant_scene(**changes: Any) -> Any:
    return edited_scene("helicopter_tail", stiffness={"method": "rectangular",
                                                      "single": K_CONST, "double": K_CONST},
                        **changes)


def closed_form(model: MeshModel, order: float) -> tuple[complex, complex]:
    """x / e and F / e of a constant-stiffness model for e = e^{i Omega t}: with u = x - e,
    (k - m W^2 + i c W) u = m W^2 e."""
    om = 2 * math.pi * order * model.mesh_frequency
    k, m, c = model.mean_stiffness, model.mass, model.damping
    u = m * om**2 / (k - m * om**2 + 1j * c * om)
    return 1 + u, (k + 1j * c * om) * u


def test_unit_responses_match_the_closed_form_of_a_constant_stiffness_model() -> None:
    scene = constant_scene()
    model = cast(MeshModel, SceneModels.of(scene)(3319 * RPM))
    orders = np.array([1 / 23, 5 / 23, 1 / 64, 31 / 64, 1.0, 2.0])
    spp = 16
    r = unit_responses(model, orders, spp)
    f_w, x_w, f_q, x_q = r.force_w, r.dte_w, r.force_q, r.dte_q
    t = np.arange(spp) / (spp * model.mesh_frequency)
    assert r.rho < 1
    np.testing.assert_allclose(f_w, model.static_load, rtol=1e-12)
    np.testing.assert_allclose(x_w, model.static_load / K_CONST, rtol=1e-12)
    for i, q in enumerate(orders):
        hx, hf = closed_form(model, q)
        rot = np.exp(2j * math.pi * q * model.mesh_frequency * t)
        # exact cell propagation: rounding only (1e-9 of the response's scale)
        np.testing.assert_allclose(x_q[i], hx * rot, atol=1e-9 * abs(hx))
        np.testing.assert_allclose(f_q[i], hf * rot, atol=1e-9 * abs(hf))


def _pattern_sample(z1: int, z2: int) -> tuple[PairDeviations, np.ndarray]:
    """A deterministic pinion pattern (a sawtooth of 4 teeth with a 3 um step at tooth 7), no
    gear deviations, no profile harmonic; and its Fourier coefficients, summed directly."""
    i = np.arange(z1)
    v = 1e-6 * ((i % 4) - 1.5 + 3.0 * (i >= 7))
    k = np.arange(1, z1 // 2 + 1)
    coef = 2 / z1 * np.exp(-2j * math.pi * np.outer(k, i) / z1) @ (v - v.mean())
    return PairDeviations(z1, z2, v, np.zeros(z2), 0j), coef


def test_pitch_pattern_gives_shaft_order_lines_of_the_fourier_series_through_the_model() -> None:
    """A time integration of the model excited by the pattern: the DTE spectrum over one pinion
    revolution has lines at the pinion's shaft orders, of amplitude |x/e| |C_k| (closed form),
    and the tolerance study's RMS DTE and peak force agree with the same lines."""
    scene = constant_scene()
    factory = SceneModels.of(scene)
    base = cast(MeshModel, factory(3319 * RPM))
    dev, coef = _pattern_sample(23, 64)
    full = replace(base, transmission_error=dev.transmission_error())
    assert not full.mesh_periodic and full.excitation_period == 23 * 64
    # the gear and profile parts are zero: integrate with the pinion's part alone (cheaper)
    model = replace(base, transmission_error=dev.signals()[0])
    spp = 32
    k = np.arange(1, 12)
    hx = np.array([closed_form(model, kk / 23)[0] for kk in k])
    om = 2 * math.pi * k / 23 * model.mesh_frequency
    # one revolution from the closed form's periodic state (a wrong state leaves a transient)
    y0 = [model.static_load / K_CONST + np.real(np.sum(coef * hx)),
          np.real(np.sum(coef * hx * 1j * om))]
    t = np.arange(23 * spp + 1) / (spp * model.mesh_frequency)
    y, _ = integrate(model, t, SolverSettings(method="DOP853", rtol=1e-10), np.array(y0))
    x = y[0, :-1]
    spec = np.fft.rfft(x) * 2 / x.size
    expected = np.abs(hx * coef[k - 1])
    # integration at rtol 1e-10 and an exact-period window: errors far below 1e-4 of a line
    np.testing.assert_allclose(np.abs(spec[k]), expected, atol=1e-4 * expected.max())
    others = np.delete(np.abs(spec[1:]), k - 1)  # no line away from the shaft orders 1..11
    assert others.max() < 1e-4 * expected.max()
    # the study: RMS by Parseval over the lines; peak force against the integration
    res = sample_figures(cast(MeshModel, factory(3319 * RPM)), Coefficients.of([dev]), 23, 64,
                         spp)
    assert res["rms_dte"][0] == pytest.approx(math.sqrt(np.sum(expected**2) / 2), rel=1e-6)
    force = model.outputs(t[:-1], y[:, :-1])["mesh_force"]
    assert res["peak_force"][0] == pytest.approx(force.max(), rel=1e-6)


def test_gear_residues_over_the_hunting_period_match_brute_force() -> None:
    """z1 = 23, z2 = 46 (gcd 23): the peak and RMS taken by residues equal the figures of the
    closed-form response evaluated over every mesh cycle of the hunting period."""
    scene = constant_scene(gear={"teeth_gear": 46})
    pair = build_pair(scene)
    model = cast(MeshModel, SceneModels.of(scene)(5000 * RPM))
    dev = sample_deviations(pair, pair_tolerances(pair, 7), "random", [5, 0])
    spp = 8
    res = sample_figures(model, Coefficients.of([dev]), 23, 46, spp)
    p = np.arange(46 * spp) / spp  # the hunting period, lcm(23, 46) = 46 mesh cycles
    x = np.full(p.size, model.static_load / K_CONST)
    f = np.full(p.size, model.static_load)
    for sig in dev.signals():
        for n, (a, b) in enumerate(zip(sig.cos, sig.sin, strict=True), start=1):
            hx, hf = closed_form(model, n / sig.period)
            rot = (a - 1j * b) * np.exp(2j * math.pi * n * p / sig.period)
            x += np.real(hx * rot)
            f += np.real(hf * rot)
    assert res["peak_force"][0] == pytest.approx(f.max(), rel=1e-9)
    assert res["min_force"][0] == pytest.approx(f.min(), rel=1e-9)
    assert res["rms_dte"][0] == pytest.approx(x.std(), rel=1e-7)


def test_shaft_order_response_with_varying_stiffness_matches_a_time_integration() -> None:
    """ISO 6336 rectangular stiffness: the quasi-periodic response to one pinion shaft order
    (with its sidebands about the mesh harmonics) against DOP853 from the method's state."""
    factory = SceneModels.of(edited_scene("helicopter_tail"))
    base = cast(MeshModel, factory(4000 * RPM))
    spp = 32
    amp = np.zeros(3)
    amp[2] = 5e-6  # 5 um at shaft order 3
    te = HarmonicSignal(0.0, amp, 0.5 * amp, period=23)
    model = replace(base, transmission_error=te)
    r = unit_responses(base, np.array([3 / 23]), spp)
    f_w, x_w, f_q, x_q = r.force_w, r.dte_w, r.force_q, r.dte_q
    c = 5e-6 - 0.5j * 5e-6
    # from the state the method gives, the true flow must stay on its response for the next
    # periods (a wrong state leaves a transient of the size of the response, decaying by
    # e^-0.7 per mesh period)
    periods = 8
    y0 = r.start_w + np.real(c * r.start_q[:, 0])
    t = np.arange(periods * spp + 1) / (spp * model.mesh_frequency)
    y, _ = integrate(model, t, SolverSettings(method="DOP853", rtol=1e-10), y0)
    out = model.outputs(t[:-1], y[:, :-1])
    n = np.arange(periods)[:, None]
    lam = np.exp(2j * math.pi * 3 * n / 23)
    x = (x_w[None, :] + np.real(c * lam * x_q[0][None, :])).ravel()
    f = (f_w[None, :] + np.real(c * lam * f_q[0][None, :])).ravel()
    scale_x = np.ptp(x)
    np.testing.assert_allclose(out["dte"], x, atol=1e-6 * scale_x)
    # the force jumps with k at the switches; a sample on a switch (phase 0 of every period
    # here) may read k on either side, by the rounding of its phase: compare the others
    k_s = np.tile(np.asarray(base.stiffness(np.arange(spp) / spp)), periods)
    same = out["stiffness"] == k_s
    assert same.mean() > 0.9
    np.testing.assert_allclose(out["mesh_force"][same], f[same], atol=1e-5 * model.static_load)


def test_deviations_raise_the_resonance_and_k_dyn_tends_to_one_at_low_speed() -> None:
    scene = constant_scene()
    pair = build_pair(scene)
    factory = SceneModels.of(scene)
    model = cast(MeshModel, factory(3319 * RPM))
    fn = model.natural_frequency
    to_speed = 2 * math.pi / pair.z1
    dev = sample_deviations(pair, pair_tolerances(pair, 8), "sine")
    low, res = fn / 50 * to_speed, fn * to_speed
    out = tolerance_study(factory, [low, res], [dev], samples_per_period=32)
    k_dyn = out.values["k_dyn"][0]
    assert out.quasi_static_peak_ratio == pytest.approx(1.0, abs=1e-6)  # constant stiffness
    assert out.baseline["k_dyn"] == pytest.approx([1.0, 1.0], abs=1e-6)
    assert k_dyn[1] > 1.5  # at resonance the deviations' orders near f_n ring up
    # at f_m = f_n / 50 the forcing -m e'' of every order q adds at most
    # sum |C_q| k (q f_m / f_n)^2 / (1 - (q f_m / f_n)^2) to the force
    bound = 0.0
    for sig in dev.signals():
        q = np.arange(1, sig.cos.size + 1) / sig.period / 50
        bound += float(np.sum(np.hypot(sig.cos, sig.sin) * K_CONST * q**2 / (1 - q**2)))
    assert 1.0 <= k_dyn[0] <= 1.0 + 1.01 * bound / model.static_load
    assert bound / model.static_load < 0.01




def test_monte_carlo_error_narrows_as_one_over_sqrt_n_as_stated() -> None:
    """40 independent studies of N = 16 and of N = 64 samples at one speed near resonance:
    the scatter of their mean peak force matches the standard error they state (std/sqrt N),
    and it halves when N grows fourfold. The scatter of 40 estimates is itself uncertain by
    1/sqrt(2 x 39) = 11 %: the bounds allow about three of those."""
    scene = edited_scene("helicopter_tail")
    pair = build_pair(scene)
    model = cast(MeshModel, SceneModels.of(scene)(6500 * RPM))
    tol = pair_tolerances(pair, 6)
    reps, sizes = 40, (16, 64)
    devs = [sample_deviations(pair, tol, "random", [1000 + r, n, i])
            for n in sizes for r in range(reps) for i in range(n)]
    peak = sample_figures(model, Coefficients.of(devs), pair.z1, pair.z2, 16)["peak_force"]
    scatter, stated, med_scatter, med_stated = {}, {}, {}, {}
    for n in sizes:
        first = 0 if n == sizes[0] else reps * sizes[0]
        runs = peak[first:first + reps * n].reshape(reps, n)
        scatter[n] = runs.mean(axis=1).std(ddof=1)
        stated[n] = np.mean(runs.std(axis=1, ddof=1) / math.sqrt(n))
        med_scatter[n] = np.median(runs, axis=1).std(ddof=1)
        med_stated[n] = np.mean([quantile_stderr(r[:, None], 0.5)[0] for r in runs])
        assert 0.65 < scatter[n] / stated[n] < 1.5
        assert 0.5 < med_scatter[n] / med_stated[n] < 2.0  # order-statistic estimate
    assert 1.4 < scatter[16] / scatter[64] < 2.9  # sqrt(64 / 16) = 2
    assert 1.4 < stated[16] / stated[64] < 2.9


def test_local_and_dask_runs_give_the_same_numbers() -> None:
    from distributed import Client, LocalCluster

    scene = edited_scene("helicopter_tail")
    speeds = "4000 rpm:8000 rpm:12"
    serial = tolerance_scene(scene, speeds, samples=6, grade=7, samples_per_period=16)
    with LocalCluster(n_workers=1, processes=False, threads_per_worker=2,
                      dashboard_address=":0") as cluster, Client(cluster) as client:
        remote = tolerance_scene(scene, speeds, samples=6, grade=7, samples_per_period=16,
                                 executor=client.get_executor())
    assert remote.executor == "ClientExecutor" and serial.executor == "serial"
    for name, v in serial.values.items():
        np.testing.assert_array_equal(v, remote.values[name])
    assert serial.seeds == remote.seeds == [[1, i] for i in range(6)]


def test_the_study_refuses_what_it_does_not_cover() -> None:
    with pytest.raises(InputError, match="piecewise-constant stiffness"):
        tolerance_scene(edited_scene("helicopter_tail", stiffness={"method": "weber"}),
                        ["3000 rpm"], samples=2, grade=6)
    with pytest.raises(InputError, match="no backlash"):
        tolerance_scene(edited_scene("helicopter_tail_backlash"), ["3000 rpm"], samples=2,
                        grade=6)
    with pytest.raises(InputError, match="samples"):
        tolerance_scene(edited_scene("helicopter_tail"), ["3000 rpm"], samples=0, grade=6)


def test_the_grade_sets_the_response_linearly() -> None:
    """Grades 4 and 8 of the deterministic pattern (every tolerance a factor 4 apart): the
    deviations' share of the RMS DTE, sqrt(rms^2 - rms_0^2), is a factor 4 apart at every
    speed (the response is linear, and with constant stiffness the load's response is a
    constant, so the shares add in square)."""
    scene = constant_scene()
    pair = build_pair(scene)
    factory = SceneModels.of(scene)
    devs = [sample_deviations(pair, pair_tolerances(pair, g), "sine") for g in (4, 8)]
    speeds = np.array([2000.0, 5000.0, 7600.0]) * RPM
    out = tolerance_study(factory, speeds, devs, samples_per_period=16)
    base = out.baseline["rms_dte"]
    share = np.sqrt(out.values["rms_dte"] ** 2 - base**2)
    np.testing.assert_allclose(share[1] / share[0], 4.0, rtol=1e-6)
    assert np.all(out.values["peak_force"][1] > out.values["peak_force"][0])


def test_without_deviations_the_study_is_the_sweep() -> None:
    """The study's response without deviations (its baseline) is the steady sweep's: K_dyn and
    RMS DTE at the same speeds, with the same quasi-static reference (both exact cells:
    rounding only)."""
    from gear_dyn.scene.sweep import sweep_scene

    scene = edited_scene("helicopter_tail")
    speeds = "2000 rpm:9000 rpm:4"
    study = tolerance_scene(scene, speeds, samples=1, grade=6)
    curve = sweep_scene(scene, speeds).curves[0]
    np.testing.assert_allclose(study.baseline["k_dyn"], curve.dynamic_factor, rtol=1e-12)
    np.testing.assert_allclose(study.baseline["rms_dte"], curve.rms_dte, rtol=1e-12)
