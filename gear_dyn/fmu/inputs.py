"""How the FMU inputs (pinion speed and torque) enter a built model, without rebuilding it.

Each function returns the keyword changes for ``dataclasses.replace(base_model, **changes)``,
so a changed input costs a cheap model copy (no stiffness recomputation) and the changes are
plain numbers that an FMU state can store.
"""

from __future__ import annotations

from dataclasses import fields, is_dataclass
from typing import Any

from gear_dyn.errors import InputError
from gear_dyn.geometry import GearPair, mesh_frequency


def input_changes(model: Any, pair: GearPair, speed: float, torque: float,
                  t: float) -> dict[str, float]:
    """Changes to ``model`` for pinion speed ``speed`` (rad/s) and torque ``torque`` (N m).

    The single-DOF model takes W = T1 / r_b1 and f_m = z1 w1 / (2 pi); its mesh phase
    ``p = f_m t + p0`` stays continuous at ``t`` (s) through a new ``p0``. Models with ``speed``
    and ``torque`` fields (the torsional model) take them directly.

    Raises
    ------
    InputError
        The model has no known way to take the inputs.
    """
    if model.mesh_periodic:  # the single-DOF mesh model: only f_m, W and the phase change
        f_m = mesh_frequency(pair, speed)
        phase_now = model.mesh_frequency * t + model.phase0
        return {"static_load": torque / pair.rb1, "mesh_frequency": f_m,
                "phase0": phase_now - f_m * t}
    names = {f.name for f in fields(model)} if is_dataclass(model) else set()
    if {"speed", "torque"} <= names:
        return {"speed": speed, "torque": torque}
    raise InputError(f"model {type(model).__name__} does not take the inputs operating.speed "
                     "and operating.torque")


def driven_speed(pair: GearPair, speed: float, v: Any) -> Any:
    """Driven gear speed (rad/s) of the single-DOF model: w2 = (r_b1 w1 - x') / r_b2."""
    return (pair.rb1 * speed - v) / pair.rb2
