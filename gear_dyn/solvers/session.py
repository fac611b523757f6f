"""The stepwise session: the solve_ivp driver's integration advanced point by point.

A caller that asks for the state at ``t + h`` again and again (the FMU's communication steps)
cannot use :func:`gear_dyn.solvers.ode.flow`, which needs the whole output grid up front.
:class:`Session` advances the driver's own integrator,
:class:`~gear_dyn.solvers.events.RestartingSolver` (one scipy ``OdeSolver`` kept alive,
restarted at the switching instants and at contact changes located by the one event locator),
to each point in turn and reads the state there from its dense output, so the points never
disturb the integration; with :func:`~gear_dyn.solvers.ode.step_limit` and
:func:`~gear_dyn.solvers.ode.atol_of`. What the session adds: the switching instants found for
windows of mesh periods (the stop time is not known), a restart where the caller changes the
model (:meth:`Session.replace_model`, an input). ``exact`` carries the state with cached matrix
exponentials (:class:`gear_dyn.solvers.exact.StepPropagator`). What this buys and how it is
tested: docs/fmu.md, "Inside doStep".
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError, SolverError
from gear_dyn.models.base import Model
from gear_dyn.solvers.events import ODE_METHODS, RestartingSolver
from gear_dyn.solvers.exact import StepPropagator
from gear_dyn.solvers.integrate import resolve_auto
from gear_dyn.solvers.ode import atol_of, step_limit
from gear_dyn.solvers.settings import DEFAULT_ODE_METHOD, SolverSettings

FloatArray = NDArray[np.float64]


def session_method(model: Model) -> str:
    """The method ``auto`` means for a session: the exact propagator where it applies, else
    the solve_ivp default (the closed form between contact changes, which ``auto`` takes for a
    whole run with backlash, is not kept alive across steps)."""
    method = resolve_auto(model)
    return method if method in ("exact", *ODE_METHODS) else DEFAULT_ODE_METHOD


class Session:
    """Integrator state of one model, advanced point by point.

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
        method = (session_method(model) if settings.method in ("auto", "periodic")
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
        self._ode: RestartingSolver | None = None
        self._events_before = 0  # contact changes located with the models replaced
        self._pieces: list[tuple[float, float, FloatArray, FloatArray]] = []
        self._props: list[StepPropagator] = []  # the propagator of each piece
        self._piece = 0
        self._exps: dict[bytes, StepPropagator] = {}

    # ------------------------------------------------------------------ helpers
    @property
    def n_events(self) -> int:
        """Contact changes located so far."""
        return self._events_before + (self._ode.n_events if self._ode is not None else 0)

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

    def _new_ode(self, t: float, y: FloatArray) -> RestartingSolver:
        """The restarted solver from ``(t, y)``: the model's own functions, its contact events,
        explicit Runge-Kutta steps limited as in integrate (their dense output, which gives the
        communication points inside a step, stays within the tolerance). Neither the switching
        windows nor the solver's bounds depend on the announced stop time: an FMU's outputs at
        t must not depend on what the master plans after t."""
        model = self.model
        return RestartingSolver(
            self.method, lambda ta, tb: (model.rhs, model.jac), list(model.contact_events()),
            len(model.state_labels), self._next_switch, t, y, self.settings.rtol, self.atol,
            step_limit(model, self.settings), span=1.0 / model.mesh_frequency)

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
        if self._ode is None:
            self._ode = self._new_ode(self.t, self.y)
        self.y = self._ode.advance(np.array([float(t1)]))[:, 0]
        self.t = float(t1)

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
                prop = self._exps[key] = StepPropagator(m, tol)
            props.append(prop)
        self._pieces, self._props = pieces, props
        self._piece = 0

    def replace_model(self, model: Model) -> None:
        """Continue with another model (e.g. a new input value) from the current state.

        The solver is restarted at the current time: the right-hand side jumps there.
        """
        self.model = model
        if self._ode is not None:
            self._events_before += self._ode.n_events
        self._ode = None
        self._pieces, self._props, self._piece, self._exps = [], [], 0, {}
        self._switches, self._switch_end = np.empty(0), None
