"""The solve_ivp driver (gear_dyn.solvers.ode.flow) against the exact propagator.

A linear single-DOF model with a rectangular stiffness has an exact one-period map ``(Phi, q)``
(products of matrix exponentials, :func:`gear_dyn.analysis.stability.one_period_map`). The
driver's state and its variational part over three mesh periods must match them by scipy's own
test criterion, ``|y - y_true| / (atol + rtol |y_true|) < 5``, with the stiffness frozen per
piece or evaluated by the model's rhs at every call.
"""

from __future__ import annotations

import numpy as np
import pytest

from gear_dyn import SDOFModel, rectangular_stiffness
from gear_dyn.analysis.stability import one_period_map
from gear_dyn.errors import SolverError
from gear_dyn.solvers.ode import flow


def _model() -> SDOFModel:
    return SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 3000.0)


@pytest.mark.parametrize("frozen", [True, False])
def test_variational_flow_matches_the_exact_period_map(frozen: bool) -> None:
    model = _model()
    phi1, q1, how = one_period_map(model)
    assert how == "expm"
    # three periods from rest: y = q3, d y / d y0 = Phi^3 (the exact composition)
    phi = np.linalg.matrix_power(phi1, 3)
    q = phi1 @ (phi1 @ q1 + q1) + q1
    rtol = 1e-10
    t = np.linspace(0.0, 3 / model.mesh_frequency, 7)
    z, counts = flow(model, np.zeros(2), t, rtol=rtol, variational=True, frozen=frozen)
    assert z.shape == (6, t.size)
    assert counts["n_segments"] == 6 and "n_events" not in counts
    scale = np.asarray(model.state_scale)
    y, p = z[:2, -1], z[2:, -1].reshape(2, 2)
    assert np.all(np.abs(y - q) / (rtol * scale + rtol * np.abs(q)) < 5)
    atol_phi = rtol * scale[:, None] / scale[None, :]
    assert np.all(np.abs(p - phi) / (atol_phi + rtol * np.abs(phi)) < 5)
    # the state rows are the plain flow's (same steps: the variational part is error-controlled
    # too, so only to the tolerance)
    plain, _ = flow(model, np.zeros(2), t, rtol=rtol, frozen=frozen)
    assert np.all(np.abs(plain[:, -1] - q) / (rtol * scale + rtol * np.abs(q)) < 5)


def test_flow_stops_at_its_work_budget() -> None:
    model = _model()
    t = np.linspace(0.0, 20 / model.mesh_frequency, 21)
    with pytest.raises(SolverError, match="gave up .* right-hand-side evaluations"):
        flow(model, np.zeros(2), t, method="RK45", rtol=1e-12, max_nfev=1000)
