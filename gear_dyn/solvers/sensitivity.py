"""A state and its sensitivity to the initial state, ``y(t1)`` and ``d y(t1) / d y0``, by route:
the closed form of the backlash propagator or the variational equations (shooting, Floquet
multipliers of an orbit, Lyapunov exponents)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError
from gear_dyn.models.base import Model
from gear_dyn.solvers.contact_exact import contact_exact_applies, flow_with_sensitivity
from gear_dyn.solvers.ode import flow

FloatArray = NDArray[np.float64]

#: routes of :func:`integrate_with_sensitivity`
SENSITIVITY_ROUTES = ("auto", "exact", "variational")


def integrate_with_sensitivity(model: Model, y0: FloatArray, t1: float, rtol: float = 1e-10,
                               route: str = "auto") -> tuple[FloatArray, FloatArray]:
    """State ``y(t1)`` from ``y(0) = y0`` and its sensitivity ``d y(t1) / d y0``, by the route
    asked for: the backlash propagator's closed form or the variational equations.

    Parameters
    ----------
    model : Model
        The single-DOF mesh model (any model with a Jacobian for ``variational``).
    y0 : ndarray
        Start state at t = 0 ([m, m/s] for the single-DOF model).
    t1 : float
        End time in s.
    rtol : float
        Relative tolerance of the variational integration (unused by the exact route).
    route : str
        ``exact``: the closed-form pieces and saltation matrices of the backlash propagator
        (:func:`gear_dyn.solvers.contact_exact.flow_with_sensitivity`; single-DOF model with
        backlash, piecewise-constant stiffness and at most a harmonic transmission error),
        exact up to rounding; ``variational``: the variational equations with DOP853 at
        ``rtol`` (the solve_ivp driver's augmented state, :func:`gear_dyn.solvers.ode.flow`;
        imports scipy.integrate); ``auto``: ``exact`` where it applies.

    Returns
    -------
    y : ndarray (n,)
        State at ``t1``.
    phi : ndarray (n, n)
        ``d y(t1) / d y0``.

    Raises
    ------
    InputError
        An unknown route, or ``exact`` for a model it does not cover.
    SolverError
        Integration failure or a diverging response.
    """
    if route not in SENSITIVITY_ROUTES:
        raise InputError(f"route = {route!r}: valid choices are {', '.join(SENSITIVITY_ROUTES)}")
    if route == "exact" or (route == "auto" and contact_exact_applies(model)):
        return flow_with_sensitivity(model, y0, t1)
    n = len(model.state_labels)
    z = flow(model, y0, np.array([0.0, t1]), rtol=rtol, variational=True)[0][:, -1]
    return z[:n].copy(), z[n:].reshape(n, n).copy()
