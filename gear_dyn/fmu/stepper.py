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
from gear_dyn.solvers.events import STATE
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
        ode = None
        if self._ode is not None:
            ode = {"solver": _save_attrs(self._ode.solver),
                   "state": copy.deepcopy({k: getattr(self._ode, k) for k in STATE})}
        return {"t": self.t, "y": self.y.copy(), "method": self.method, "ode": ode,
                # the switching instants in use (found numerically by some models: another
                # search window could move them in the last digits)
                "switches": self._switches.copy(), "switch_end": self._switch_end,
                "events_before": self._events_before}

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
        self._events_before = int(snap["events_before"])
        saved = snap["ode"]
        if saved is None:
            self._ode = None
            return
        attrs = saved["solver"]
        ode = self._new_ode(float(attrs["t"]), np.array(attrs["y"], dtype=float))
        _load_attrs(ode.solver, attrs)
        for key, val in copy.deepcopy(saved["state"]).items():
            setattr(ode, key, val)
        self._ode = ode
