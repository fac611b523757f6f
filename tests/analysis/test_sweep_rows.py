"""A sweep row (gear_dyn.analysis.sweep.types.Point) reads its orbit part from the
PeriodicSolution it holds.

Second method for the least-period case: shooting over two mesh periods from a period-1 orbit
closes on that orbit; the row calls it period-1, and its spectral radius (the two-period
map's, to the power 1/2) must equal that of shooting over one period, to the multipliers'
accuracy (both monodromy matrices come from the exact closed-form route, to rounding; 1e-9
relative leaves room for the Newton residual of 100 rtol moving the orbit's state).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gear_dyn.analysis.stability import shoot
from gear_dyn.analysis.sweep import SweepCurve, SweepOptions
from gear_dyn.analysis.sweep.points import steady_point
from gear_dyn.scene import load_scene
from gear_dyn.scene.sweep import model_at_speed
from gear_dyn.solvers import SolverSettings
from gear_dyn.solvers.contact_exact import propagate_contact_exact

SCENE = Path(__file__).resolve().parents[2] / "gear_dyn" / "scenes" / \
    "backlash_constant_stiffness.toml"
SPEED = 5500.0 * 2 * np.pi / 60  # rad/s: a period-1 orbit with a gap and back contact


def test_a_row_found_over_two_periods_is_the_period_1_orbit() -> None:
    model = model_at_speed(load_scene(SCENE), SPEED)
    settled = propagate_contact_exact(model, np.linspace(0.0, 300 / model.mesh_frequency,
                                                         301))[0][:, -1]
    settings = SolverSettings(rtol=1e-10)
    one = shoot(model, settled, settings.rtol)
    assert one.converged and one.stable
    point, _ = steady_point(model, SPEED, settings, SweepOptions(), one.y0, n_prev=2)
    assert point.orbit is not None and point.orbit.periods == 2  # shot over two periods
    assert (point.orbit_periods, point.status, point.periodic) == (1, "periodic", True)
    assert point.spectral_radius == pytest.approx(one.spectral_radius, rel=1e-9)
    assert point.stable == point.orbit.stable
    np.testing.assert_array_equal(point.state, point.orbit.y0)
    curve = SweepCurve.from_points("up", [point])
    assert (curve.spectral_radius[0], curve.separation[0], curve.orbit_periods[0]) == (
        point.spectral_radius, point.orbit.separation, 1)
