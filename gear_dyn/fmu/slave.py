"""The pythonfmu slave: a thin FMI 2.0 co-simulation shell over a gear_dyn model.

The FMU built by :mod:`gear_dyn.fmu.build` contains a generated script with one class
``class GearDyn_<model>_<id>(GearDynSlave)`` and a private copy of gear_dyn; this module is that
copy's slave. Everything physical is gear_dyn's: the parameters form a scene (SI values, so no
pint), :func:`gear_dyn.scene.build_plan` builds the model exactly as ``gear-dyn run`` does, and
:class:`gear_dyn.fmu.stepper.Stepper` advances it, keeping the scipy solver alive across
communication steps.

Lifecycle
---------
- instantiate: parameters and inputs take the scene's values (cheap; nothing is built);
- set parameters (before exitInitializationMode) and inputs (any time); each value is checked
  against its scene field (range, unit, kind) and a bad one is refused;
- exitInitializationMode: the model is built and checked as a whole (e.g. a contact ratio
  below 1 is refused);
- doStep(t, h): inputs that changed are applied (cheap model copy, solver restarted at t), the
  stepper advances to t + h, outputs are updated;
- get/set/serialize FMU state: the whole integrator state (solver step size, stages, work
  arrays), the parameter and input values and the built model's input changes;
- reset: pythonfmu creates a fresh instance; terminate: further doSteps are refused.

Errors
------
pythonfmu (0.7) turns any Python exception raised into an FMI call into status ``fmi2Fatal``
and drops its references to the Python objects, although later calls (and fmi2FreeInstance)
still use them. A refused call here therefore: logs the reason (status error, category
logStatusError; pythonfmu forwards it when debug logging is on), gives the native wrapper the
references it is about to drop (so the instance stays valid and freeing it is safe), and
raises. The importer sees the call fail with ``fmi2Error`` and one message naming the FMI
call and the reason; the instance stays usable (fmi2Reset, an FMU state, a corrected value).
The boot library (``pyboot.c``) turns pythonfmu's ``fmi2Fatal`` into ``fmi2Error`` when the
slave logged a status-error message during the call: only a refusal here logs one. Any other
failure (e.g. inside pythonfmu) stays ``fmi2Fatal``, and so does every failure of an FMU
without the boot library (where it cannot be built, e.g. on Windows). A refused parameter
keeps its previous value.

pythonfmu's loader also releases, at every instantiation, a reference to the slave script's
module dict that it does not own; :meth:`GearDynSlave.__init__` hands it one back (a reset adds
one more than needed: the module dict lives as long as the process anyway).
"""

from __future__ import annotations

import ctypes
import io
import json
import math
import pickle
import sys
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any, NoReturn

from pythonfmu import Boolean, Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real, String
from pythonfmu.default_experiment import DefaultExperiment
from pythonfmu.enums import Fmi2Status

from gear_dyn.errors import GearDynError, InputError, SolverError
from gear_dyn.fmu.inputs import input_changes
from gear_dyn.fmu.outputs import Writer, output_writer
from gear_dyn.fmu.stepper import Stepper
from gear_dyn.fmu.variables import SPEC_FILE, check_spec
from gear_dyn.scene import SECTIONS, build_pair, build_plan, load_feature_sections, parse_scene

_TYPES = {"Real": Real, "Integer": Integer, "String": String, "Boolean": Boolean}
_CAUSALITY = {"parameter": Fmi2Causality.parameter, "input": Fmi2Causality.input,
              "output": Fmi2Causality.output}
_VARIABILITY = {"fixed": Fmi2Variability.fixed, "tunable": Fmi2Variability.tunable,
                "continuous": Fmi2Variability.continuous}


class FmuCallError(GearDynError):
    """An FMI call refused by the slave (the message is also logged)."""


#: FMI function of each slave entry point (named in the message of a refused call)
_FMI_NAMES = {"setup_experiment": "fmi2SetupExperiment",
              "enter_initialization_mode": "fmi2EnterInitializationMode",
              "exit_initialization_mode": "fmi2ExitInitializationMode",
              "do_step": "fmi2DoStep", "terminate": "fmi2Terminate",
              "_get_fmu_state": "fmi2GetFMUstate", "_set_fmu_state": "fmi2SetFMUstate"}


