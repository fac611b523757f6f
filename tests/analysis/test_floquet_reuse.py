"""The Floquet check of a periodic run reuses the run's own step maps (no integration).

Two routes to the largest Floquet multiplier: the reused one (the product of the run's step maps,
Magnus substeps in the compiled kernel, its ``multiplier_error`` measured against Gauss-Legendre
collocation maps) and the independent one it replaced (the variational equations over one period by
DOP853, ``floquet_multipliers``, here at rtol 1e-13). They must agree within the stated error, and
that error must be at least 10 times the variational route's own error (its change from rtol 1e-12
to 1e-13), so that the comparison tests the stated figure, not the reference.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
import pytest

from gear_dyn.analysis.accuracy import multiplier_distance, relative_errors
from gear_dyn.analysis.bench import reference_solution
from gear_dyn.analysis.stability import floquet_multipliers, period_map
from gear_dyn.analysis.study import simulate
from gear_dyn.excitation import HarmonicSignal
from gear_dyn.scene import load_scene
from gear_dyn.scene.build import build_plan
from gear_dyn.solvers import SolverSettings, time_grid
from gear_dyn.stiffness.periodic import PiecewiseStiffness

SCENE = "examples/scenes/helicopter_tail.toml"


@pytest.fixture(scope="module")
def heli() -> Any:
    return build_plan(load_scene(SCENE)).model


def fourier(heli: Any) -> Any:
    """The 5-term Fourier stiffness of Jiang et al. (2018) (smooth: auto takes the periodic step
    maps)."""
    return replace(heli, stiffness=heli.stiffness.truncated(5))


def resonant(heli: Any) -> Any:
    """The Fourier pair with 2 f_n / f_m = 1 and xi = 0.01: parametrically unstable."""
    model = fourier(heli)
    ratio = 2 * model.natural_frequency / model.mesh_frequency
    return replace(model, mass=model.mass * ratio**2, damping_ratio=0.01)


def pwl_te(heli: Any) -> Any:
    """Piecewise-linear stiffness with jumps plus a transmission error (maps cut at the
    switching instants)."""
    pwl = PiecewiseStiffness(
        np.array([0.0, 0.3, 1.0]),
        ((np.array([0.0, 0.15, 0.3]), np.array([1.2e9, 1.3e9, 1.25e9])),
         (np.array([0.3, 1.0]), np.array([0.7e9, 0.75e9]))))
    te = HarmonicSignal(0.0, np.array([2e-6]), np.array([1e-6]))
    return replace(heli, stiffness=pwl, transmission_error=te)


def variational(model: Any) -> tuple[np.ndarray, float]:
    """The independent route's multipliers at rtol 1e-13 and its own error."""
    mu13 = floquet_multipliers(model, rtol=1e-13)
    return mu13, multiplier_distance(mu13, floquet_multipliers(model, rtol=1e-12))


@pytest.mark.parametrize(("case", "estimate", "rtol", "spp"), [
    (fourier, True, 1e-5, 32), (fourier, False, 1e-6, 32), (resonant, False, 1e-8, 64),
    (pwl_te, True, 1e-6, 64)])
def test_reused_monodromy_agrees_with_variational_route(heli: Any, case: Any, estimate: bool,
                                                        rtol: float, spp: int) -> None:
    """(Loose rtols, the smooth stable case at 32 samples per period: at 64 and 1e-8 the
    maps' stated error sits within 10x of the variational route's own error, too close to
    test it.)"""
    model = case(heli)
    res = simulate(model, 6 / model.mesh_frequency,
                   SolverSettings(rtol=rtol, samples_per_period=spp, estimate_error=estimate))
    assert res.stats.method == "periodic" and res.step_maps is not None
    flo = res.extra["floquet"]
    assert "no integration" in flo["basis"]
    err = flo["multiplier_error"]
    mu_var, own = variational(model)
    mu_run = np.linalg.eigvals(period_map(*res.step_maps)[0]).astype(np.complex128)
    assert flo["max_multiplier_modulus"] == pytest.approx(float(np.max(np.abs(mu_run))),
                                                          rel=1e-15)
    assert multiplier_distance(mu_run, mu_var) <= err, (mu_run, mu_var, err)
    assert abs(flo["max_multiplier_modulus"] - float(np.max(np.abs(mu_var)))) <= err
    assert own <= 0.1 * err, (own, err)
    assert flo["unstable"] == (float(np.max(np.abs(mu_var))) > 1.0 + 1e-6)


