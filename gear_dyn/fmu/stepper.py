"""The FMU's stepper: the stepwise session of the solvers, with the FMU's state API.

A co-simulation master asks for the state at ``t + h`` again and again. The integration itself,
one scipy ``OdeSolver`` kept alive across communication steps and restarted where the solve_ivp
driver restarts (switching instants, contact changes) and where the importer changes an input,
is :class:`gear_dyn.solvers.session.Session`; ``exact`` carries the state with
:class:`gear_dyn.solvers.exact.StepPropagator`. What this buys and how it is tested:
docs/fmu.md, "Inside doStep".

:class:`Stepper` adds what only an FMU needs: :meth:`Stepper.snapshot` and
:meth:`Stepper.restore` save and restore the whole integrator state (the solver's step size,
stage derivatives, error history, LSODA work arrays), not only the model state, so a restored
run continues bit for bit as the original did (FMI's get/set FMU state).
"""

from __future__ import annotations

import copy
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError
from gear_dyn.models.base import Model
from gear_dyn.solvers.session import Session, session_method

FloatArray = NDArray[np.float64]


def stepper_method(model: Model) -> str:
    """The method ``auto`` means for the FMU's stepper
    (:func:`~gear_dyn.solvers.session.session_method`)."""
    return session_method(model)


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


class Stepper(Session):
    """The stepwise session of one model (:class:`~gear_dyn.solvers.session.Session`, same
    parameters), with ``snapshot`` and ``restore`` of its whole integrator state."""

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
