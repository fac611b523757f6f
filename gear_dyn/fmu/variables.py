"""What an exported FMU exposes: parameters, inputs and outputs, with units and descriptions.

The FMU's variables come from the scene it was built from:

- every scalar key of every table present in the scene is a **parameter** named
  ``table.key`` (SI value of the scene as start value; ``Integer``, ``Real``, ``String`` or
  ``Boolean``), except the run length and output grid of ``[solver]`` (they define the
  DefaultExperiment instead) and the free text of ``[scene]``;
- ``operating.speed`` (pinion speed, rad/s) and ``operating.torque`` (pinion torque, N m) are
  **inputs**: the importer may change them at any communication point;
- the model's states (``state.<label>``) and derived series (``dte``, ``mesh_force``, ...) are
  **outputs**, plus ``driven_speed`` for the single-DOF model.

The spec is plain JSON (written into the FMU's resources), so the FMU needs neither pint nor
the scene file at run time.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from gear_dyn.errors import InputError
from gear_dyn.scene import SECTIONS, Scene, build_plan

SPEC_FILE = "gear_dyn_fmu.json"
SPEC_FORMAT = 1

#: inputs (table, key): changeable at every communication point
INPUTS = (("operating", "speed"), ("operating", "torque"))
#: scene keys that describe the experiment, not the model
EXPERIMENT_KEYS = {("solver", "periods"), ("solver", "steady_periods"),
                   ("solver", "samples_per_period")}
SKIP_TABLES = {"scene"}

#: gear_dyn unit -> (FMI unit name, SI base-unit exponents, display units (name, factor))
UNITS: dict[str, tuple[str, dict[str, int], tuple[tuple[str, float], ...]]] = {
    "m": ("m", {"m": 1}, (("mm", 1e3), ("um", 1e6))),
    "rad": ("rad", {"rad": 1}, (("deg", 180.0 / math.pi),)),
    "rad/s": ("rad/s", {"rad": 1, "s": -1}, (("rpm", 30.0 / math.pi),)),
    "N*m": ("N.m", {"kg": 1, "m": 2, "s": -2}, ()),
    "N": ("N", {"kg": 1, "m": 1, "s": -2}, (("kN", 1e-3),)),
    "Pa": ("Pa", {"kg": 1, "m": -1, "s": -2}, (("MPa", 1e-6), ("GPa", 1e-9))),
    "kg/m**3": ("kg/m3", {"kg": 1, "m": -3}, ()),
    "kg*m**2": ("kg.m2", {"kg": 1, "m": 2}, ()),
    "kg": ("kg", {"kg": 1}, ()),
    "N/m": ("N/m", {"kg": 1, "s": -2}, ()),
    "N*s/m": ("N.s/m", {"kg": 1, "s": -1}, ()),
    "m/s": ("m/s", {"m": 1, "s": -1}, ()),
    "s": ("s", {"s": 1}, ()),
    "Hz": ("Hz", {"s": -1}, ()),
}

#: outputs by name: (gear_dyn unit, description)
OUTPUTS: dict[str, tuple[str, str]] = {
    "dte": ("m", "dynamic transmission error r_b1 th1 - r_b2 th2 along the line of action"),
    "delta": ("m", "mesh deflection (DTE plus eccentric displacement minus static TE)"),
    "mesh_force": ("N", "dynamic mesh force along the line of action"),
    "stiffness": ("N/m", "mesh stiffness k(t)"),
    "driven_speed": ("rad/s", "speed of the driven gear"),
    "w1": ("rad/s", "pinion speed"),
    "w2": ("rad/s", "driven gear speed"),
    "w2_kinematic": ("rad/s", "driven speed of the rigid (eccentric) pair"),
    "e_ecc": ("m", "eccentric displacement along the line of action"),
    "contact_length": ("m", "total contact-line length"),
    "friction_torque_pinion": ("N*m", "friction torque on the pinion"),
    "friction_torque_gear": ("N*m", "friction torque on the gear"),
}
STATES: dict[str, tuple[str, str]] = {
    "x": ("m", "state: dynamic transmission error"),
    "v": ("m/s", "state: rate of the dynamic transmission error"),
    "q1": ("rad", "state: pinion angle relative to the nominal rotation"),
    "q2": ("rad", "state: gear angle relative to the nominal rotation"),
    "q1_dot": ("rad/s", "state: pinion speed relative to the nominal speed"),
    "q2_dot": ("rad/s", "state: gear speed relative to the nominal speed"),
}

_KINDS = {"int": "Integer", "float": "Real", "str": "String", "bool": "Boolean"}


def _jsonable(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: _jsonable(v) for k, v in value.items() if v is not None}
    if isinstance(value, list | tuple):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value


def _bounds(field: Any, start: Any) -> dict[str, Any]:
    """FMI ``min``/``max`` (the field's physical range; an open bound such as ``0 < x`` gives
    ``min = 0``, the FMU still refuses 0 itself) and, for Reals, ``nominal`` = |start|."""
    out: dict[str, Any] = {}
    if field.kind not in ("float", "int"):
        return out
    cast = int if field.kind == "int" else float
    if field.low is not None and math.isfinite(field.low):
        out["min"] = cast(math.ceil(field.low) if cast is int else field.low)
    if field.high is not None and math.isfinite(field.high):
        out["max"] = cast(math.floor(field.high) if cast is int else field.high)
    if field.kind == "float" and isinstance(start, int | float) and start != 0:
        out["nominal"] = abs(float(start))
    return out


def fmu_spec(scene: Scene) -> dict[str, Any]:
    """The FMU description of a scene: SI tables, variables and the default experiment.

    Builds the scene's model once (so a bad scene is refused at build time, and the output
    names are those the model really produces).

    Raises
    ------
    SceneError
        The scene is invalid or its model cannot be built.
    """
    if "deviations" in scene.tables:
        raise InputError("[deviations]: an FMU takes a transmission error of mesh harmonics "
                         "only; deviations repeat over the hunting period: remove the table")
    plan = build_plan(scene)
    model = plan.model
    kind = scene.get("scene")["model"]
    variables: list[dict[str, Any]] = []
    for table, values in scene.tables.items():
        if table in SKIP_TABLES or table not in SECTIONS:
            continue
        for f in SECTIONS[table].fields:
            value = values.get(f.name)
            if value is None or f.kind == "floatlist" or (table, f.name) in EXPERIMENT_KEYS:
                continue
            is_input = (table, f.name) in INPUTS
            doc = f.doc or f.name
            unit_txt = f" [{f.unit}]" if f.unit else ""
            variables.append({
                "name": f"{table}.{f.name}", "table": table, "key": f.name,
                "type": "Enumeration" if f.choices else _KINDS[f.kind],
                **({"choices": list(f.choices)} if f.choices else {}),
                "causality": "input" if is_input else "parameter",
                "variability": "continuous" if is_input else "fixed",
                "unit": f.unit, "start": value,
                "description": f"{SECTIONS[table].name}: {doc}{unit_txt}",
                **_bounds(f, value),
            })
    y0 = model.initial_state()
    out_names = list(model.outputs(np.zeros(1), np.asarray(y0, float)[:, None]))
    if kind == "sdof":
        out_names.append("driven_speed")
    for label in model.state_labels:
        unit, doc = STATES.get(label, ("", f"state {label}"))
        variables.append({"name": f"state.{label}", "type": "Real", "causality": "output",
                          "variability": "continuous", "unit": unit, "description": doc})
    for name in out_names:
        unit, doc = OUTPUTS.get(name, ("", f"model output {name}"))
        variables.append({"name": name, "type": "Real", "causality": "output",
                          "variability": "continuous", "unit": unit, "description": doc})
    return {**scene_record(scene, plan), "variables": variables}


def scene_record(scene: Scene, plan: Any) -> dict[str, Any]:
    """The scene an FMU was built from, as plain JSON: format, model, name, source, SI tables,
    the default experiment and the mesh frequency (the FMU spec without its variables; the
    native FMU stores this alone, :mod:`gear_dyn.fmu.fmu_info`). ``plan``: the scene's
    ``build_plan``."""
    f_m = plan.model.mesh_frequency
    spp = scene.get("solver")["samples_per_period"]
    return {
        "format": SPEC_FORMAT,
        "model": scene.get("scene")["model"],
        "scene_name": scene.name,
        "source": scene.source,
        "tables": _jsonable(scene.tables),
        "experiment": {"start_time": 0.0, "stop_time": float(plan.t_end),
                       "step_size": 1.0 / (f_m * spp), "tolerance": plan.settings.rtol,
                       "steady_start": float(plan.steady_start)},
        "mesh_frequency": f_m,
    }


def check_spec(spec: Any) -> dict[str, Any]:
    """Check the FMU spec read back from JSON (format and required keys)."""
    if not isinstance(spec, dict) or spec.get("format") != SPEC_FORMAT:
        raise InputError(f"{SPEC_FILE}: not a gear_dyn FMU spec of format {SPEC_FORMAT}")
    for key in ("model", "tables", "variables", "experiment"):
        if key not in spec:
            raise InputError(f"{SPEC_FILE}: missing key {key!r}")
    return spec
