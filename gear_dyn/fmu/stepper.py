"""Advance a gear_dyn model from one communication point to the next, keeping the solver alive.

A co-simulation master asks for the state at ``t + h`` again and again. :class:`Stepper` keeps
one scipy ``OdeSolver`` object (DOP853, RK45, RK23, Radau, BDF or LSODA) alive across
communication steps and reads the state at each point from its dense output, so the points
never disturb the integration; it restarts the solver only where :mod:`gear_dyn.solvers.ode`
does (the model's switching instants, contact changes) and where the importer changes an input.
``exact`` carries the state with cached matrix exponentials (``_Propagator``). What this
buys and how it is tested: docs/fmu.md, "Inside doStep".

:meth:`Stepper.snapshot` and :meth:`Stepper.restore` save and restore the whole integrator state
(the solver's step size, stage derivatives, error history, LSODA work arrays), not only the model
state, so a restored run continues bit for bit as the original did.
"""

from __future__ import annotations

import copy
import math
import operator
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.integrate import BDF, DOP853, LSODA, RK23, RK45, OdeSolver, Radau

from gear_dyn.errors import InputError, SolverError
from gear_dyn.models.base import Model
from gear_dyn.solvers import DEFAULT_ODE_METHOD, IMPLICIT, SolverSettings, resolve_auto
from gear_dyn.solvers.exact import _Exponential  # the exact propagator's cached matrix exponential
from gear_dyn.solvers.ode import atol_of, step_limit

FloatArray = NDArray[np.float64]
EPS = float(np.finfo(float).eps)

#: OdeSolver classes the stepper can keep alive, by solve_ivp method name
ODE_CLASSES: dict[str, type[OdeSolver]] = {
    "RK45": RK45, "RK23": RK23, "DOP853": DOP853, "Radau": Radau, "BDF": BDF, "LSODA": LSODA,
}


def stepper_method(model: Model) -> str:
    """The method ``auto`` means for a stepper: the exact propagator where it applies, else
    the solve_ivp default (the closed form between contact changes, which ``auto`` takes for a
    whole run with backlash, is not kept alive across communication steps)."""
    method = resolve_auto(model)
    return method if method in ("exact", *ODE_CLASSES) else DEFAULT_ODE_METHOD


#: the key of the saved attributes of an object nested in the solver (LSODA's work object);
#: a tagged plain dict, so a snapshot pickles with builtins and numpy only
NESTED = "__nested__"


def _save_attrs(obj: Any) -> dict[str, Any]:
    """Deep copy of the non-callable attributes of ``obj`` (recursing into helper objects)."""
    out: dict[str, Any] = {}
    for key, val in vars(obj).items():
        if callable(val) and not isinstance(val, np.ndarray):
            continue  # right-hand side and Jacobian closures: rebuilt from the model
        if hasattr(val, "__dict__") and not isinstance(val, np.ndarray | np.generic):
            out[key] = {NESTED: _save_attrs(val)}
        else:
            out[key] = copy.deepcopy(val)
    return out


def _load_attrs(obj: Any, saved: dict[str, Any]) -> None:
    """Put saved attributes back. Arrays are copied *into* the fresh solver's own arrays where
    shapes match, so views stay views (DOP853's ``K`` is a view of ``K_extended``)."""
    for key, val in saved.items():
        cur = getattr(obj, key, None)
        if isinstance(val, dict) and set(val) == {NESTED}:
            _load_attrs(cur, val[NESTED])
        elif _copy_into(cur, val):
            pass
        elif isinstance(val, list) and isinstance(cur, list) and len(cur) == len(val):
            # LSODA's call_args holds its work arrays: keep them the very same objects
            for i, item in enumerate(val):
                if not _copy_into(cur[i], item):
                    cur[i] = copy.deepcopy(item)
        else:
            setattr(obj, key, copy.deepcopy(val))


