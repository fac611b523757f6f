"""Every solve_ivp method converges to the exact solution as the tolerance shrinks, at its order.

Problem: the helicopter-tail single-DOF model (rectangular ISO wave), 2 mesh periods, restarted
at every switching instant (so each piece is smooth and the methods keep their order); the
reference is the exact propagator (rounding level, tests/solvers/test_exact.py).

Two figures per method over rtol = 1e-5 .. 1e-11 (measured, this test's problem):
- tolerance proportionality: log10(err) falls by 0.75..1.25 per decade of rtol (measured
  0.80..1.0 overall for all five);
- order: the slope of log(err) against log(nfev) is about -p; measured RK45 -5.4 (p = 5),
  DOP853 -8.2 (p = 8), Radau -5.0 (p = 5), BDF -6.0 and LSODA < -15 (variable order; nfev
  also counts Newton iterations). The bands below allow +-30 % around the fixed orders.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from gear_dyn.analysis.accuracy import relative_errors
from gear_dyn.models.sdof import SDOFModel
from gear_dyn.solvers import SolverSettings, integrate, time_grid
from gear_dyn.stiffness.periodic import rectangular_stiffness

RTOLS = (1e-5, 1e-7, 1e-9, 1e-11)
#: (lowest, highest) accepted -slope of log err vs log nfev
ORDER_BAND = {
    "RK45": (3.5, 6.5),     # order 5
    "DOP853": (5.6, 10.4),  # order 8
    "Radau": (3.5, 6.5),    # order 5
    "BDF": (3.0, 9.0),      # variable order 1..5
    "LSODA": (4.0, math.inf),  # variable order up to 12 (Adams)
}


@pytest.fixture(scope="module")
def problem() -> tuple[SDOFModel, np.ndarray, np.ndarray]:
    k = rectangular_stiffness(1.58, 7.09e8, 1.24e9)
    model = SDOFModel(mass=3.05, stiffness=k, damping_ratio=0.06, static_load=2.31e4,
                      mesh_frequency=1272.0)
    t = time_grid(model.mesh_frequency, 2 / model.mesh_frequency, 16)
    y_ref, _ = integrate(model, t, SolverSettings(method="exact"))
    return model, t, y_ref


@pytest.mark.parametrize("method", ["RK45", "DOP853", "Radau", "BDF", "LSODA"])
def test_converges_at_its_order(method: str, problem: tuple) -> None:
    model, t, y_ref = problem
    errs, nfev = [], []
    for rtol in RTOLS:
        y, st = integrate(model, t, SolverSettings(method=method, rtol=rtol))
        errs.append(relative_errors(model, t, y, y_ref)[0])
        nfev.append(st["nfev"])
    e = np.array(errs)
    # converges: every tightening by 100 reduces the error, and the tightest is within
    # 1000 rtol of the exact solution (global error = local tolerance times the accumulation
    # over ~100 steps; measured 5..360 rtol, BDF the largest)
    assert np.all(np.diff(e) < 0), e
    assert e[-1] < 1000 * RTOLS[-1], e
    per_decade = math.log10(e[0] / e[-1]) / math.log10(RTOLS[0] / RTOLS[-1])
    assert 0.75 <= per_decade <= 1.25, per_decade
    order = -math.log(e[-1] / e[0]) / math.log(nfev[-1] / nfev[0])
    lo, hi = ORDER_BAND[method]
    assert lo <= order <= hi, (order, nfev, e)
