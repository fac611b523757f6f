"""Continuation on the constant-stiffness backlash scene excited by its transmission error
(packaged ``backlash_constant_stiffness``), on the exact route (the closed form with the
transmission error's particular solution, gear_dyn.solvers.contact_exact).

- The fold of the resonance located by continuation on the exact route against the second
  method: the minimally extended system ``P(y, w) - y = 0, det(M - I) = 0`` solved by MINPACK on
  the variational route (DOP853 with located contact events at rtol 1e-12). They agree to 1e-8
  relative in speed (measured: ~1e-13).
- In heavy separation (f_m / f_n = 1.56, teeth apart for over half of the time) the period-2
  orbit period-doubles (the period-1 orbit is already flip-unstable there: it doubled at
  0.96 f_n). The doubling is located on the period-2 branch (a multiplier -1) and confirmed by
  the period-4 orbit's own multipliers: shot over four mesh periods, independently of the
  continuation, just past the doubling, one multiplier tends to +1 linearly with the distance.
"""

from __future__ import annotations

import math
from functools import partial

import numpy as np
import pytest
from extended_system import solve_extended

from gear_dyn.analysis.continuation import ContinuationSettings, continue_orbits, fold_test
from gear_dyn.analysis.stability import shoot
from gear_dyn.scene import load_scene
from gear_dyn.scene.sweep import SceneModels
from gear_dyn.solvers.sensitivity import integrate_with_sensitivity

RPM = 2 * math.pi / 60


@pytest.fixture(scope="module")
def family() -> SceneModels:
    return SceneModels.of(load_scene("backlash_constant_stiffness"))


@pytest.mark.slow
def test_fold_agrees_with_the_extended_system_on_the_variational_route(family) -> None:
    """Above the lower fold (6941 rpm) only the resonant orbit exists; followed upwards it
    turns back at the upper fold near 7082 rpm (stable -> unstable)."""
    br = continue_orbits(family, 6990 * RPM, 7100 * RPM, doublings=0)
    assert br.route == "exact"
    fold = next(f for f in br.of_kind("fold") if f.before == "stable")
    assert 7000 * RPM < fold.parameter < 7100 * RPM
    assert fold.parameter_error <= 1e-9 * fold.parameter
    scale = family(fold.parameter).state_scale
    variational = partial(integrate_with_sensitivity, rtol=1e-12, route="variational")
    # start the second method 1e-4 away from the located fold, in state and speed
    sol = solve_extended(family, fold_test, variational, scale, fold.parameter,
                         np.append(fold.point.state / scale * (1 + 1e-4), 1.0 + 1e-4), 1e-13)
    assert np.max(np.abs(sol.fun)) < 1e-9, sol.message
    assert sol.x[2] == pytest.approx(1.0, abs=1e-8)


@pytest.mark.slow
def test_period_doubling_in_heavy_separation_confirmed_by_the_period4_orbit(family) -> None:
    """From 11500 rpm the period-2 branch runs up to its fold near 12211 rpm, back (unstable)
    to the fold near 11554 rpm and up again, stable, with the teeth apart most of the time,
    to the doubling near 11766 rpm (f_m / f_n = 1.56)."""
    br = continue_orbits(family, 11500 * RPM, 12250 * RPM, periods=2, doublings=1,
                         settings=ContinuationSettings(max_points=300))
    (pd,) = br.of_kind("period_doubling")
    ratio = family(pd.parameter).mesh_frequency / family(pd.parameter).natural_frequency
    assert 1.4 < ratio < 1.6
    assert pd.point.separation > 0.5, "heavy separation: teeth apart most of the time"
    mu = pd.point.multipliers
    assert np.min(np.abs(mu + 1.0)) < 1e-6  # located on the test function to ~1e-11
    (child,) = br.children
    assert child.periods == 4
    # the period-4 orbit shot independently just past the doubling: its multiplier nearest +1
    # approaches 1 linearly in the distance (a pitchfork of the four-period map)
    gaps = []
    for eps in (1e-5, 1e-6):
        m = family(pd.parameter * (1 + eps))
        sol = shoot(m, child.points[0].state, 1e-10, 30, 4, "exact")
        assert sol.converged
        two, _ = integrate_with_sensitivity(m, sol.y0, 2 / m.mesh_frequency, 1e-10, "exact")
        assert np.max(np.abs(two - sol.y0) / m.state_scale) > 1e-6, "a true period-4 orbit"
        gaps.append(float(np.min(np.abs(sol.multipliers - 1.0))))
    assert gaps[1] < 1e-3
    assert 5 < gaps[0] / gaps[1] < 20
