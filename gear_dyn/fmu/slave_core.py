"""What the FMI 2 and FMI 3 slaves share: a gear_dyn scene run as a co-simulation slave.

:class:`SlaveCore` is a mixin with everything that does not depend on the FMI version or on
the exporter (pythonfmu for FMI 2, pythonfmu3 for FMI 3; this module imports neither, so both
FMUs carry it): the parameters form a scene (SI values, so no pint),
:func:`gear_dyn.scene.build_plan` builds the model exactly as ``gear-dyn run`` does,
:class:`gear_dyn.fmu.stepper.Stepper` advances it (keeping the scipy solver alive across
communication steps, :meth:`~gear_dyn.solvers.session.Session.step_to`),
:mod:`gear_dyn.fmu.inputs` applies changed inputs, :mod:`gear_dyn.fmu.outputs` writes the
outputs as Python floats, and a refused call is logged and raised safely (``_refuse()``).
The slaves (:class:`gear_dyn.fmu.slave.GearDynSlave`,
:class:`gear_dyn.fmu.slave3.GearDynSlave3`) name their exporter's variable classes and error
status and add what their FMI version passes on (FMI 2: the start time, stop time and tolerance
of fmi2SetupExperiment).

What each FMI call does and refuses, what an FMU state holds, and how a refusal reaches the
importer: docs/fmu.md, "Lifecycle and errors". pythonfmu (0.7) and pythonfmu3 (0.3) turn any
Python exception raised into an FMI call into status Fatal and drop one reference to the class,
the instance and its log queue, although later calls (and freeing the instance) still use them;
``SlaveCore._refuse()`` therefore logs the reason, hands those references back, and raises.
"""

from __future__ import annotations

import ctypes
import functools
import io
import json
import math
import pickle
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any, NoReturn

from gear_dyn.errors import GearDynError, InputError, SolverError
from gear_dyn.fmu.clean_exit import release_at_exit
from gear_dyn.fmu.inputs import input_changes
from gear_dyn.fmu.outputs import Writer, output_writer
from gear_dyn.fmu.stepper import Stepper
from gear_dyn.fmu.variables import SPEC_FILE, check_spec
from gear_dyn.scene import SECTIONS, build_pair, build_plan, parse_scene


class FmuCallError(GearDynError):
    """An FMI call refused by the slave (the message is also logged)."""


def fmi_call(func: Callable[..., Any]) -> Callable[..., Any]:
    """Wrap an FMI entry point: a failure is logged and refused safely (see module doc); the
    message names the FMI function (the slave's ``FMI_NAMES``)."""

    @functools.wraps(func)
    def wrapper(self: SlaveCore, *args: Any) -> Any:
        try:
            return func(self, *args)
        except FmuCallError:
            raise
        except Exception as exc:  # every failure becomes a logged, refused call
            name = self.FMI_NAMES.get(func.__name__, func.__name__)
            self._refuse(f"{name} refused: {exc}")

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


