"""The error estimate stated in every run summary bounds the measured error.

Each case measures the run's max error of x, relative to the static deflection, against an
independent reference (the exact propagator, or DOP853 at rtol 1e-13 whose own error is checked
to be far below the tested one) and asserts estimate >= measured. The estimate must also be
useful, not a blanket: at most 20 times the measured error (measured ratios 1.1..4.5).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
import pytest

from gear_dyn.analysis.accuracy import relative_errors
from gear_dyn.analysis.bench import reference_solution
from gear_dyn.analysis.study import simulate
from gear_dyn.scene import load_scene, run_scene
from gear_dyn.scene.build import build_plan
from gear_dyn.solvers import Result, SolverSettings, time_grid

SCENE = "examples/scenes/helicopter_tail.toml"


@pytest.fixture(scope="module")
def heli() -> Any:
    return build_plan(load_scene(SCENE)).model


def check(model: Any, res: Result, y_ref: np.ndarray) -> tuple[float, float]:
    measured = relative_errors(model, res.t, res.y, y_ref)[0]
    est = res.extra["estimated_error"]["max_rel"]
    assert measured <= est <= 20 * measured, (measured, est)
    return measured, est


@pytest.mark.parametrize(("method", "rtol"), [("LSODA", 1e-5), ("LSODA", 1e-8),
                                              ("DOP853", 1e-6), ("RK45", 1e-8), ("BDF", 1e-6)])
def test_helicopter_scene_estimate_bounds_error(method: str, rtol: float) -> None:
    """The helicopter tail scene itself (run_scene, 30 periods) against the exact propagator."""
    scene = load_scene(SCENE)
    res = run_scene(scene, method=method, rtol=rtol, periods=30)
    model = build_plan(scene).model
    ref = simulate(model, float(res.t[-1]), SolverSettings(method="exact"))
    assert np.array_equal(ref.t, res.t)
    check(model, res, ref.y)


def test_zero_damping_growing_error_is_bounded(heli: Any) -> None:
    """Undamped: the phase error grows linearly along the span; the estimate (a second run over
    the whole span) sees the end error and bounds it; the growth is linear, not exponential
    (growth per period below the 1.02 of an unstable response), and the run is reproducible."""
    model = replace(heli, damping_ratio=0.0)
    t_end = 60 / model.mesh_frequency
    ref = simulate(model, t_end, SolverSettings(method="exact"))
    res = simulate(model, t_end, SolverSettings(method="DOP853", rtol=1e-7))
    est = res.extra["estimated_error"]
    assert "whole span" in est["basis"] and est["reproducible"]
    check(model, res, ref.y)


def test_smooth_fourier_stiffness(heli: Any) -> None:
    """The 5-term Fourier stiffness of Jiang et al. (2018) (no exact propagator), LSODA at rtol
    1e-7, against the DOP853 rtol-1e-13 reference whose own error is 1e-3 of the tested one or
    less."""
    model = replace(heli, stiffness=heli.stiffness.truncated(5))
    t_end = 25 / model.mesh_frequency
    res = simulate(model, t_end, SolverSettings(method="LSODA", rtol=1e-7))
    ref = reference_solution(model, time_grid(model.mesh_frequency, t_end, 64))
    measured, _ = check(model, res, ref.y)
    assert ref.own_error < 1e-3 * measured


@pytest.fixture(scope="module")
def pwl_te(heli: Any) -> tuple[Any, Any]:
    """Piecewise-linear stiffness with jumps (the shape of the potential-energy and Weber
    methods) plus a transmission error, and its DOP853 rtol-1e-13 reference over 30 periods."""
    from gear_dyn.excitation import HarmonicSignal
    from gear_dyn.stiffness.periodic import PiecewiseStiffness

    pwl = PiecewiseStiffness(
        np.array([0.0, 0.3, 1.0]),
        ((np.array([0.0, 0.15, 0.3]), np.array([1.2e9, 1.3e9, 1.25e9])),
         (np.array([0.3, 1.0]), np.array([0.7e9, 0.75e9]))))
    te = HarmonicSignal(0.0, np.array([2e-6]), np.array([1e-6]))
    model = replace(heli, stiffness=pwl, transmission_error=te)
    t = time_grid(model.mesh_frequency, 30 / model.mesh_frequency, 64)
    return model, reference_solution(model, t)


@pytest.mark.parametrize("rtol", [1e-4, 1e-5])
def test_periodic_maps_piecewise_linear_stiffness_with_te(pwl_te: tuple[Any, Any],
                                                          rtol: float) -> None:
    """That model is linear and mesh-periodic, so auto takes the periodic step maps; the
    estimate bounds the error against the reference. The reference's own error (4e-2 of the
    measured one at rtol 1e-5) is small enough to tell the method's error (below 1e-1 of it),
    and the estimate bounds the largest error the run can have: measured + the reference's.
    (At rtol 1e-7 the maps' error is below the reference's own: it cannot tell them.)"""
    model, ref = pwl_te
    res = simulate(model, float(ref.t[-1]), SolverSettings(rtol=rtol))
    assert res.stats.method == "periodic"
    assert np.array_equal(res.t, ref.t)
    measured, est = check(model, res, ref.y)
    assert ref.own_error < 1e-1 * measured
    assert measured + ref.own_error <= est


def test_backlash_with_contact_events(heli: Any) -> None:
    """Light load (50 N m) with backlash and a transmission error that opens the gap every
    cycle: contact changes are located by events of the ODE solver (LSODA, asked for: ``auto``
    takes the closed form, exact_contact, for a harmonic TE); the estimate bounds the error
    against a DOP853 rtol-1e-12 reference (also event-located)."""
    from gear_dyn.excitation import HarmonicSignal

    te = HarmonicSignal(0.0, np.array([5e-6]), np.array([0.0]))
    model = replace(heli, static_load=50 / 0.0637, backlash=5e-5, transmission_error=te)
    t_end = 15 / model.mesh_frequency
    res = simulate(model, t_end, SolverSettings(method="LSODA", rtol=1e-8))
    assert res.extra["n_contact_events"] >= 20  # the teeth really separate, twice a cycle
    ref = simulate(model, t_end, SolverSettings(method="DOP853", rtol=1e-12,
                                                estimate_error=False))
    check(model, res, ref.y)