def test_resonant_case_flagged_by_the_reused_route(heli: Any) -> None:
    """Unstable: flagged with its warning, the modulus as the variational route gives it."""
    model = resonant(heli)
    flo = simulate(model, 4 / model.mesh_frequency,
                   SolverSettings(estimate_error=False)).extra["floquet"]
    assert flo["unstable"] and "unstable" in flo["advice"]
    assert flo["max_multiplier_modulus"] > 1.1


def test_loose_maps_state_their_larger_error(heli: Any) -> None:
    """16 samples per period at rtol 1e-5: the run's maps are visibly inexact; the stated
    multiplier error grows with them and still covers the difference from the variational
    route."""
    model = fourier(heli)
    res = simulate(model, 6 / model.mesh_frequency,
                   SolverSettings(rtol=1e-5, samples_per_period=16))
    flo = res.extra["floquet"]
    mu_var, own = variational(model)
    mu_run = np.linalg.eigvals(period_map(*res.step_maps)[0]).astype(np.complex128)
    dist = multiplier_distance(mu_run, mu_var)
    assert 1e3 * own < dist <= flo["multiplier_error"] <= 20 * dist


@pytest.mark.parametrize("ratio", [None, 1.0])
def test_exact_pieces_reused_within_rounding_bound(heli: Any, ratio: float | None) -> None:
    """Piecewise-constant stiffness (exact propagator): the product of its piece maps, against
    an independent product of scipy.linalg.expm over the same period (own error at rounding,
    far below the stated bound), for the scene as built and at parametric resonance
    (2 f_n / f_m = 1, xi = 0.01: unstable)."""
    from scipy.linalg import expm

    model = heli
    if ratio is not None:
        r = 2 * heli.natural_frequency / heli.mesh_frequency
        model = replace(heli, mass=heli.mass * r**2, damping_ratio=0.01)
    flo = simulate(model, 4 / model.mesh_frequency, SolverSettings()).extra["floquet"]
    assert "exact propagator" in flo["basis"]
    phi = np.eye(2)
    for ta, tb, a, _g in model.linear_segments(0.0, 1.0 / model.mesh_frequency):
        phi = expm(a * (tb - ta)) @ phi
    rho = float(np.max(np.abs(np.linalg.eigvals(phi))))
    assert abs(flo["max_multiplier_modulus"] - rho) <= flo["multiplier_error"]
    assert flo["multiplier_error"] < 1e-10
    assert flo["unstable"] == (ratio is not None)


@pytest.mark.parametrize("rtol", [1e-5, 1e-7])
def test_gauss_reference_estimate_bounds_error(heli: Any, rtol: float) -> None:
    """The periodic run's stated error, now against Gauss-Legendre step maps, bounds the error
    measured against DOP853 at rtol 1e-13 (own error 1e-2 of the measured one or less) and is
    not a blanket (at most 20 times it). 16 samples per period make the run's error visible."""
    model = fourier(heli)
    t_end = 30 / model.mesh_frequency
    res = simulate(model, t_end, SolverSettings(rtol=rtol, samples_per_period=16))
    est = res.extra["estimated_error"]
    assert "Gauss-Legendre" in est["basis"]
    ref = reference_solution(model, time_grid(model.mesh_frequency, t_end, 16))
    measured = relative_errors(model, res.t, res.y, ref.y)[0]
    assert ref.own_error < 1e-2 * measured
    assert measured <= est["max_rel"] <= 20 * measured, (measured, est["max_rel"])
