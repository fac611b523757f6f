"""The solve_ivp driver: scipy's solve_ivp methods piece by piece between switching instants,
restarted at contact changes, optionally with the variational equations.

:func:`flow` is the one loop: the span is cut at ``model.switching_times`` and one scipy
``OdeSolver`` is stepped over it, restarted at each cut and, for a model with contact changes
(``model.contact_events()``: backlash), at each of them
(:class:`~gear_dyn.solvers.events.RestartingSolver`, the one event locator, which the stepwise
session of :mod:`gear_dyn.solvers.session` steps too); ``variational=True`` carries
``d y / d y0`` along (augmented state). :func:`integrate_ode` is that loop with a
:class:`~gear_dyn.solvers.settings.SolverSettings` (the methods RK45 ... LSODA of
:func:`~gear_dyn.solvers.integrate`). The dense output's interpolation error is not controlled
by scipy, so there explicit Runge-Kutta steps are limited to ``omega_n h <= (pi / 4)
(rtol / 1e-8)^(1 / (q + 1))`` (:func:`step_limit`, ``q`` the interpolant's order). A reported
failure or a non-finite state raises :class:`~gear_dyn.errors.SolverError` with scipy's message.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError, SolverError
from gear_dyn.models.base import Model
from gear_dyn.solvers import settings as limits
from gear_dyn.solvers.events import RestartingSolver
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
    """States on ``t_grid`` with the solve_ivp method ``settings.method``, piece by piece
    (:func:`~gear_dyn.solvers.ode.flow` with the settings' tolerances, step limit and work
    budget).

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
    out, counts = flow(model, y, t_grid, method=settings.method, rtol=settings.rtol,
                       atol=atol_of(model, settings), max_step=step_limit(model, settings),
                       frozen=False, max_nfev=settings.max_nfev)
    stats: dict[str, Any] = {"nfev": counts["nfev"], "njev": counts["njev"],
                             "nlu": counts["nlu"], "n_segments": counts["n_segments"]}
    if "n_events" in counts:
        stats["n_contact_events"] = counts["n_events"]
    return out, stats


def flow(
    model: Model, y0: FloatArray, t_grid: FloatArray, *, method: str = "DOP853",
    rtol: float = 1e-8, atol: FloatArray | float | None = None, max_step: float = math.inf,
    frozen: bool = True, variational: bool = False, max_nfev: int = limits.MAX_NFEV,
) -> tuple[FloatArray, dict[str, int]]:
    """The solve_ivp driver: states on ``t_grid`` from ``y(t_grid[0]) = y0``, one solve_ivp
    method's solver restarted at the model's switching instants and at every contact change
    (:class:`~gear_dyn.solvers.events.RestartingSolver`), so that no step crosses a jump or
    kink of the coefficients or of the dead zone; the grid points are read from its dense
    output, a piece's end from the step that ends there.

    Parameters
    ----------
    model : Model
    y0 : ndarray
        Initial state (SI units of ``model.state_labels``).
    t_grid : ndarray
        Increasing output times in s; the first is the initial time.
    method : str
        solve_ivp method; the implicit ones (:data:`~gear_dyn.solvers.settings.IMPLICIT`) get
        the Jacobian (not with ``variational``: they difference the augmented system).
    rtol : float
        Relative tolerance.
    atol : float, ndarray (n,) or None
        Absolute tolerance of the states; None: ``rtol * model.state_scale``.
    max_step : float
        Largest step in s.
    frozen : bool
        On a piece where the single-DOF model's stiffness is constant and there is no
        transmission error, integrate closures with that stiffness fixed
        (:func:`frozen_functions`): the model's own ``rhs`` evaluates ``k(t)`` at every call.
        The same equation; several times faster for sweeps.
    variational : bool
        Integrate the variational equations with the state (augmented state ``[y, vec(Phi)]``,
        ``Phi' = J(t, y) Phi``, ``Phi(t0) = I``): the returned rows ``n..n + n^2`` are
        ``d y(t) / d y0`` row by row. The absolute tolerance of ``Phi[i, j]`` is
        ``atol[i] / state_scale[j]``. Across a contact change the vector field is continuous,
        so the saltation matrix is the identity: the restart needs no correction; what it buys
        is the integrator's full order on both sides (a step across the kink loses it, and with
        it the accuracy of the sensitivities: 3e-4 in a Floquet multiplier, seen in a test).
    max_nfev : int
        Right-hand-side evaluations allowed (checked between pieces).

    Returns
    -------
    z : ndarray (n, n_t), or (n + n^2, n_t) with ``variational``
    counts : dict
        nfev, njev, nlu, n_segments, and n_events where the model has contact events.

    Raises
    ------
    SolverError
        solve_ivp failure, non-finite states, a chattering contact or the work budget spent,
        with scipy's message where it gave one.
    """
    t_grid = np.asarray(t_grid, dtype=float)
    t0, t1 = float(t_grid[0]), float(t_grid[-1])
    n = len(model.state_labels)
    scale = np.asarray(model.state_scale, dtype=float)
    tol = rtol * scale if atol is None else np.broadcast_to(np.asarray(atol, dtype=float), (n,))
    z = np.array(y0, dtype=float)
    events = list(model.contact_events())
    if variational:
        z = np.concatenate([z, np.eye(n).ravel()])
        ratio = (tol[:, None] / scale[None, :]).ravel() if atol is not None else (
            rtol * (scale[:, None] / scale[None, :]).ravel())  # the same, rounded as rtol * ratio
        tol = np.concatenate([tol, ratio])
    cuts = np.concatenate([[t0], model.switching_times(t0, t1), [t1]])

    made: dict[float, tuple[Any, Any]] = {}  # per piece (keyed by its end), over restarts

    def functions(ta: float, tb: float) -> tuple[Any, Any]:
        if tb not in made:
            f, jac = frozen_functions(model, ta, tb) if frozen else (model.rhs, model.jac)
            made.clear()
            made[tb] = (_augmented(f, jac, n), None) if variational else (f, jac)
        return made[tb]

    def next_cut(t: float) -> float:
        i = int(np.searchsorted(cuts, t, side="right"))
        return float(cuts[i]) if i < cuts.size else math.inf

    run = RestartingSolver(method, functions, events, n, next_cut, t0, z, rtol, tol, max_step,
                           span=t1 - t0)
    out = np.empty((z.size, t_grid.size))
    out[:, 0] = z
    for _ta, tb, i0, i1, t_eval in pieces(t_grid, cuts):
        out[:, i0:i1] = run.advance(t_eval)[:, : i1 - i0]
        _check_nfev(run.counts()["nfev"], method, tb, max_nfev)
    counts = {**run.counts(), "n_segments": int(cuts.size - 1)}
    if events:
        counts["n_events"] = run.n_events
    return out, counts