def _copy_into(cur: Any, val: Any) -> bool:
    if (isinstance(val, np.ndarray) and isinstance(cur, np.ndarray) and cur.shape == val.shape
            and cur.dtype == val.dtype and cur.flags.writeable):
        np.copyto(cur, val)
        return True
    return False


class _Propagator:
    """``z -> expm(M s) z`` for one constant matrix ``M``, on plain Python floats.

    A co-simulation master steps with a fixed communication step, and the stiffness is
    periodic: the piece durations ``s`` repeat (up to rounding of the times). Their matrices
    ``expm(M s)`` are computed once (:class:`gear_dyn.solvers.exact._Exponential`) for ``s``
    rounded to a grid of width ``q`` (a power of two with ``rho q <= 1e-6``, ``rho`` the
    spectral radius of ``M``), and the remainder ``d = s - s_grid`` (``|d| <= q / 2``) is
    applied through ``expm(M d) = I + M d + (M d)^2 / 2 + O((rho d)^3)``: the neglected term
    is below 1e-19 (times the eigenvector condition, < 1e3), far below rounding. Without a
    usable eigendecomposition every call takes the exact propagator as before.
    """

    MAX_CACHED = 4096

    def __init__(self, m: FloatArray, tol: float) -> None:
        self.ex = _Exponential(m, tol)
        n = m.shape[0]
        self.rows = [tuple(r) for r in m[:-1].tolist()]  # M z (the last row of M is zero)
        self.sq = [tuple(r[:-1]) for r in m[:-1, :].tolist()]  # M w for w with w[-1] = 0
        self.n = n
        rho = float(np.max(np.abs(self.ex.lam))) if self.ex.eigen else 0.0
        self.q = 2.0 ** math.floor(math.log2(1e-6 / rho)) if rho > 0 else 0.0
        self.cache: dict[int, list[tuple[float, ...]]] = {}

    def apply(self, s: float, z: list[float]) -> list[float]:
        """``expm(M s) z`` (``z`` augmented: its last entry is 1)."""
        q = self.q
        if not q:
            return self.ex.apply(np.array([s]), np.array(z)[None, :])[0].tolist()
        k = round(s / q)
        phi = self.cache.get(k)
        if phi is None:
            if len(self.cache) >= self.MAX_CACHED:
                self.cache.clear()
            phi = self.cache[k] = [tuple(r) for r in self.ex(np.array([k * q]))[0][:-1].tolist()]
        d = s - k * q
        if self.n == 3:  # two states (the single-DOF model): the same sums, unrolled
            x, v = z[0], z[1]
            if d:
                (a0, a1, a2), (b0, b1, b2) = self.rows
                w0, w1 = a0 * x + a1 * v + a2, b0 * x + b1 * v + b2  # M z
                h2 = 0.5 * d * d
                x, v = (x + d * w0 + h2 * (a0 * w0 + a1 * w1),
                        v + d * w1 + h2 * (b0 * w0 + b1 * w1))
            (p0, p1, p2), (r0, r1, r2) = phi
            return [p0 * x + p1 * v + p2, r0 * x + r1 * v + r2, 1.0]
        if d:
            w = [sum(map(operator.mul, r, z)) for r in self.rows]  # M z
            w2 = [sum(map(operator.mul, r, w)) for r in self.sq]  # M^2 z
            h2 = 0.5 * d * d
            z = [zi + d * wi + h2 * vi for zi, wi, vi in zip(z[:-1], w, w2, strict=True)] + [1.0]
        return [sum(map(operator.mul, r, z)) for r in phi] + [1.0]