class SlaveCore:
    """The FMI-version-independent part of a gear_dyn slave (a mixin placed before the
    exporter's slave class, whose ``do_step`` and friends it provides).

    A slave calls ``_init_core()`` in its ``__init__`` and names its exporter's classes and
    error status below.
    """

    #: FMI function of each slave entry point (named in the message of a refused call)
    FMI_NAMES: dict[str, str] = {}
    #: what a doStep from the wrong time adds to its message
    WRONG_TIME_HINT = "; set an FMU state to go back"
    #: the exporter's variable class of each spec type, its causality and variability enums
    #: and its DefaultExperiment class (set by the slave)
    VARIABLE_TYPES: dict[str, Any] = {}
    CAUSALITY: Any = None
    VARIABILITY: Any = None
    EXPERIMENT: Any = None
    #: the exporter's status error, of the log message of a refused call
    ERROR_STATUS: Any = None
    #: set by the exporter's slave class
    instance_name: str
    log_queue: Any
    resources: Any
    register_variable: Callable[..., Any]
    log: Callable[..., Any]

    def _init_core(self, native: bool, fmi: int) -> None:
        """Read the spec from the FMU's resources; values, description, default experiment,
        variables and empty run state of a new instance of FMI version ``fmi`` (``native``:
        called by the exporter's binary, which drops references on a raise, see module doc; it
        then also registers the host's clean exit, :mod:`gear_dyn.fmu.clean_exit`)."""
        if native:
            release_at_exit(str(self.resources), type(self).__name__, fmi)
        spec = check_spec(json.loads(Path(str(self.resources), SPEC_FILE).read_text("utf-8")))
        self._native = native
        self._spec = spec
        self._tables: dict[str, dict[str, Any]] = {k: dict(v) for k, v in spec["tables"].items()}
        self._outputs: dict[str, float] = {}
        self._real_getters: dict[int, Callable[[], Any]] = {}  # by value reference
        self._phase = "instantiated"
        self._start_time = 0.0
        self._tolerance: float | None = None
        self._stepper: Stepper | None = None
        self._base_model: Any = None
        self._pair: Any = None
        self._changes: dict[str, float] = {}
        self._applied: tuple[float, float] | None = None
        self._built_tables: dict[str, dict[str, Any]] | None = None
        self._write: Writer | None = None
        self.author = "gear_dyn"
        self.license = "MIT"
        self.description = (f"gear_dyn {spec['model']} model of scene '{spec['scene_name']}' "
                            f"(FMI {fmi}.0 co-simulation)")
        ex = spec["experiment"]
        self.default_experiment = self.EXPERIMENT(
            start_time=ex["start_time"], stop_time=ex["stop_time"], step_size=ex["step_size"],
            tolerance=ex["tolerance"])
        for v in spec["variables"]:
            getter, setter = self._access(v)
            var = self.VARIABLE_TYPES[v["type"]](
                v["name"], causality=self.CAUSALITY[v["causality"]],
                variability=self.VARIABILITY[v["variability"]], description=v["description"],
                getter=getter, setter=setter)
            self.register_variable(var, nested=False)
            if v["type"] == "Real":
                self._real_getters[var.value_reference] = getter

    # ------------------------------------------------------------------ variables
    def _access(self, v: dict[str, Any]) -> tuple[Callable[[], Any], Callable[[Any], None] | None]:
        """Getter and setter (None for an output) of spec variable ``v``; an Enumeration is
        read and written as its item number 1..n."""
        name, causality = v["name"], v["causality"]
        getter: Callable[[], Any]
        setter: Callable[[Any], None] | None = None
        if causality == "output":
            self._outputs[name] = 0.0
            getter = functools.partial(self._outputs.__getitem__, name)  # dict kept in place
        else:
            getter = self._value_getter(v["table"], v["key"])
            setter = functools.partial(self._set_value, v["table"], v["key"], causality)
        if v["type"] == "Enumeration":
            getter, setter = self._enum_access(v, getter, setter)
        return getter, setter

    def _get_reals(self, vrs: Any, call: str) -> list[float]:
        """Values of Real (Float64) variables by value reference, without the exporter's
        per-variable type check (the getters are collected at registration); another
        reference is refused naming ``call``."""
        getters = self._real_getters
        try:
            return [getters[vr]() for vr in vrs]
        except KeyError:
            bad = next(vr for vr in vrs if vr not in getters)
            self._refuse(f"{call} refused: value reference {bad} is not a Real variable "
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

    def _value_getter(self, table: str, key: str) -> Callable[[], Any]:
        return lambda: self._tables[table][key]

    def _set_value(self, table: str, key: str, causality: str, value: Any) -> None:
        name = f"{table}.{key}"
        try:
            if causality == "parameter" and self._phase not in ("instantiated", "initializing"):
                exit_init = self.FMI_NAMES["exit_initialization_mode"]
                raise InputError(f"{name} is a fixed parameter: set it before "
                                 f"{exit_init} (or reset the FMU)")
            field = next(f for f in SECTIONS[table].fields if f.name == key)
            if isinstance(value, float) and field.kind == "int":
                raise InputError(f"{name} = {value!r}: expected a whole number")
            parsed = field.parse(value, f"FMU parameter {name}", si=True)
        except Exception as exc:  # refuse; the previous value stays
            self._refuse(f"set {name}: {exc}")
        self._tables[table][key] = parsed

    # ------------------------------------------------------------------ refusal
    def _refuse(self, message: str) -> NoReturn:
        """Log ``message`` (status error) and raise so the FMI call fails; see module doc."""
        text = " ".join(str(message).split())
        self.log(text, self.ERROR_STATUS)
        if self._native:
            # the exporter drops one reference to the class, the instance and its log queue
            # when a call raises, yet keeps using them: hand it those references first
            for obj in (type(self), self, self.log_queue):
                ctypes.pythonapi.Py_IncRef(ctypes.py_object(obj))
        raise FmuCallError(text)

    # ------------------------------------------------------------------ lifecycle
    @fmi_call
    def enter_initialization_mode(self) -> None:
        """Parameters stay settable until exitInitializationMode."""
        if self._phase != "instantiated":
            raise InputError(f"enterInitializationMode in state {self._phase}")
        self._phase = "initializing"

    @fmi_call
    def exit_initialization_mode(self) -> None:
        """Build the model from the parameter values and compute the initial outputs."""
        if self._phase != "initializing":
            raise InputError(f"exitInitializationMode in state {self._phase}")
        self._build(self._tables)
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
        self._stepper = Stepper(plan.model, plan.settings, t0=self._start_time)
        self._built_tables = {k: dict(v) for k, v in tables.items()}
        self._new_writer()

    def _new_writer(self) -> None:
        """The output writer of the model the stepper runs (after every model change)."""
        assert self._stepper is not None and self._applied is not None
        names = [v["name"] for v in self._spec["variables"] if v["causality"] == "output"]
        self._write = output_writer(self._stepper.model, self._pair, self._applied[0], names)

    @fmi_call
    def do_step(self, current_time: float, step_size: float) -> bool:
        """Advance from ``current_time`` by ``step_size`` (s)."""
        st = self._stepper
        if self._phase != "stepping" or st is None:
            raise InputError(f"doStep in state {self._phase}: initialize the FMU first")
        t = st.t
        if not abs(current_time - t) <= 1e-9 * max(1.0, abs(t)):
            raise InputError(f"doStep from t = {current_time:.12g} s but the FMU is at "
                             f"t = {t:.12g} s{self.WRONG_TIME_HINT}")
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

    @fmi_call
    def terminate(self) -> None:
        """End the run; further doSteps are refused (reset to start again)."""
        self._phase = "terminated"

    # ------------------------------------------------------------------ FMU state
    @fmi_call
    def _get_fmu_state(self) -> dict[str, Any]:
        """A deep snapshot: values, phase and the whole integrator state."""
        return {
            "phase": self._phase,
            "start_time": self._start_time,
            "tolerance": self._tolerance,
            "tables": {k: dict(v) for k, v in self._tables.items()},
            "built_tables": self._built_tables,
            "changes": dict(self._changes),
            "applied": self._applied,
            "outputs": dict(self._outputs),
            "stepper": self._stepper.snapshot() if self._stepper is not None else None,
        }

    @fmi_call
    def _set_fmu_state(self, state: dict[str, Any]) -> None:
        """Return to a state from :meth:`_get_fmu_state` (or its deserialised bytes)."""
        if not isinstance(state, dict) or "stepper" not in state:
            reason = state.get("invalid") if isinstance(state, dict) else None
            raise InputError("not an FMU state of this FMU" + (f" ({reason})" if reason else ""))
        self._start_time = float(state["start_time"])
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
        # never raises: the exporter calls it on the class, so a failure could not keep the
        # instance valid; setting the state refuses the invalid state instead, naming the reason
        try:
            loaded = _StateUnpickler(io.BytesIO(bytes(state))).load()
        except Exception as exc:  # any bytes may arrive: a state of another FMU, garbage
            return {"invalid": f"cannot read the serialized state: {exc}"}
        return dict(loaded) if isinstance(loaded, dict) else {"invalid": "not a state dict"}


__all__ = ["FmuCallError", "SlaveCore", "fmi_call"]