def _fmi_call(func: Callable[..., Any]) -> Callable[..., Any]:
    """Wrap an FMI entry point: a failure is logged and refused safely (see module doc)."""
    fmi_name = _FMI_NAMES.get(func.__name__, func.__name__)

    def wrapper(self: GearDynSlave, *args: Any) -> Any:
        try:
            return func(self, *args)
        except FmuCallError:
            raise
        except Exception as exc:  # every failure becomes a logged, refused call
            self._refuse(f"{fmi_name} refused: {exc}")

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


class GearDynSlave(Fmi2Slave):
    """Co-simulation slave of a gear_dyn scene (single-DOF or torsional model).

    The FMU's generated class derives from this one; the scene comes from the FMU resources
    (``gear_dyn_fmu.json``, written by :func:`gear_dyn.fmu.build.build_fmu`).
    """

    author = "gear_dyn"
    license = "MIT"

    def __init__(self, **kwargs: Any) -> None:
        # the native wrapper passes its logger; pythonfmu's builder and direct Python use do not
        native = "logger" in kwargs
        if native:
            # pythonfmu's loader releases a reference to the slave script's module dict that
            # it never owned, once per instantiation: give it one back, or after a few
            # instantiations the dict is freed under the module (a crash)
            module = sys.modules.get(type(self).__module__)
            if module is not None:
                ctypes.pythonapi.Py_IncRef(ctypes.py_object(vars(module)))
        super().__init__(**kwargs)
        self._native = native
        spec = check_spec(json.loads(Path(str(self.resources), SPEC_FILE).read_text("utf-8")))
        load_feature_sections()
        self._spec = spec
        self._kind: str = spec["model"]
        self.description = (f"gear_dyn {self._kind} model of scene '{spec['scene_name']}' "
                            "(FMI 2.0 co-simulation)")
        ex = spec["experiment"]
        self.default_experiment = DefaultExperiment(
            start_time=ex["start_time"], stop_time=ex["stop_time"], step_size=ex["step_size"],
            tolerance=ex["tolerance"])
        self._tables: dict[str, dict[str, Any]] = {k: dict(v) for k, v in spec["tables"].items()}
        self._outputs: dict[str, float] = {}
        self._input_names: list[str] = []
        self._real_getters: dict[int, Callable[[], Any]] = {}  # by value reference
        self._phase = "instantiated"
        self._start_time = 0.0
        self._stop_time: float | None = None
        self._tolerance: float | None = None
        self._stepper: Stepper | None = None
        self._base_model: Any = None
        self._pair: Any = None
        self._changes: dict[str, float] = {}
        self._applied: tuple[float, float] | None = None
        self._built_tables: dict[str, dict[str, Any]] | None = None
        self._write: Writer | None = None
        for v in spec["variables"]:
            self._register(v)

    # ------------------------------------------------------------------ variables
    def _register(self, v: dict[str, Any]) -> None:
        name, causality = v["name"], v["causality"]
        getter: Callable[[], Any]
        setter: Callable[[Any], None] | None = None
        if causality == "output":
            self._outputs[name] = 0.0
            getter = self._output_getter(name)
        else:
            table, key = v["table"], v["key"]
            getter = self._value_getter(table, key)
            setter = self._value_setter(table, key, causality)
            if causality == "input":
                self._input_names.append(name)
        if v["type"] == "Enumeration":  # an FMI Integer 1..n (modelDescription: Enumeration)
            getter, setter = self._enum_access(v, getter, setter)
        kind = _TYPES["Integer" if v["type"] == "Enumeration" else v["type"]]
        var = kind(
            name, causality=_CAUSALITY[causality], variability=_VARIABILITY[v["variability"]],
            description=v["description"], getter=getter, setter=setter)
        self.register_variable(var, nested=False)
        if kind is Real:
            self._real_getters[var.value_reference] = getter

    def get_real(self, vrs: list[int]) -> list[float]:
        """Values of Real variables (pythonfmu's own lookup, without its per-variable type
        check: the getters are collected at registration; another reference is refused)."""
        getters = self._real_getters
        try:
            return [getters[vr]() for vr in vrs]
        except KeyError:
            bad = next(vr for vr in vrs if vr not in getters)
            self._refuse(f"fmi2GetReal refused: value reference {bad} is not a Real variable "
                         "of this FMU")

    def _enum_access(self, v: dict[str, Any], getter: Callable[[], Any],
                     setter: Callable[[Any], None] | None
                     ) -> tuple[Callable[[], int], Callable[[Any], None] | None]:
        """Getter and setter of an enumeration: item k (1..n) stands for choice k."""
        choices: list[str] = v["choices"]

        def get() -> int:
            return choices.index(getter()) + 1

        def put(value: Any) -> None:
            assert setter is not None
            if isinstance(value, int) and not isinstance(value, bool):
                if not 1 <= value <= len(choices):
                    self._refuse(f"set {v['name']}: {v['name']} = {value}: valid range "
                                 f"1 <= x <= {len(choices)} ("
                                 + ", ".join(f"{i} {c}" for i, c in enumerate(choices, 1))
                                 + ")")
                value = choices[value - 1]
            setter(value)

        return get, (put if setter is not None else None)

    def _output_getter(self, name: str) -> Callable[[], float]:
        return lambda: self._outputs[name]

    def _value_getter(self, table: str, key: str) -> Callable[[], Any]:
        return lambda: self._tables[table][key]

    def _value_setter(self, table: str, key: str, causality: str) -> Callable[[Any], None]:
        def setter(value: Any) -> None:
            self._set_value(table, key, causality, value)
        return setter

    def _set_value(self, table: str, key: str, causality: str, value: Any) -> None:
        name = f"{table}.{key}"
        try:
            if causality == "parameter" and self._phase not in ("instantiated", "initializing"):
                raise InputError(f"{name} is a fixed parameter: set it before "
                                 "fmi2ExitInitializationMode (or reset the FMU)")
            field = next(f for f in SECTIONS[table].fields if f.name == key)
            if isinstance(value, float) and field.kind == "int":
                raise InputError(f"{name} = {value!r}: expected a whole number")
            parsed = field.parse(value, f"FMU parameter {name}", si=True)
        except Exception as exc:  # refuse; the previous value stays
            self._refuse(f"set {name}: {exc}")
        self._tables[table][key] = parsed

    # ------------------------------------------------------------------ refusal
    def _refuse(self, message: str) -> NoReturn:
        """Log ``message`` (status error: the boot library takes it as the sign of a refusal
        that kept the instance valid) and raise so the FMI call fails; see module doc."""
        text = " ".join(str(message).split())
        self.log(text, Fmi2Status.error)
        if self._native:
            # pythonfmu drops one reference to the class, the instance and its log queue when
            # a call raises, yet keeps using them: hand it those references first
            for obj in (type(self), self, self.log_queue):
                ctypes.pythonapi.Py_IncRef(ctypes.py_object(obj))
        raise FmuCallError(text)

    # ------------------------------------------------------------------ lifecycle
    @_fmi_call
    def setup_experiment(self, start_time: float, stop_time: float | None = None,
                         tolerance: float | None = None) -> None:
        """Start time (s) of the run and, if given, the solver's relative tolerance."""
        if self._phase != "instantiated":
            raise InputError("setupExperiment is allowed only right after instantiation")
        if not math.isfinite(start_time):
            raise InputError(f"start time = {start_time!r} s: must be finite")
        self._start_time = float(start_time)
        self._stop_time = float(stop_time) if stop_time is not None else None
        self._tolerance = tolerance if tolerance is not None and tolerance > 0 else None

    @_fmi_call
    def enter_initialization_mode(self) -> None:
        """Parameters stay settable until exitInitializationMode."""
        if self._phase != "instantiated":
            raise InputError(f"enterInitializationMode in state {self._phase}")
        self._phase = "initializing"

    @_fmi_call
    def exit_initialization_mode(self) -> None:
        """Build the model from the parameter values and compute the initial outputs."""
        if self._phase != "initializing":
            raise InputError(f"exitInitializationMode in state {self._phase}")
        self._build(self._tables)
        assert self._stepper is not None
        self._phase = "stepping"
        self._update_outputs()

    def _build(self, tables: dict[str, dict[str, Any]]) -> None:
        scene = parse_scene({k: dict(v) for k, v in tables.items()},
                            source=f"FMU {self.instance_name}", si=True)
        overrides: dict[str, Any] = {}
        if self._tolerance is not None:
            overrides["rtol"] = self._tolerance
        plan = build_plan(scene, **overrides)
        self._pair = build_pair(scene)
        self._base_model = plan.model
        self._changes = {}
        op = scene.get("operating")
        self._applied = (float(op["speed"]), float(op["torque"]))
        self._stepper = Stepper(plan.model, plan.settings, t0=self._start_time,
                                stop_time=self._stop_time)
        self._built_tables = {k: dict(v) for k, v in tables.items()}
        self._new_writer()

    def _new_writer(self) -> None:
        """The output writer of the model the stepper runs (after every model change)."""
        assert self._stepper is not None and self._applied is not None
        names = [v["name"] for v in self._spec["variables"] if v["causality"] == "output"]
        self._write = output_writer(self._stepper.model, self._pair, self._applied[0], names)

    @_fmi_call
    def do_step(self, current_time: float, step_size: float) -> bool:
        """Advance from ``current_time`` by ``step_size`` (s)."""
        st = self._stepper
        if self._phase != "stepping" or st is None:
            raise InputError(f"doStep in state {self._phase}: initialize the FMU first")
        t = st.t
        if not abs(current_time - t) <= 1e-9 * max(1.0, abs(t)):
            raise InputError(f"doStep from t = {current_time:.12g} s but the FMU is at "
                             f"t = {t:.12g} s; set an FMU state to go back")
        if not (step_size > 0 and math.isfinite(step_size)):
            raise InputError(f"communication step = {step_size!r} s: valid range > 0 s")
        op = self._tables["operating"]
        if (op["speed"], op["torque"]) != self._applied:
            inputs = (float(op["speed"]), float(op["torque"]))
            self._changes = input_changes(self._base_model, self._pair, inputs[0], inputs[1],
                                          t)
            st.replace_model(replace(self._base_model, **self._changes))
            self._applied = inputs
            self._new_writer()
        st.step_to(current_time + step_size)
        self._update_outputs()
        return True

    def _update_outputs(self) -> None:
        st = self._stepper
        assert st is not None and self._write is not None
        out = self._outputs
        self._write(st.t, st.y, out)
        if not all(map(math.isfinite, out.values())):
            bad = [k for k, v in out.items() if not math.isfinite(v)]
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
            "start_time": self._start_time,
            "stop_time": self._stop_time,
            "tolerance": self._tolerance,
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
            reason = state.get("invalid") if isinstance(state, dict) else None
            raise InputError("not an FMU state of this FMU" + (f" ({reason})" if reason else ""))
        self._start_time = float(state["start_time"])
        self._stop_time = state["stop_time"]
        self._tolerance = state["tolerance"]
        built = state["built_tables"]
        if built is not None and (self._stepper is None or built != self._built_tables):
            self._build(built)  # the state was taken with other parameter values
        self._tables = {k: dict(v) for k, v in state["tables"].items()}
        self._phase = state["phase"]
        self._applied = tuple(state["applied"]) if state["applied"] is not None else None
        self._changes = dict(state["changes"])
        self._outputs.clear()
        self._outputs.update(state["outputs"])
        if state["stepper"] is not None and self._stepper is not None:
            model = (replace(self._base_model, **self._changes) if self._changes
                     else self._base_model)
            self._stepper.model = model
            self._stepper.restore(state["stepper"])
            self._new_writer()
        elif state["stepper"] is None:
            self._stepper = None

    @staticmethod
    def _fmu_state_to_bytes(state: dict[str, Any]) -> bytes:
        return pickle.dumps(state, protocol=4)

    @staticmethod
    def _fmu_state_from_bytes(state: bytes) -> dict[str, Any]:
        # never raises: pythonfmu calls it on the class, so a failure could not keep the
        # instance valid; fmi2SetFMUstate refuses the invalid state instead, naming the reason
        try:
            loaded = _StateUnpickler(io.BytesIO(bytes(state))).load()
        except Exception as exc:  # any bytes may arrive: a state of another FMU, garbage
            return {"invalid": f"cannot read the serialized state: {exc}"}
        return dict(loaded) if isinstance(loaded, dict) else {"invalid": "not a state dict"}


__all__ = ["FmuCallError", "GearDynSlave"]
