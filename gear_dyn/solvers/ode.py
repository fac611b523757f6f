"""scipy's solve_ivp, piece by piece between switching instants, restarted at contact changes.

The span is cut at ``model.switching_times`` and each piece is one ``solve_ivp`` call; a model
with contact changes (``model.contact_events()``: backlash) is also restarted at each of them
(:mod:`gear_dyn.solvers.events`). The dense output's interpolation error is not controlled by
solve_ivp, so explicit Runge-Kutta steps are limited to ``omega_n h <= (pi / 4)
(rtol / 1e-8)^(1 / (q + 1))`` (:func:`step_limit`, ``q`` the interpolant's order). A reported
failure or a non-finite state raises :class:`~gear_dyn.errors.SolverError` with scipy's message.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError, SolverError
from gear_dyn.models.base import Model
from gear_dyn.solvers import settings as limits
from gear_dyn.solvers.events import solve_piece_with_events
from gear_dyn.solvers.pieces import pieces
from gear_dyn.solvers.settings import IMPLICIT, SolverSettings

FloatArray = NDArray[np.float64]


def atol_of(model: Model, settings: SolverSettings) -> FloatArray:
    """Absolute tolerances per state: ``settings.atol`` or ``rtol * model.state_scale``."""
    if settings.atol is not None:
        return np.full(len(model.state_labels), settings.atol)
    return settings.rtol * np.asarray(model.state_scale, dtype=float)


#: order of the dense output (interpolant) of solve_ivp's explicit Runge-Kutta methods
DENSE_ORDER = {"RK23": 3, "RK45": 4, "DOP853": 7}


def step_limit(model: Model, settings: SolverSettings) -> float:
    """Largest step in s: ``settings.max_step``, for explicit Runge-Kutta methods also the
    limit that keeps their dense output within the tolerance (module docstring)."""
    q = DENSE_ORDER.get(settings.method)
    f_n = model.natural_frequency
    if q is None or f_n is None or not (math.isfinite(float(f_n)) and float(f_n) > 0):
        return settings.max_step
    omega_h = 0.25 * math.pi * (settings.rtol / 1e-8) ** (1.0 / (q + 1))
    return min(settings.max_step, omega_h / (2 * math.pi * float(f_n)))


def integrate_ode(
    model: Model, t_grid: FloatArray, settings: SolverSettings, y0: FloatArray | None = None
) -> tuple[FloatArray, dict[str, Any]]:
    """States on ``t_grid`` with the solve_ivp method ``settings.method``, piece by piece.

    Returns
    -------
    y : ndarray (n_states, n_t)
    stats : dict with nfev, njev, nlu, n_segments (and n_contact_events with contact changes)

    Raises
    ------
    InputError
        A non-finite initial state or a span too long for an ODE solver (:func:`check_work`).
    SolverError
        solve_ivp failure or non-finite states, with scipy's message.
    """
    t0, t1 = float(t_grid[0]), float(t_grid[-1])
    y = np.array(model.initial_state() if y0 is None else y0, dtype=float)
    check_work(model, t0, t1, y)
    cuts = np.concatenate([[t0], model.switching_times(t0, t1), [t1]])
    atol = atol_of(model, settings)
    out = np.empty((len(model.state_labels), t_grid.size))
    out[:, 0] = y
    extra: dict[str, Any] = {"jac": model.jac} if settings.method in IMPLICIT else {}
    events = list(model.contact_events())
    max_step = step_limit(model, settings)
    counts = {"nfev": 0, "njev": 0, "nlu": 0, "n_events": 0}
    for ta, tb, i0, i1, t_eval in pieces(t_grid, cuts):
        ys, y, st = solve_piece_with_events(model.rhs, ta, tb, y, t_eval, events,
                                            settings.method, settings.rtol, atol, max_step, extra)
        for key in counts:
            counts[key] += st.get(key, 0)
        _check_nfev(counts["nfev"], settings.method, tb, settings.max_nfev)
        out[:, i0:i1] = ys[:, : i1 - i0]
    stats: dict[str, Any] = {"nfev": counts["nfev"], "njev": counts["njev"],
                             "nlu": counts["nlu"], "n_segments": int(cuts.size - 1)}
    if events:
        stats["n_contact_events"] = counts["n_events"]
    return out, stats


def check_work(model: Model, t0: float, t1: float, y0: FloatArray) -> None:
    """Refuse an ODE run that cannot give a sensible answer in reasonable time.

    Raises
    ------
    InputError
        The initial state is not finite, or the span covers more than
        :data:`~gear_dyn.solvers.settings.MAX_NATURAL_PERIODS` periods of the model's
        ``natural_frequency`` (an ODE solver needs several steps per natural period, so such a
        run would take hours).
    """
    if not np.all(np.isfinite(y0)):
        labels = ", ".join(f"{n} = {v:.6g}" for n, v in zip(model.state_labels, y0, strict=False))
        raise InputError(
            f"initial state is not finite ({labels}): the inputs are beyond what the model can "
            "represent (check near-zero sizes, stiffnesses or inertias and huge loads)"
        )
    f_n = model.natural_frequency
    if f_n is None:
        return
    n_nat = (t1 - t0) * float(f_n)
    if not (math.isfinite(n_nat) and n_nat <= limits.MAX_NATURAL_PERIODS):
        n_mesh = (t1 - t0) * model.mesh_frequency
        f_min = float(f_n) * n_mesh / limits.MAX_NATURAL_PERIODS
        raise InputError(
            f"the run spans {n_nat:.4g} natural periods (natural frequency {float(f_n):.6g} Hz, "
            f"mesh frequency {model.mesh_frequency:.6g} Hz, duration {t1 - t0:.6g} s): valid "
            f"range <= {limits.MAX_NATURAL_PERIODS} for an ODE solver, i.e. a mesh frequency "
            f">= {f_min:.4g} Hz for these {n_mesh:.4g} mesh periods; raise operating.speed, "
            "lower solver.periods, or use method 'exact' where it applies (--speed, --periods, "
            "--method on the command line)"
        )


def _check_nfev(nfev: int, method: str, t: float, limit: int = limits.MAX_NFEV) -> None:
    if nfev > limit:
        others = ", ".join(m for m in IMPLICIT if m != method)
        advice = (f"an implicit method ({others})" if method not in IMPLICIT
                  else f"another implicit method ({others})")
        raise SolverError(
            f"solve_ivp ({method}) gave up at t = {t:.6g} s after {nfev} right-hand-side "
            f"evaluations (limit {limit}): the problem is stiff or the tolerance too "
            f"tight; try {advice}, a looser rtol, or fewer solver.periods, or raise the budget "
            "(--max-nfev N on the command line, SolverSettings(max_nfev=N) in Python)"
        )