def _augmented(f: Callable[[float, FloatArray], FloatArray],
               jac: Callable[[float, FloatArray], FloatArray], n: int
               ) -> Callable[[float, FloatArray], FloatArray]:
    """Right-hand side of the state with its variational equations, ``[f(t, y); J Phi]``."""
    def rhs(t: float, z: FloatArray) -> FloatArray:
        y = z[:n]
        return np.concatenate([f(t, y), (jac(t, y) @ z[n:].reshape(n, n)).ravel()])
    return rhs


def frozen_functions(model: Model, ta: float, tb: float) -> tuple[Any, Any]:
    """(rhs, jac) of the model on the piece [ta, tb].

    Where the single-DOF model's stiffness is constant on the piece and there is no
    transmission error, closures with that ``k`` fixed (the model's own ``rhs`` evaluates
    ``k(t)`` at every call); otherwise the model's own functions.
    """
    mm: Any = model
    stiffness = getattr(mm, "stiffness", None)
    if (not model.mesh_periodic or stiffness is None or stiffness.segments() is None
            or getattr(mm, "transmission_error", None) is not None):
        return model.rhs, model.jac
    kt = float(stiffness(mm.phase(0.5 * (ta + tb))))
    m, c, w = mm.mass, mm.damping, model.static_load
    b = model.backlash
    if b is None:
        a = np.array([[0.0, 1.0], [-kt / m, -c / m]])

        def rhs(t: float, y: FloatArray) -> FloatArray:
            return np.array([y[1], (w - c * y[1] - kt * y[0]) / m])

        def jac(t: float, y: FloatArray) -> FloatArray:
            return a
        return rhs, jac
    a_in = np.array([[0.0, 1.0], [0.0, -c / m]])
    a_out = np.array([[0.0, 1.0], [-kt / m, -c / m]])
    bb = float(b)

    def rhs_b(t: float, y: FloatArray) -> FloatArray:
        x, v = y[0], y[1]
        fx = x - bb if x > bb else (x + bb if x < -bb else 0.0)
        return np.array([v, (w - c * v - kt * fx) / m])

    def jac_b(t: float, y: FloatArray) -> FloatArray:
        return a_in if abs(y[0]) <= bb else a_out
    return rhs_b, jac_b


def solve_once(model: Model, t_grid: FloatArray, method: str, rtol: float
               ) -> tuple[FloatArray, dict[str, Any]]:
    """One solve_ivp call over the whole span from ``model.initial_state()``: no cuts at the
    switching instants, no contact restarts, no Jacobian, ``atol = rtol * state_scale``. Not a
    method: the hand-written use of solve_ivp that ``gear-dyn bench`` (mode ``once``) measures
    :func:`flow` against.

    Returns
    -------
    y : ndarray (n_states, n_t)
    stats : dict with nfev, njev, nlu, n_segments (1)

    Raises
    ------
    SolverError
        solve_ivp failure or non-finite states.
    """
    from scipy.integrate import solve_ivp

    atol = rtol * np.asarray(model.state_scale, dtype=float)
    sol = solve_ivp(model.rhs, (float(t_grid[0]), float(t_grid[-1])), model.initial_state(),
                    method=method, t_eval=t_grid, rtol=rtol, atol=atol)
    if sol.status != 0 or not np.all(np.isfinite(sol.y)):
        raise SolverError(f"solve_ivp ({method}, once over the span) failed: {sol.message}")
    return sol.y, {"nfev": sol.nfev, "njev": sol.njev, "nlu": sol.nlu, "n_segments": 1}


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
