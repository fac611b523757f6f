"""One Newton settings object: the defaults each study keeps, and that its settings reach the
solve (closing tolerance and iteration limit of shooting)."""

from __future__ import annotations

import numpy as np
import pytest

from gear_dyn import InputError, SDOFModel, rectangular_stiffness
from gear_dyn.analysis import study
from gear_dyn.analysis.continuation import ContinuationSettings
from gear_dyn.analysis.motion import DiagramOptions, classify
from gear_dyn.analysis.newton import NewtonSettings
from gear_dyn.analysis.stability import shoot
from gear_dyn.analysis.sweep import SweepOptions


def test_each_study_keeps_its_documented_default() -> None:
    """The table of NewtonSettings' docstring, read back from the option objects."""
    c = ContinuationSettings()
    assert (c.newton.max_iter, c.newton.tolerance) == (8, 1e-10)
    assert (c.start_newton.max_iter, c.start_newton.tolerance) == (30, None)
    assert (SweepOptions().newton.max_iter, SweepOptions().newton.tolerance) == (12, None)
    assert (DiagramOptions().newton.max_iter, DiagramOptions().newton.tolerance) == (15, None)
    assert (classify.NEWTON.max_iter, classify.LEAST_PERIOD_NEWTON.max_iter) == (15, 3)
    assert study.ORBIT_NEWTON.max_iter == 12


def test_bad_settings_are_refused_with_the_field_name() -> None:
    with pytest.raises(InputError, match="max_iter = 0"):
        NewtonSettings(max_iter=0)
    with pytest.raises(InputError, match="tolerance = 0.1"):
        NewtonSettings(tolerance=0.1)
    with pytest.raises(InputError, match="newton.tolerance = None"):
        ContinuationSettings(newton=NewtonSettings(max_iter=8))
    with pytest.raises(InputError, match="newton.max_iter = 1"):
        SweepOptions(newton=NewtonSettings(max_iter=1))


def test_shooting_stops_at_the_tolerance_asked_for() -> None:
    """From 1e-6 state scales off the orbit the closing error is about 1e-6: a tolerance of
    1e-4 accepts the guess itself (one map), the default 100 rtol = 1e-8 takes a Newton step,
    and one iteration allowed is then not enough."""
    m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 136.9,
                  backlash=1e-3)
    orbit = shoot(m, m.initial_state(), 1e-10)
    assert orbit.converged
    y = orbit.y0 + 1e-6 * np.asarray(m.state_scale)
    tight = shoot(m, y, 1e-10)
    loose = shoot(m, y, 1e-10, tol=1e-4)
    assert tight.converged and tight.iterations >= 2 and tight.residual <= 1e-8
    assert loose.converged and loose.iterations == 1 and 1e-8 < loose.residual <= 1e-4
    assert not shoot(m, y, 1e-10, max_iter=1).converged
