"""Contact-change events: locate tooth separation and impact, restart the solver there.

With backlash the mesh force has kinks where ``|x - e| = b_g``; a solver stepping across them
loses its order. Each kink (a zero of one of ``model.contact_events()``) is located with
solve_ivp's event finder and the integration restarted there, looking only for the opposite
crossing of the event just hit. A cap on restarts per piece turns a chattering contact into a
:class:`~gear_dyn.errors.SolverError` instead of a hang.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import SolverError

FloatArray = NDArray[np.float64]
EventFn = Callable[[float, FloatArray], float]

#: restarts allowed within one piece between switching instants before giving up
MAX_EVENTS_PER_PIECE = 10_000


def _event(fn: EventFn, direction: float) -> Any:
    def ev(t: float, y: FloatArray) -> float:
        return fn(t, y)

    ev.terminal = True  # type: ignore[attr-defined]
    ev.direction = direction  # type: ignore[attr-defined]
    return ev


def _take(sol: Any, method: str, t: float, tb: float, n: int, y_eval: FloatArray, done: int,
          st: dict[str, int]) -> int:
    """Add one solve_ivp call's statistics to ``st`` and its output points to ``y_eval`` (from
    column ``done``); the new count of filled columns. Raises SolverError on a failed call or
    non-finite states."""
    st["nfev"] += sol.nfev
    st["njev"] += sol.njev
    st["nlu"] += sol.nlu
    if sol.status == -1:
        raise SolverError(
            f"solve_ivp ({method}) failed at t = {t:.6g}..{tb:.6g} s: {sol.message}; "
            "try a smaller rtol or an implicit method (Radau, BDF)"
        )
    # solve_ivp returns a plain [] when no t_eval point lies before the event
    sy = np.asarray(sol.y, dtype=float).reshape(n, -1)
    k = sy.shape[1]
    y_eval[:, done:done + k] = sy
    if not np.all(np.isfinite(sy)):
        raise SolverError(
            f"solve_ivp ({method}) produced non-finite states at t = {t:.6g}..{tb:.6g} s; "
            "the response diverges (parametric instability?) or the tolerances are too loose"
        )
    return done + k


def solve_piece_with_events(
    rhs: Callable[[float, FloatArray], FloatArray],
    ta: float,
    tb: float,
    y: FloatArray,
    t_eval: FloatArray,
    events: list[EventFn],
    method: str,
    rtol: float,
    atol: FloatArray,
    max_step: float,
    extra: dict[str, Any],
) -> tuple[FloatArray, FloatArray, dict[str, int]]:
    """Integrate ``[ta, tb]`` restarting at every contact change (one solve_ivp call without).

    Parameters
    ----------
    rhs : callable
        Right-hand side ``f(t, y)``.
    ta, tb : float
        Piece ends in s.
    y : ndarray
        State at ``ta``.
    t_eval : ndarray
        Output times in ``[ta, tb]`` (increasing; ``tb`` last).
    events : list of callables
        Contact functions ``g(t, y)`` (may be empty).
    method, rtol, atol, max_step, extra
        As for solve_ivp (``extra`` e.g. ``{"jac": ...}``).

    Returns
    -------
    y_eval : ndarray (n, len(t_eval))
    y_end : ndarray
        State at ``tb``.
    stats : dict
        nfev, njev, nlu, n_events.

    Raises
    ------
    SolverError
        solve_ivp failure, non-finite states, or more than MAX_EVENTS_PER_PIECE contact
        changes in one piece (a chattering contact).
    """
    from scipy.integrate import solve_ivp

    n = y.size
    y_eval = np.empty((n, t_eval.size))
    done = 0
    t = ta
    dirs = [0.0] * len(events)
    st = {"nfev": 0, "njev": 0, "nlu": 0, "n_events": 0}
    tiny = 1e-12 * (tb - ta)  # an event closer than this to the restart point is the same one
    flipped = False
    while True:
        evs = [_event(fn, d) for fn, d in zip(events, dirs, strict=True)]
        te = t_eval[done:]
        sol = solve_ivp(rhs, (t, tb), y, method=method, t_eval=te, rtol=rtol, atol=atol,
                        max_step=max_step, events=evs or None, **extra)  # None: no checks
        done = _take(sol, method, t, tb, n, y_eval, done, st)
        if sol.status == 0:
            return y_eval, np.asarray(sol.y[:, -1], dtype=float), st
        # a contact change: restart there, looking only for the opposite crossing of that g
        j = next(j for j, tev in enumerate(sol.t_events) if len(tev))
        t_new = float(sol.t_events[j][0])
        if t_new <= t + tiny and t > ta:
            # found again at the restart point: g is tangent there (a grazing contact), so the
            # slope test picked the wrong side. Try the other side once; then step past the
            # graze without events (a step of 1e-9 of the piece: the kink costs O(h^2) there)
            if not flipped:
                dirs[j] = -dirs[j]
                flipped = True
                continue
            y, done, st = _step_past(rhs, t, tb, y, t_eval, done, y_eval, method, rtol, atol,
                                     extra, st)
            t = min(t + 1e-9 * (tb - ta), tb)
            dirs, flipped = [0.0] * len(events), False
            if t >= tb:
                return y_eval, y, st
            continue
        flipped = False
        y = np.asarray(sol.y_events[j][0], dtype=float)
        slope = events[j](t_new + 1e-9 * (tb - ta), y + 1e-9 * (tb - ta) * rhs(t_new, y))
        dirs = [0.0] * len(events)
        dirs[j] = -1.0 if slope > 0 else 1.0
        st["n_events"] += 1
        if st["n_events"] > MAX_EVENTS_PER_PIECE:
            raise SolverError(
                f"more than {MAX_EVENTS_PER_PIECE} contact changes between t = {ta:.6g} and "
                f"{tb:.6g} s (chattering contact); loosen rtol or check the backlash"
            )
        t = t_new
        if t >= tb:
            return y_eval, y, st


def _step_past(rhs: Callable[[float, FloatArray], FloatArray], t: float, tb: float, y: FloatArray,
               t_eval: FloatArray, done: int, y_eval: FloatArray, method: str, rtol: float,
               atol: FloatArray, extra: dict[str, Any], st: dict[str, int]
               ) -> tuple[FloatArray, int, dict[str, int]]:
    """Integrate a step of 1e-9 of the remaining span without events (past a grazing contact),
    filling the output points that fall inside it."""
    from scipy.integrate import solve_ivp

    t1 = min(t + 1e-9 * (tb - t), tb)
    inside = t_eval[done:][t_eval[done:] <= t1]
    sol = solve_ivp(rhs, (t, t1), y, method=method, t_eval=np.append(inside, t1) if (
        inside.size == 0 or inside[-1] < t1) else inside, rtol=rtol, atol=atol, **extra)
    st["nfev"] += sol.nfev
    st["njev"] += sol.njev
    st["nlu"] += sol.nlu
    if sol.status != 0 or not np.all(np.isfinite(sol.y)):
        raise SolverError(f"solve_ivp ({method}) failed past a grazing contact at t = {t:.6g} s: "
                          f"{sol.message}")
    y_eval[:, done:done + inside.size] = sol.y[:, :inside.size]
    return np.asarray(sol.y[:, -1], dtype=float), done + inside.size, st
