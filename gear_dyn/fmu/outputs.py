"""The FMU's outputs at one communication point, as plain Python floats.

A master reads the outputs after every communication step, one instant at a time; the model's
vectorised ``outputs`` costs tens of microseconds of numpy set-up for one sample, more than
the exact step itself. :func:`output_writer` returns a function that writes the output values
at ``(t, y)`` into the slave's dict of outputs:

- for the single-DOF model (:class:`gear_dyn.models.sdof.SDOFModel`) the same formulas as its
  ``outputs`` on Python floats, with the scalar stiffness of the solver's right-hand side
  (:func:`gear_dyn.models.sdof.scalar_stiffness`, same values to rounding);
- for every other model, ``model.outputs`` on a one-sample grid.

The test ``tests/fmu/test_fmu_outputs.py`` checks that both agree with ``model.outputs`` on
every example scene with the single-DOF model (with transmission error and backlash too).
"""

from __future__ import annotations

from collections.abc import Callable, Collection
from typing import Any

import numpy as np

from gear_dyn.fmu.inputs import driven_speed
from gear_dyn.geometry import GearPair
from gear_dyn.models.sdof import SDOFModel, scalar_stiffness

#: write(t, y, out): the outputs at time t (s) and state y into the dict out (by FMU name)
Writer = Callable[[float, Any, dict[str, float]], None]


def output_writer(model: Any, pair: GearPair | None, speed: float,
                  names: Collection[str]) -> Writer:
    """Writer of the outputs ``names`` (FMU variable names) of ``model``.

    Parameters
    ----------
    model : Model
        The model the stepper runs (with the current inputs applied).
    pair : GearPair or None
        The gear pair (for ``driven_speed`` of the single-DOF model).
    speed : float
        Pinion speed input in rad/s (for ``driven_speed``).
    names : collection of str
        The FMU's output variables: ``state.<label>``, the model's outputs, ``driven_speed``.
    """
    names = set(names)
    if type(model) is SDOFModel and pair is not None and names <= _SDOF_NAMES:
        return _sdof_writer(model, pair, speed)
    labels = [f"state.{label}" for label in model.state_labels]

    def write(t: float, y: Any, out: dict[str, float]) -> None:
        for name, value in zip(labels, y.tolist(), strict=True):
            out[name] = value
        for name, arr in model.outputs(np.array([t]), y[:, None]).items():
            if name in names:
                out[name] = float(np.asarray(arr).ravel()[0])
        if "driven_speed" in names and pair is not None:
            out["driven_speed"] = float(driven_speed(pair, speed, float(y[1])))
    return write


_SDOF_NAMES = {"state.x", "state.v", "dte", "mesh_force", "stiffness", "driven_speed"}


def _sdof_writer(model: SDOFModel, pair: GearPair, speed: float) -> Writer:
    """``SDOFModel.outputs`` and ``driven_speed`` for one instant, on floats."""
    k = scalar_stiffness(model.stiffness)
    fm, p0, c = model.mesh_frequency, model.phase0, model.damping
    te, b = model.transmission_error, model.backlash
    w1 = pair.rb1 * speed  # driven_speed: (r_b1 w1 - v) / r_b2
    rb2 = pair.rb2

    def write(t: float, y: Any, out: dict[str, float]) -> None:
        x, v = y.tolist()
        p = fm * t + p0
        kt = float(k(p))
        u, ud = x, v
        if te is not None:
            u = x - float(te.value(p))
            ud = v - fm * float(te.slope(p))
        if b is not None:
            u = u - b if u > b else (u + b if u < -b else 0.0)
        out["state.x"] = out["dte"] = x
        out["state.v"] = v
        out["mesh_force"] = kt * u + c * ud
        out["stiffness"] = kt
        out["driven_speed"] = (w1 - v) / rb2
    return write

