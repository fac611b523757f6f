"""The ``periodic`` method's step maps: Magnus substeps in the compiled kernel, checked against
the Gauss-Legendre collocation maps (an independent method) and the solve_ivp driver."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
import pytest

from gear_dyn.analysis.accuracy import relative_errors
from gear_dyn.excitation import HarmonicSignal
from gear_dyn.scene import load_scene
from gear_dyn.scene.build import build_plan
from gear_dyn.solvers import SolverSettings, integrate, time_grid
from gear_dyn.solvers.periodic import _step_maps, gauss_step_maps, propagate_periodic
from gear_dyn.stiffness.periodic import PiecewiseStiffness


@pytest.fixture(scope="module")
def pwl_te() -> Any:
    """Piecewise-linear stiffness with a jump (0.3) and a kink (0.15) and a transmission error,
    at a phase offset."""
    heli: Any = build_plan(load_scene("examples/scenes/helicopter_tail.toml")).model
    pwl = PiecewiseStiffness(
        np.array([0.0, 0.3, 1.0]),
        ((np.array([0.0, 0.15, 0.3]), np.array([1.2e9, 1.3e9, 1.25e9])),
         (np.array([0.3, 1.0]), np.array([0.7e9, 0.75e9]))))
    te = HarmonicSignal(0.0, np.array([2e-6]), np.array([1e-6]))
    return replace(heli, stiffness=pwl, transmission_error=te, phase0=0.21)


@pytest.mark.parametrize("start", [0.0, 0.37])
def test_maps_agree_with_gauss_legendre_maps(pwl_te: Any, start: float) -> None:
    """From a grid start at 0 and inside a period: at rtol 1e-12 every step map agrees with the
    12th-order collocation maps (4 substeps, cut at the same jumps and kinks; its change from
    2 substeps, below 1e-13, shows its own error) to 1e-12 of the largest entry."""
    model = pwl_te
    dt = 1.0 / (model.mesh_frequency * 32)
    t0 = start / model.mesh_frequency
    f, h, nfev = _step_maps(model, t0, dt, 32, 1e-12)
    fg, hg = gauss_step_maps(model, t0, dt, 32, 4)
    fg2, hg2 = gauss_step_maps(model, t0, dt, 32, 2)
    scale = np.asarray(model.state_scale, dtype=float)
    # entries in the state scale: F_ij scale_j / scale_i, h_i / scale_i
    rel_f = lambda a: a * scale[None, None, :] / scale[None, :, None]  # noqa: E731
    assert np.max(np.abs(rel_f(fg) - rel_f(fg2))) < 1e-13
    assert np.max(np.abs(rel_f(f) - rel_f(fg))) < 1e-12
    assert np.max(np.abs((h - hg) / scale)) < 1e-12 * np.max(np.abs(hg / scale))
    assert nfev % 2 == 0 and nfev >= 2 * 32  # two coefficient evaluations per substep


def test_substeps_follow_rtol(pwl_te: Any) -> None:
    """``(omega h / 2)^4 <= rtol``: 10^4 times tighter, about 10 times the substeps."""
    dt = 1.0 / (pwl_te.mesh_frequency * 16)
    n_loose = _step_maps(pwl_te, 0.0, dt, 16, 1e-6)[2]
    n_tight = _step_maps(pwl_te, 0.0, dt, 16, 1e-10)[2]
    assert 6 < n_tight / n_loose < 12


def test_span_shorter_than_a_period(pwl_te: Any) -> None:
    """Ten samples of a 64-sample period: the maps of those steps only, against the solve_ivp
    driver (DOP853 at rtol 1e-12), within 1e-8 of the state scale at rtol 1e-8."""
    t = time_grid(pwl_te.mesh_frequency, 1.0 / pwl_te.mesh_frequency, 64)[:11]
    y, st = propagate_periodic(pwl_te, t, SolverSettings(method="periodic", rtol=1e-8))
    assert st["method"] == "periodic" and st["n_segments"] == 10 and "step_maps" not in st
    y_ref, _ = integrate(pwl_te, t, SolverSettings(method="DOP853", rtol=1e-12))
    assert relative_errors(pwl_te, t, y, y_ref)[0] < 1e-8
