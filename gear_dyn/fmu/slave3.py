"""The pythonfmu3 slave: a thin FMI 3.0 co-simulation shell over the same core as FMI 2.

Its :class:`gear_dyn.fmu.slave_core.SlaveCore` is the FMI 2 slave's, so both FMUs give the
same outputs on the same communication grid. Built by ``gear-dyn fmu build --fmi 3``
(:mod:`gear_dyn.fmu.build`); it does not import pythonfmu (the FMI 3 FMU carries pythonfmu3
only).

pythonfmu3 (0.3.4) limits and how the slave meets them (docs/fmu.md, "FMI 3.0"):
fmi3EnterInitializationMode passes no start time, stop time or tolerance (the FMU starts at
0 s with the scene's ``solver.rtol``); its ``Enumeration`` variable cannot be read or written
(choices are Int64, made Enumerations by the build); a refused call is fmi3Fatal (handled as
in FMI 2).
"""

from __future__ import annotations

from typing import Any

from pythonfmu3 import Boolean, Float64, Fmi3Causality, Fmi3Slave, Fmi3Variability, Int32, Int64
from pythonfmu3 import String as String3
from pythonfmu3.default_experiment import DefaultExperiment
from pythonfmu3.enums import Fmi3Status

from gear_dyn.fmu.slave_core import FmuCallError, SlaveCore

#: the former name of the refusal exception of this slave
Fmu3CallError = FmuCallError


class GearDynSlave3(SlaveCore, Fmi3Slave):
    """FMI 3.0 co-simulation slave of a gear_dyn scene (single-DOF or torsional model).

    The FMU's generated class derives from this one; the scene comes from the FMU resources
    (``gear_dyn_fmu.json``, written by :func:`gear_dyn.fmu.build.build_fmu`).
    """

    FMI_NAMES = {"enter_initialization_mode": "fmi3EnterInitializationMode",
                 "exit_initialization_mode": "fmi3ExitInitializationMode",
                 "do_step": "fmi3DoStep", "terminate": "fmi3Terminate",
                 "_get_fmu_state": "fmi3GetFMUState", "_set_fmu_state": "fmi3SetFMUState"}
    WRONG_TIME_HINT = ("; set an FMU state to go back (this FMI 3 FMU starts at 0 s: "
                       "pythonfmu3 does not pass the start time on)")
    #: FMI 2 type name in the spec -> pythonfmu3 variable class (Enumeration: Int64, see above)
    VARIABLE_TYPES = {"Real": Float64, "Integer": Int32, "String": String3, "Boolean": Boolean,
                      "Enumeration": Int64}
    CAUSALITY = Fmi3Causality
    VARIABILITY = Fmi3Variability
    EXPERIMENT = DefaultExperiment
    ERROR_STATUS = Fmi3Status.error

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        native = "logger" in kwargs  # the native wrapper passes its logger
        self._init_core(native, 3)  # the spec's experiment starts at 0 s, as this FMU does
        # FMI 3 requires the independent variable; last, so the other value references are
        # those of the FMI 2 FMU
        time = Float64("time", causality=Fmi3Causality.independent,
                       variability=Fmi3Variability.continuous, description="simulation time",
                       unit="s", getter=self._time)
        self.register_variable(time, nested=False)
        self._real_getters[time.value_reference] = self._time

    def _time(self) -> float:
        return float(self._stepper.t) if self._stepper is not None else 0.0

    def get_float64(self, vrs: list[int]) -> list[float]:
        """Values of Float64 variables (pythonfmu3's own lookup, without its per-variable type
        and dimension checks: every Float64 here is a scalar whose getter was collected at
        registration; another reference is refused)."""
        return self._get_reals(vrs, "fmi3GetFloat64")


__all__ = ["Fmu3CallError", "GearDynSlave3"]
