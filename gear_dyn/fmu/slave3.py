"""The pythonfmu3 slave: a thin FMI 3.0 co-simulation shell over the same stepper as FMI 2.

Built by ``gear-dyn fmu build --fmi 3`` (:mod:`gear_dyn.fmu.build3`). The physics and the
stepping are those of the FMI 2 slave (:mod:`gear_dyn.fmu.slave`): the parameters form a scene
in SI values, :func:`gear_dyn.scene.build_plan` builds the model,
:class:`gear_dyn.fmu.stepper.Stepper` advances it and :mod:`gear_dyn.fmu.inputs` applies
changed inputs, so both FMUs give the same outputs on the same communication grid. This module
does not import pythonfmu (the FMI 3 FMU carries pythonfmu3 only).

What pythonfmu3 (0.3.4) passes on, and what follows
---------------------------------------------------
- ``fmi3EnterInitializationMode`` reaches Python without its arguments: the start time is
  0 s, the tolerance is the scene's ``solver.rtol`` and an announced stop time is never seen
  (the outputs cannot depend on it). A first doStep from another time is refused.
- Enumerations: pythonfmu3's ``Enumeration`` variable cannot be read or written (it lacks the
  size and dimensions pythonfmu3's ``get_int64`` and ``set_int64`` use), so choice parameters
  are registered as Int64 and the build turns them into ``<Enumeration>`` with an
  EnumerationType (item k = choice k), as for FMI 2; ``fmi3GetInt64``/``fmi3SetInt64`` reach
  them.
- A Python exception in any call is ``fmi3Fatal`` and pythonfmu3 then drops its references to
  the class, the instance and the log queue (yet frees them again later): a refused call logs
  its reason (status error), hands those references back and raises, as the FMI 2 slave does.
  The instance stays valid, so the boot library (``pyboot3.c``, Linux) reports a refusal of
  fmi3Set* and fmi3ExitInitializationMode as ``fmi3Error``.
- FMU state: get/set/serialize keep the whole integrator state, as in FMI 2 (pickled with
  builtins and numpy arrays only).
"""

from __future__ import annotations

import ctypes
import io
import json
import math
import pickle
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any, NoReturn

import numpy as np
from pythonfmu3 import Boolean, Float64, Fmi3Causality, Fmi3Slave, Fmi3Variability, Int32, Int64
from pythonfmu3 import String as String3
from pythonfmu3.default_experiment import DefaultExperiment
from pythonfmu3.enums import Fmi3Status

from gear_dyn.errors import GearDynError, InputError, SolverError
from gear_dyn.fmu.inputs import driven_speed, input_changes
from gear_dyn.fmu.stepper import Stepper
from gear_dyn.fmu.variables import SPEC_FILE, check_spec
from gear_dyn.scene import SECTIONS, build_pair, build_plan, load_feature_sections, parse_scene

#: FMI 2 type name in the spec -> pythonfmu3 variable class (Enumeration: Int64, see above)
_TYPES = {"Real": Float64, "Integer": Int32, "String": String3, "Boolean": Boolean,
          "Enumeration": Int64}
_CAUSALITY = {"parameter": Fmi3Causality.parameter, "input": Fmi3Causality.input,
              "output": Fmi3Causality.output}
_VARIABILITY = {"fixed": Fmi3Variability.fixed, "tunable": Fmi3Variability.tunable,
                "continuous": Fmi3Variability.continuous}


class Fmu3CallError(GearDynError):
    """An FMI 3 call refused by the slave (the message is also logged)."""


def _fmi_call(func: Callable[..., Any]) -> Callable[..., Any]:
    """Wrap an FMI entry point: a failure is logged and refused safely (see module doc)."""

    def wrapper(self: GearDynSlave3, *args: Any) -> Any:
        try:
            return func(self, *args)
        except Fmu3CallError:
            raise
        except Exception as exc:  # every failure becomes a logged, refused call
            self._refuse(f"{func.__name__.strip('_')}: {exc}")

    wrapper.__name__ = func.__name__
    wrapper.__doc__ = func.__doc__
    return wrapper


class _StateUnpickler(pickle.Unpickler):
    """Unpickler for FMU states: builtins and numpy arrays only (no arbitrary objects)."""

    ALLOWED = {("numpy", "ndarray"), ("numpy", "dtype"), ("numpy.core.multiarray", "_reconstruct"),
               ("numpy._core.multiarray", "_reconstruct"), ("numpy.core.multiarray", "scalar"),
               ("numpy._core.multiarray", "scalar"), ("builtins", "complex")}

    def find_class(self, module: str, name: str) -> Any:
        if (module, name) not in self.ALLOWED:
            raise pickle.UnpicklingError(f"FMU state may not contain {module}.{name}")
        return super().find_class(module, name)


