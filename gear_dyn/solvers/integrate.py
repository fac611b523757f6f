"""Choose the integration method for a model and grid, and run it.

``auto`` picks, in order: ``exact`` (:mod:`~gear_dyn.solvers.exact`), ``exact_contact``
(:mod:`~gear_dyn.solvers.contact_exact`), ``kernel`` (:mod:`~gear_dyn.solvers.kernel_method`:
the eccentric torsional model on any span, stepped by the native FMU's compiled kernel from its
table in the mesh phase, where the table meets its error limit and the library is built),
``periodic`` (:mod:`~gear_dyn.solvers.periodic`), ``gauss`` (:mod:`~gear_dyn.solvers.gauss`),
else solve_ivp with :data:`~gear_dyn.solvers.settings.DEFAULT_ODE_METHOD`
(:mod:`~gear_dyn.solvers.ode`), each where the model says it applies (docs/solvers.md). The
choice depends on the model and the grid only, never on what ran before in the process: runs
step through the compiled kernel, and ``gauss`` runs under ``auto`` only for an affine model the
kernel does not take (no table fits, or the library is not built); it falls back to the ODE
path where its affine form fails.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError
from gear_dyn.models.base import Model
from gear_dyn.solvers.contact_exact import contact_exact_applies, propagate_contact_exact
from gear_dyn.solvers.exact import exact_applies, propagate_exact
from gear_dyn.solvers.gauss import gauss_applies, propagate_gauss
from gear_dyn.solvers.kernel_method import kernel_applies, kernel_auto, propagate_kernel
from gear_dyn.solvers.ode import integrate_ode
from gear_dyn.solvers.periodic import periodic_map_applies, propagate_periodic
from gear_dyn.solvers.settings import DEFAULT_ODE_METHOD, SolverSettings

FloatArray = NDArray[np.float64]


def resolve_auto(model: Model) -> str:
    """The method ``auto`` picks without a grid: ``exact`` or ``exact_contact`` where they
    apply (in that order), else LSODA (which :func:`resolve_method` may turn into ``kernel``,
    ``periodic`` or ``gauss``: those choices need the grid or the model's table)."""
    if exact_applies(model):
        return "exact"
    return "exact_contact" if contact_exact_applies(model) else DEFAULT_ODE_METHOD


def resolve_method(model: Model, t_grid: FloatArray, method: str) -> str:
    """The concrete method that ``method`` means for ``model`` on ``t_grid``."""
    if method != "auto":
        return method
    chosen = resolve_auto(model)
    t_arr = np.asarray(t_grid, dtype=float)
    if chosen == DEFAULT_ODE_METHOD and kernel_auto(model, t_arr):
        return "kernel"  # the eccentric torsional model, whatever the span
    if chosen == DEFAULT_ODE_METHOD and periodic_map_applies(model, t_arr):
        return "periodic"  # linear, mesh-periodic: one period of integration
    if chosen == DEFAULT_ODE_METHOD and gauss_applies(model):
        return "gauss"  # affine in the state: all step maps at once
    return chosen


def integrate(
    model: Model, t_grid: FloatArray, settings: SolverSettings, y0: FloatArray | None = None
) -> tuple[FloatArray, dict[str, Any]]:
    """States on ``t_grid`` (which starts at the initial time) and the solver statistics.

    Returns
    -------
    y : ndarray (n_states, n_t)
    stats : dict with method, nfev, njev, nlu, n_segments (and method-specific counts)

    Raises
    ------
    InputError
        ``exact`` asked for a model it does not apply to; a span too long for an ODE solver.
    SolverError
        solve_ivp failure or non-finite states, with scipy's message.
    """
    method = resolve_method(model, t_grid, settings.method)
    run = replace(settings, method=method)
    if method == "exact":
        y, st = propagate_exact(model, t_grid, run, y0)
    elif method == "exact_contact":
        y, st = propagate_contact_exact(model, t_grid, run, y0)
    elif method == "kernel":
        if not kernel_applies(model):
            raise InputError(f"solver.method = 'kernel' does not apply to the "
                             f"{type(model).__name__} model: it steps the single-DOF mesh "
                             "equation with mesh-periodic coefficients and the eccentric "
                             "torsional model without backlash and transmission error, with the "
                             "compiled kernel built; use method 'auto'")
        y, st = propagate_kernel(model, t_grid, run, y0)
    elif method == "periodic":
        y, st = propagate_periodic(model, t_grid, run, y0)
    elif method == "gauss":
        done = propagate_gauss(model, t_grid, run, y0) if gauss_applies(model) else None
        if done is None:  # not affine here: the ODE path, as auto would without gauss
            y, st = integrate_ode(model, t_grid, replace(run, method=DEFAULT_ODE_METHOD), y0)
            st = {**st, "method": DEFAULT_ODE_METHOD, "gauss_fallback": True}
        else:
            y, st = done
    else:
        y, st = integrate_ode(model, t_grid, run, y0)
    return y, {**st, "method": st.get("method", method)}