class Stepper:
    """Integrator state of one model, advanced by communication steps.

    Parameters
    ----------
    model : Model
        Any gear_dyn model (the face of :mod:`gear_dyn.models.base`).
    settings : SolverSettings
        Method (``auto``, ``exact`` or a solve_ivp method name), rtol, atol, max_step.
    t0 : float
        Start time in s.
    y0 : ndarray or None
        Initial state; None uses ``model.initial_state()``.

    Raises
    ------
    InputError
        ``exact`` asked for a model that is not piecewise-constant linear.
    """

    def __init__(self, model: Model, settings: SolverSettings, t0: float = 0.0,
                 y0: FloatArray | None = None) -> None:
        # a whole-run method (periodic step maps) is not kept alive across steps: auto's choice
        method = (stepper_method(model) if settings.method in ("auto", "periodic")
                  else settings.method)
        if method == "exact" and model.linear_segments(0.0, 1.0 / model.mesh_frequency) is None:
            raise InputError("solver.method = 'exact' needs a linear model with "
                             "piecewise-constant coefficients; use DOP853 or LSODA")
        self.model = model
        self.settings = replace(settings, method=method)
        self.method = method
        self.t = float(t0)
        self.y = np.array(model.initial_state() if y0 is None else y0, dtype=float)
        self._switches: FloatArray = np.empty(0)
        self._switch_end: float | None = None
        self._solver: OdeSolver | None = None
        # contact changes (backlash): restart the solver where one happens, as integrate does
        self._events = list(model.contact_events())
        self._dirs: list[float] = []
        self._g: list[float] = []
        self._cut: tuple[float, FloatArray] | None = None
        self._cut_event: int | None = None
        self.n_events = 0
        self._pieces: list[tuple[float, float, FloatArray, FloatArray]] = []
        self._props: list[_Propagator] = []  # the propagator of each piece
        self._piece = 0
        self._exps: dict[bytes, _Propagator] = {}

    # ------------------------------------------------------------------ helpers
    @property
    def atol(self) -> FloatArray:
        """Absolute tolerances per state (:func:`gear_dyn.solvers.ode.atol_of`)."""
        return atol_of(self.model, self.settings)

    def _next_switch(self, t: float) -> float:
        """First switching instant after ``t``, from switching times computed for windows of
        64 mesh periods from the start time (some models find them numerically, too costly per
        restart); the windows never depend on the announced stop time."""
        sw = self._switches
        i = int(np.searchsorted(sw, t, side="right"))
        if i < sw.size:
            return float(sw[i])
        period = 1.0 / self.model.mesh_frequency
        if self._switch_end is None:
            start, end = t, t + 64.0 * period
        else:  # windows overlap by half a period: an instant on a window end is not lost
            start = max(t, self._switch_end - 0.5 * period)
            end = start + 64.0 * period
        while True:
            found = np.asarray(self.model.switching_times(start, end), dtype=float)
            self._switches, self._switch_end = found[found > t], end
            if self._switches.size:
                return float(self._switches[0])
            if end - t > 4096.0 * period:  # a smooth model: no switching instants at all
                return math.inf
            start, end = end - 0.5 * period, end + 64.0 * period

    def _new_solver(self, t: float, y: FloatArray) -> OdeSolver:
        cls = ODE_CLASSES[self.method]
        extra: dict[str, Any] = {"jac": self.model.jac} if self.method in IMPLICIT else {}
        # neither the switching windows nor the solver's bound depend on the announced stop
        # time: an FMU's outputs at t must not depend on what the master plans after t
        t_bound = self._next_switch(t)
        # explicit Runge-Kutta steps limited as in integrate (their dense output, which gives
        # the communication points inside a step, stays within the tolerance)
        return cls(self.model.rhs, t, y, t_bound, rtol=self.settings.rtol, atol=self.atol,
                   max_step=step_limit(self.model, self.settings), **extra)

    # ------------------------------------------------------------------ stepping
    def advance(self, t1: float) -> FloatArray:
        """Integrate to ``t1`` (s, >= the current time) and return the state there.

        Raises
        ------
        InputError
            ``t1`` is before the current time.
        SolverError
            The solver failed or produced non-finite states (with scipy's message).
        """
        self.step_to(t1)
        return self.y.copy()

    def step_to(self, t1: float) -> None:
        """:meth:`advance` without returning the state (read ``y``; the FMU's per-step
        path). Raises as :meth:`advance` does."""
        if not t1 >= self.t:
            raise InputError(f"communication point t = {t1:.9g} s is before the current time "
                             f"{self.t:.9g} s; restore an FMU state to go back")
        if t1 == self.t:
            return
        if self.method == "exact":
            self.y = self._advance_exact(t1)  # checks its states itself (plain floats)
            self.t = float(t1)
            return
        y = self._advance_ode(t1)
        if not np.all(np.isfinite(y)):
            raise SolverError(f"{self.method} produced non-finite states near t = {t1:.6g} s; "
                              "the response diverges (parametric instability?) or the "
                              "tolerances are too loose")
        self.y, self.t = y, float(t1)

    def _advance_exact(self, t1: float) -> FloatArray:
        t = self.t
        z = self.y.tolist()
        z.append(1.0)
        pieces, props = self._pieces, self._props
        while t < t1:
            i = self._piece
            if i >= len(pieces) or not pieces[i][0] <= t < pieces[i][1]:
                self._load_pieces(t, t1)
                pieces, props, i = self._pieces, self._props, 0
            tb = pieces[i][1]
            te = tb if tb < t1 else t1
            z = props[i].apply(te - t, z)
            t = te
            if te == tb:
                self._piece = i + 1
        z.pop()
        if not all(map(math.isfinite, z)):
            raise SolverError(f"exact produced non-finite states near t = {t1:.6g} s; the "
                              "response diverges (parametric instability?)")
        return np.array(z)

    def _load_pieces(self, t: float, t1: float) -> None:
        horizon = max(t1, t + 64.0 / self.model.mesh_frequency)
        pieces = self.model.linear_segments(t, horizon)
        if not pieces:
            raise InputError("solver.method = 'exact' needs a linear model with "
                             "piecewise-constant coefficients; use DOP853 or LSODA")
        tol = 4 * float(np.spacing(max(t1, 1.0)))
        props = []
        for _ta, _tb, a, g in pieces:  # one propagator per distinct piece matrix
            key = a.tobytes() + np.asarray(g, float).tobytes()
            prop = self._exps.get(key)
            if prop is None:
                m = np.zeros((a.shape[0] + 1, a.shape[0] + 1))
                m[:-1, :-1], m[:-1, -1] = a, g
                prop = self._exps[key] = _Propagator(m, tol)
            props.append(prop)
        self._pieces, self._props = pieces, props
        self._piece = 0

    def _advance_ode(self, t1: float) -> FloatArray:
        solver = self._solver
        if solver is None:
            solver = self._start(self.t, self.y, None)
        while True:
            if self._cut is not None:  # a contact change inside the last step
                te, ye = self._cut
                if t1 <= te:
                    return np.asarray(solver.dense_output()(t1), dtype=float)
                solver = self._start(te, ye, self._cut_event)
                continue
            if solver.t >= t1:
                if solver.t == t1 or solver.t_old is None:
                    return np.array(solver.y, dtype=float)
                return np.asarray(solver.dense_output()(t1), dtype=float)
            if solver.status == "finished":  # reached a switching instant: restart there
                solver = self._start(solver.t, np.array(solver.y), None)
                continue
            msg = solver.step()
            if solver.status == "failed":
                raise SolverError(f"{self.method} failed at t = {solver.t:.6g} s: {msg}; try a "
                                  "smaller rtol or an implicit method (Radau, BDF)")
            if self._events:
                self._check_events(solver)

    def _start(self, t: float, y: FloatArray, event: int | None) -> OdeSolver:
        """New solver at ``(t, y)``; after a contact change of event ``event`` only that
        function's opposite crossing is looked for (as :mod:`gear_dyn.solvers.events` does)."""
        solver = self._solver = self._new_solver(t, y)
        self._cut = None
        self._cut_event = None
        if self._events:
            self._dirs = [0.0] * len(self._events)
            if event is not None:
                span = max(solver.t_bound - t, 0.0) if math.isfinite(solver.t_bound) else 0.0
                dt = 1e-9 * (span or 1.0 / self.model.mesh_frequency)
                slope = self._events[event](t + dt, y + dt * self.model.rhs(t, y))
                self._dirs[event] = -1.0 if slope > 0 else 1.0
            self._g = [float(fn(t, y)) for fn in self._events]
            self.n_events += event is not None
        return solver

    def _check_events(self, solver: OdeSolver) -> None:
        """Locate the first contact change in the last step (root of g on the dense output)."""
        from scipy.optimize import brentq

        g_new = [float(fn(solver.t, solver.y)) for fn in self._events]
        first: tuple[float, int] | None = None
        sol = None
        for i, (g0, g1, d) in enumerate(zip(self._g, g_new, self._dirs, strict=True)):
            up, down = g0 <= 0 <= g1, g0 >= 0 >= g1
            if not ((up and d >= 0) or (down and d <= 0)) or g0 == g1:
                continue
            sol = sol or solver.dense_output()
            fn = self._events[i]
            tr = float(brentq(lambda tt, fn=fn, sol=sol: fn(tt, sol(tt)), solver.t_old,
                              solver.t, xtol=4 * EPS, rtol=4 * EPS))
            if first is None or tr < first[0]:
                first = (tr, i)
        self._g = g_new
        if first is not None and sol is not None:
            self._cut = (first[0], np.asarray(sol(first[0]), dtype=float))
            self._cut_event = first[1]

    def replace_model(self, model: Model) -> None:
        """Continue with another model (e.g. a new input value) from the current state.

        The solver is restarted at the current time: the right-hand side jumps there.
        """
        self.model = model
        self._solver = None
        self._events = list(model.contact_events())
        self._cut, self._cut_event = None, None
        self._pieces, self._props, self._piece, self._exps = [], [], 0, {}
        self._switches, self._switch_end = np.empty(0), None

    # ------------------------------------------------------------------ state
    def snapshot(self) -> dict[str, Any]:
        """Everything needed to continue exactly from here (plain, picklable data)."""
        solver = None
        if self._solver is not None:
            solver = {"t_bound": float(self._solver.t_bound),
                      "attrs": _save_attrs(self._solver)}
        return {"t": self.t, "y": self.y.copy(), "method": self.method, "solver": solver,
                # the switching instants in use (found numerically by some models: another
                # search window could move them in the last digits)
                "switches": self._switches.copy(), "switch_end": self._switch_end,
                "events": {"dirs": list(self._dirs), "g": list(self._g),
                           "cut": None if self._cut is None else
                           (self._cut[0], self._cut[1].copy()),
                           "cut_event": self._cut_event, "n_events": self.n_events}}

    def restore(self, snap: dict[str, Any]) -> None:
        """Return to a :meth:`snapshot` (taken with the same model)."""
        if snap["method"] != self.method:
            raise InputError(f"FMU state was saved with solver {snap['method']!r}, this "
                             f"instance runs {self.method!r}")
        self.t = float(snap["t"])
        self.y = np.array(snap["y"], dtype=float)
        self._pieces, self._props, self._piece = [], [], 0
        self._switches = np.array(snap["switches"], dtype=float)
        self._switch_end = snap["switch_end"]
        self._events = list(self.model.contact_events())
        ev = snap["events"]
        self._dirs, self._g = list(ev["dirs"]), list(ev["g"])
        self._cut = None if ev["cut"] is None else (float(ev["cut"][0]),
                                                    np.array(ev["cut"][1], dtype=float))
        self._cut_event, self.n_events = ev["cut_event"], int(ev["n_events"])
        s = snap["solver"]
        if s is None:
            self._solver = None
            return
        attrs = s["attrs"]
        solver = self._new_solver(float(attrs["t"]), np.array(attrs["y"], dtype=float))
        _load_attrs(solver, attrs)
        self._solver = solver