class GearDynSlave3(Fmi3Slave):
    """FMI 3.0 co-simulation slave of a gear_dyn scene (single-DOF or torsional model).

    The FMU's generated class derives from this one; the scene comes from the FMU resources
    (``gear_dyn_fmu.json``, written by :func:`gear_dyn.fmu.build3.build_fmu3`).
    """

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._native = "logger" in kwargs  # the native wrapper passes its logger
        spec = check_spec(json.loads(Path(str(self.resources), SPEC_FILE).read_text("utf-8")))
        load_feature_sections()
        self._spec = spec
        self.author = "gear_dyn"
        self.license = "MIT"
        self.description = (f"gear_dyn {spec['model']} model of scene '{spec['scene_name']}' "
                            "(FMI 3.0 co-simulation)")
        ex = spec["experiment"]
        self.default_experiment = DefaultExperiment(
            start_time=0.0, stop_time=ex["stop_time"], step_size=ex["step_size"],
            tolerance=ex["tolerance"])
        self._tables: dict[str, dict[str, Any]] = {k: dict(v) for k, v in spec["tables"].items()}
        self._outputs: dict[str, float] = {}
        self._phase = "instantiated"
        self._stepper: Stepper | None = None
        self._base_model: Any = None
        self._pair: Any = None
        self._applied: tuple[float, float] | None = None
        self._changes: dict[str, float] = {}
        self._built_tables: dict[str, dict[str, Any]] | None = None
        for v in spec["variables"]:
            self._register(v)
        # FMI 3 requires the independent variable; last, so the other value references are
        # those of the FMI 2 FMU
        self.register_variable(Float64(
            "time", causality=Fmi3Causality.independent, variability=Fmi3Variability.continuous,
            description="simulation time", unit="s", getter=self._time), nested=False)

    def _time(self) -> float:
        return float(self._stepper.t) if self._stepper is not None else 0.0

    # ------------------------------------------------------------------ variables
    def _register(self, v: dict[str, Any]) -> None:
        name, causality = v["name"], v["causality"]
        getter: Callable[[], Any]
        setter: Callable[[Any], None] | None = None
        if causality == "output":
            self._outputs[name] = 0.0
            getter = self._output_getter(name)
        else:
            getter, setter = self._value_access(v["table"], v["key"], causality)
        if v["type"] == "Enumeration":
            getter, setter = self._enum_access(v, getter, setter)
        var = _TYPES[v["type"]](
            name, causality=_CAUSALITY[causality], variability=_VARIABILITY[v["variability"]],
            description=v["description"], getter=getter, setter=setter)
        self.register_variable(var, nested=False)

    def _output_getter(self, name: str) -> Callable[[], float]:
        return lambda: self._outputs[name]

    def _value_access(self, table: str, key: str, causality: str
                      ) -> tuple[Callable[[], Any], Callable[[Any], None]]:
        def setter(value: Any) -> None:
            self._set_value(table, key, causality, value)
        return (lambda: self._tables[table][key]), setter

    def _enum_access(self, v: dict[str, Any], getter: Callable[[], Any],
                     setter: Callable[[Any], None] | None
                     ) -> tuple[Callable[[], int], Callable[[Any], None] | None]:
        """Getter and setter of an enumeration: item k (1..n) stands for choice k."""
        choices: list[str] = v["choices"]

        def get() -> int:
            return choices.index(getter()) + 1

        def put(value: Any) -> None:
            assert setter is not None
            if not 1 <= int(value) <= len(choices):
                self._refuse(f"set {v['name']}: {v['name']} = {value}: valid range "
                             f"1 <= x <= {len(choices)} ("
                             + ", ".join(f"{i} {c}" for i, c in enumerate(choices, 1)) + ")")
            setter(choices[int(value) - 1])

        return get, (put if setter is not None else None)

    def _set_value(self, table: str, key: str, causality: str, value: Any) -> None:
        name = f"{table}.{key}"
        try:
            if causality == "parameter" and self._phase not in ("instantiated", "initializing"):
                raise InputError(f"{name} is a fixed parameter: set it before "
                                 "fmi3ExitInitializationMode (or reset the FMU)")
            field = next(f for f in SECTIONS[table].fields if f.name == key)
            parsed = field.parse(value, f"FMU parameter {name}", si=True)
        except Exception as exc:  # refuse; the previous value stays
            self._refuse(f"set {name}: {exc}")
        self._tables[table][key] = parsed

    # ------------------------------------------------------------------ refusal
    def _refuse(self, message: str) -> NoReturn:
        """Log ``message`` (status error) and raise so the FMI call fails; see module doc."""
        text = " ".join(str(message).split())
        self.log(text, Fmi3Status.error)
        if self._native:
            # pythonfmu3 drops one reference to the class, the instance and its log queue when
            # a call raises, yet keeps using them: hand it those references first
            for obj in (type(self), self, self.log_queue):
                ctypes.pythonapi.Py_IncRef(ctypes.py_object(obj))
        raise Fmu3CallError(text)

    # ------------------------------------------------------------------ lifecycle
    @_fmi_call
    def enter_initialization_mode(self) -> None:
        """Parameters stay settable until exitInitializationMode."""
        if self._phase != "instantiated":
            raise InputError(f"enterInitializationMode in state {self._phase}")
        self._phase = "initializing"

    @_fmi_call
    def exit_initialization_mode(self) -> None:
        """Build the model from the parameter values (start time 0 s, the scene's rtol) and
        compute the initial outputs."""
        if self._phase != "initializing":
            raise InputError(f"exitInitializationMode in state {self._phase}")
        self._build(self._tables)
        self._phase = "stepping"
        self._update_outputs()

    def _build(self, tables: dict[str, dict[str, Any]]) -> None:
        scene = parse_scene({k: dict(v) for k, v in tables.items()},
                            source=f"FMU {self.instance_name}", si=True)
        plan = build_plan(scene)
        self._pair = build_pair(scene)
        self._base_model = plan.model
        self._changes = {}
        op = scene.get("operating")
        self._applied = (float(op["speed"]), float(op["torque"]))
        self._stepper = Stepper(plan.model, plan.settings, t0=0.0, stop_time=None)
        self._built_tables = {k: dict(v) for k, v in tables.items()}

    @_fmi_call
    def do_step(self, current_time: float, step_size: float) -> bool:
        """Advance from ``current_time`` by ``step_size`` (s)."""
        if self._phase != "stepping" or self._stepper is None:
            raise InputError(f"doStep in state {self._phase}: initialize the FMU first")
        st = self._stepper
        if not abs(current_time - st.t) <= 1e-9 * max(1.0, abs(st.t)):
            raise InputError(f"doStep from t = {current_time:.12g} s but the FMU is at "
                             f"t = {st.t:.12g} s (this FMI 3 FMU starts at 0 s: pythonfmu3 "
                             "does not pass the start time on)")
        if not (math.isfinite(step_size) and step_size > 0):
            raise InputError(f"communication step = {step_size!r} s: valid range > 0 s")
        op = self._tables["operating"]
        inputs = (float(op["speed"]), float(op["torque"]))
        if inputs != self._applied:
            self._changes = input_changes(self._base_model, self._pair, inputs[0], inputs[1],
                                          st.t)
            st.replace_model(replace(self._base_model, **self._changes))
            self._applied = inputs
        st.advance(current_time + step_size)
        self._update_outputs()
        return True

    def _update_outputs(self) -> None:
        st = self._stepper
        assert st is not None
        y = st.y
        for label, value in zip(st.model.state_labels, y, strict=True):
            self._outputs[f"state.{label}"] = float(value)
        for name, arr in st.model.outputs(np.array([st.t]), y[:, None]).items():
            if name in self._outputs:
                self._outputs[name] = float(np.asarray(arr).ravel()[0])
        if "driven_speed" in self._outputs and self._applied is not None:
            self._outputs["driven_speed"] = float(driven_speed(self._pair, self._applied[0],
                                                               y[1]))
        bad = [k for k, v in self._outputs.items() if not math.isfinite(v)]
        if bad:
            raise SolverError(f"outputs {', '.join(bad)} are not finite at t = {st.t:.6g} s")

    @_fmi_call
    def terminate(self) -> None:
        """End the run; further doSteps are refused (reset to start again)."""
        self._phase = "terminated"

    # ------------------------------------------------------------------ FMU state
    @_fmi_call
    def _get_fmu_state(self) -> dict[str, Any]:
        """A deep snapshot: values, phase and the whole integrator state."""
        return {
            "phase": self._phase,
            "tables": {k: dict(v) for k, v in self._tables.items()},
            "built_tables": self._built_tables,
            "changes": dict(self._changes),
            "applied": self._applied,
            "outputs": dict(self._outputs),
            "stepper": self._stepper.snapshot() if self._stepper is not None else None,
        }

    @_fmi_call
    def _set_fmu_state(self, state: dict[str, Any]) -> None:
        """Return to a state from :meth:`_get_fmu_state` (or its deserialised bytes)."""
        if not isinstance(state, dict) or "stepper" not in state:
            raise InputError("not an FMU state of this FMU")
        built = state["built_tables"]
        if built is not None and (self._stepper is None or built != self._built_tables):
            self._build(built)  # the state was taken with other parameter values
        self._tables = {k: dict(v) for k, v in state["tables"].items()}
        self._phase = state["phase"]
        self._applied = tuple(state["applied"]) if state["applied"] is not None else None
        self._changes = dict(state["changes"])
        self._outputs = dict(state["outputs"])
        if state["stepper"] is not None and self._stepper is not None:
            self._stepper.model = (replace(self._base_model, **self._changes) if self._changes
                                   else self._base_model)
            self._stepper.restore(state["stepper"])
        elif state["stepper"] is None:
            self._stepper = None

    @staticmethod
    def _fmu_state_to_bytes(state: dict[str, Any]) -> bytes:
        return pickle.dumps(state, protocol=4)

    @staticmethod
    def _fmu_state_from_bytes(state: bytes) -> dict[str, Any]:
        return dict(_StateUnpickler(io.BytesIO(bytes(state))).load())


__all__ = ["Fmu3CallError", "GearDynSlave3"]
