"""The restarted solver: one scipy ``OdeSolver`` kept alive, restarted at switching instants
and at located contact changes. The one event locator of the Python solvers.

With backlash the mesh force has kinks where ``|x - e| = b_g``; a solver stepping across them
loses its order. :class:`RestartingSolver` steps one ``OdeSolver`` (DOP853, RK45, RK23, Radau,
BDF or LSODA) and after every step looks for the first zero of the contact functions
(``model.contact_events()``) on that step's dense output, a sign change of ``g`` at the step
ends closed by Brent's method to 4 ulps of time (as scipy's ``solve_ivp`` locates its events).
There the solver is restarted, looking only for the opposite crossing of the function just hit.
A zero found again at that restart point is a grazing contact (``g`` tangent): the other
direction is tried once, then the solver steps past without events (1e-9 of the piece: the kink
costs O(h^2) there). A cap on contact changes per piece turns a chattering contact into a
:class:`~gear_dyn.errors.SolverError` instead of a hang.

It also restarts at the switching instants its caller names (``next_switch``), so that no step
crosses a jump of the coefficients. Both the solve_ivp driver
(:func:`gear_dyn.solvers.ode.flow`, the whole grid known up front) and the stepwise session
(:class:`gear_dyn.solvers.session.Session`, the FMU's communication points one by one) advance
their states with it. The compiled kernel has its own locator (``gear_dyn/solvers/kernel``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import SolverError
from gear_dyn.solvers.settings import IMPLICIT

FloatArray = NDArray[np.float64]
EventFn = Callable[[float, FloatArray], float]
Rhs = Callable[[float, FloatArray], FloatArray]
#: the right-hand side and Jacobian (None: none given to the solver) on a piece ``[ta, tb]``
Functions = Callable[[float, float], tuple[Rhs, Any]]
EPS = float(np.finfo(float).eps)

#: the solve_ivp methods a :class:`RestartingSolver` can step
ODE_METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")

#: restarts allowed within one piece between switching instants before giving up
MAX_EVENTS_PER_PIECE = 10_000

#: the attributes that, with the solver's own, are the whole state of a RestartingSolver
#: (what the FMU's snapshot saves)
STATE = ("dirs", "g", "cut", "graze", "after_contact", "t_start", "piece_start", "count_from",
         "in_piece", "n_events", "quiet", "spent")


class RestartingSolver:
    """One ``OdeSolver`` kept alive from ``(t0, y0)``, restarted at the switching instants and
    at every located contact change; :meth:`~gear_dyn.solvers.events.RestartingSolver.advance` reads the states at given times from the
    dense output, so those times never disturb the integration.

    Parameters
    ----------
    method : str
        One of :data:`ODE_METHODS`.
    functions : callable
        ``functions(ta, tb) -> (rhs, jac)`` on a piece ``[ta, tb]`` (s) without a switching
        instant inside; ``jac`` None: the implicit methods difference the right-hand side.
    events : list of callables
        Contact functions ``g(t, y[:n])`` (may be empty).
    n : int
        Rows of the state the events see (the model's state, before any variational part).
    next_switch : callable
        ``next_switch(t)``: the first switching instant after ``t`` in s (inf: none).
    t0 : float
        Start time in s.
    y0 : ndarray
        State at ``t0``.
    rtol : float
    atol : ndarray
        Tolerances, as for solve_ivp.
    max_step : float
        Largest step in s.
    span : float
        Length in s that scales the restart offsets where a piece has no end (no switching
        instant ahead), e.g. the mesh period.
    """

    def __init__(self, method: str, functions: Functions, events: list[EventFn], n: int,
                 next_switch: Callable[[float], float], t0: float, y0: FloatArray, rtol: float,
                 atol: FloatArray, max_step: float, span: float) -> None:
        self.method = method
        self.functions = functions
        self.events = events
        self.n = n
        self.next_switch = next_switch
        self.rtol, self.atol, self.max_step, self.span = rtol, atol, max_step, span
        self.solver: Any = None
        self.spent = {"nfev": 0, "njev": 0, "nlu": 0}  # by the solvers already replaced
        self.n_events = 0  # contact changes located, in all
        self.in_piece = 0  # of them since count_from (the chattering cap)
        self.piece_start = self.count_from = float(t0)
        self.graze = 0  # restarts at one grazing contact so far (1: direction flipped)
        self.after_contact = False  # the solver (re)started at a contact change
        self.quiet = False  # stepping past a grazing contact, without events
        self.cut: tuple[float, FloatArray, int] | None = None
        self._start(float(t0), np.array(y0, dtype=float), None)

    # ------------------------------------------------------------------ state
    def counts(self) -> dict[str, int]:
        """Right-hand-side evaluations, Jacobians and LU decompositions so far."""
        s = self.solver
        return {"nfev": self.spent["nfev"] + s.nfev, "njev": self.spent["njev"] + s.njev,
                "nlu": self.spent["nlu"] + s.nlu}

    def _length(self, end: float) -> float:
        """Length in s of the piece that ends at ``end`` (``span`` where it has no end)."""
        return end - self.piece_start if math.isfinite(end) else self.span

    def _start(self, t: float, y: FloatArray, dirs: list[float] | None,
               quiet: bool = False) -> None:
        """A new solver at ``(t, y)``, bound by the next switching instant (``quiet``: by the
        end of the step past a grazing contact), looking for the crossings ``dirs``
        (None: both directions of every contact function)."""
        from scipy.integrate import BDF, DOP853, LSODA, RK23, RK45, Radau

        if self.solver is not None:
            for key in self.spent:
                self.spent[key] += getattr(self.solver, key)
        t_sw = self.next_switch(t)
        bound = t_sw
        if quiet:
            # at least one ulp on: a step that does not move would meet the graze again
            bound = min(t_sw, max(t + 1e-9 * self._length(t_sw), math.nextafter(t, math.inf)))
        rhs, jac = self.functions(t, t_sw)
        cls = {"RK45": RK45, "RK23": RK23, "DOP853": DOP853, "Radau": Radau, "BDF": BDF,
               "LSODA": LSODA}[self.method]
        extra = {"jac": jac} if self.method in IMPLICIT and jac is not None else {}
        self.solver = cls(rhs, t, y, bound, rtol=self.rtol, atol=self.atol,
                          max_step=self.max_step, **extra)
        self.rhs, self.quiet, self.t_start, self.cut = rhs, quiet, t, None
        self.dirs = [0.0] * len(self.events) if dirs is None else dirs
        self.g = [float(fn(t, y[:self.n])) for fn in self.events]
        self._sol: Any = None

    def dense(self) -> Any:
        """The dense output of the solver's last step (made once per step)."""
        if self._sol is None:
            self._sol = self.solver.dense_output()
        return self._sol

    # ------------------------------------------------------------------ stepping
    def advance(self, times: FloatArray) -> FloatArray:
        """States at ``times`` (s, increasing, none before the current time).

        Returns
        -------
        ndarray (len(y0), len(times))

        Raises
        ------
        SolverError
            A failed step, non-finite states or a chattering contact, with scipy's message.
        """
        out = np.empty((self.solver.y.size, times.size))
        done, n_t = 0, times.size
        while done < n_t:
            solver = self.solver
            end = self.cut[0] if self.cut is not None else solver.t
            if times[done] > end:
                self._step()
                continue
            k = int(np.searchsorted(times, end, side="right"))
            m = k
            if self.cut is None and times[k - 1] == solver.t:
                out[:, k - 1] = solver.y  # the step's own end: no interpolation
                m = k - 1
            if m > done:
                out[:, done:m] = self.dense()(times[done:m])
            if not np.all(np.isfinite(out[:, done:k])):
                raise SolverError(
                    f"{self.method} produced non-finite states near t = {end:.6g} s; the "
                    "response diverges (parametric instability?) or the tolerances are too "
                    "loose")
            done = k
        return out

    def _step(self) -> None:
        """One step of the solver, or a restart where the last one ended or was cut."""
        solver = self.solver
        if self.cut is not None:
            self._restart_at_cut()
        elif solver.status == "finished":  # a switching instant, or past a grazing contact
            if not self.quiet:
                self.piece_start = self.count_from = solver.t
                self.in_piece = self.graze = 0
                self.after_contact = False
            self._start(solver.t, np.array(solver.y), None)
        else:
            msg = solver.step()
            self._sol = None
            if solver.status == "failed":
                raise SolverError(f"{self.method} failed at t = {solver.t:.6g} s: {msg}; try a "
                                  "smaller rtol or an implicit method (Radau, BDF)")
            if self.events and not self.quiet:
                self._locate()

    def _locate(self) -> None:
        """The first contact change in the last step: a sign change of a contact function in
        its looked-for direction, closed on the dense output (``cut``)."""
        from scipy.optimize import brentq

        solver, n = self.solver, self.n
        g_new = [float(fn(solver.t, solver.y[:n])) for fn in self.events]
        first: tuple[float, int] | None = None
        for i, (g0, g1, d) in enumerate(zip(self.g, g_new, self.dirs, strict=True)):
            up, down = g0 <= 0 <= g1, g0 >= 0 >= g1
            if g0 == g1 or not ((up and d >= 0) or (down and d <= 0)):
                continue
            sol, fn = self.dense(), self.events[i]
            try:
                tr = float(brentq(lambda tt, fn=fn, sol=sol: fn(tt, sol(tt)[:n]),
                                  solver.t_old, solver.t, xtol=4 * EPS, rtol=4 * EPS))
            except RuntimeError as exc:  # no convergence in brentq's iteration limit
                raise SolverError(f"{self.method}: the contact change between t = "
                                  f"{solver.t_old:.9g} s and {solver.t:.9g} s was not located "
                                  f"({exc}); try a smaller rtol") from exc
            if first is None or tr < first[0]:
                first = (tr, i)
        self.g = g_new
        if first is not None:
            self.cut = (first[0], np.asarray(self.dense()(first[0]), dtype=float), first[1])

    def _restart_at_cut(self) -> None:
        """Restart at the located contact change, looking only for the opposite crossing of
        that function; at a grazing contact flip that direction once, then step past."""
        assert self.cut is not None
        t, y, j = self.cut
        length = self._length(float(self.solver.t_bound))
        if self.after_contact and t <= self.t_start + 1e-12 * length:
            # found again at the restart point: g is tangent there (a grazing contact), so the
            # slope test picked the wrong side. Try the other side once; then step past
            if self.graze == 0:
                dirs = list(self.dirs)
                dirs[j] = -dirs[j]
                self.graze = 1
                self._start(t, y, dirs)
            else:
                self.graze = 0
                self._start(t, y, None, quiet=True)
            return
        self.graze = 0
        self.n_events += 1
        if t - self.count_from > length:  # a piece without end: the cap per its span
            self.in_piece, self.count_from = 0, t
        self.in_piece += 1
        if self.in_piece > MAX_EVENTS_PER_PIECE:
            raise SolverError(
                f"more than {MAX_EVENTS_PER_PIECE} contact changes between t = "
                f"{self.count_from:.6g} and {t:.6g} s (chattering contact); loosen rtol or "
                "check the backlash")
        dt = 1e-9 * length
        slope = self.events[j](t + dt, (y + dt * self.rhs(t, y))[:self.n])
        dirs = [0.0] * len(self.events)
        dirs[j] = -1.0 if slope > 0 else 1.0
        self.after_contact = True
        self._start(t, y, dirs)
