"""The pythonfmu slave: a thin FMI 2.0 co-simulation shell over a gear_dyn model.

The FMU built by :mod:`gear_dyn.fmu.build` contains a generated script with one class
``class GearDyn_<model>_<id>(GearDynSlave)`` and a private copy of gear_dyn; this module is that
copy's slave. What the FMI 2 and FMI 3 slaves share is in
:class:`gear_dyn.fmu.slave_core.SlaveCore`; this module names pythonfmu's variable classes and
adds fmi2SetupExperiment (start time, stop time, tolerance) and a fast fmi2GetReal.
"""

from __future__ import annotations

import ctypes
import math
import sys
from typing import Any

from pythonfmu import Boolean, Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real, String
from pythonfmu.default_experiment import DefaultExperiment
from pythonfmu.enums import Fmi2Status

from gear_dyn.errors import InputError
from gear_dyn.fmu.slave_core import FmuCallError, SlaveCore, fmi_call


class GearDynSlave(SlaveCore, Fmi2Slave):
    """Co-simulation slave of a gear_dyn scene (single-DOF or torsional model).

    The FMU's generated class derives from this one; the scene comes from the FMU resources
    (``gear_dyn_fmu.json``, written by :func:`gear_dyn.fmu.build.build_fmu`).
    """

    FMI_NAMES = {"setup_experiment": "fmi2SetupExperiment",
                 "enter_initialization_mode": "fmi2EnterInitializationMode",
                 "exit_initialization_mode": "fmi2ExitInitializationMode",
                 "do_step": "fmi2DoStep", "terminate": "fmi2Terminate",
                 "_get_fmu_state": "fmi2GetFMUstate", "_set_fmu_state": "fmi2SetFMUstate"}
    VARIABLE_TYPES = {"Real": Real, "Integer": Integer, "String": String, "Boolean": Boolean,
                      "Enumeration": Integer}
    CAUSALITY = Fmi2Causality
    VARIABILITY = Fmi2Variability
    EXPERIMENT = DefaultExperiment
    ERROR_STATUS = Fmi2Status.error

    def __init__(self, **kwargs: Any) -> None:
        # the native wrapper passes its logger; pythonfmu's builder and direct Python use do not
        native = "logger" in kwargs
        if native:
            # pythonfmu's loader releases a reference to the slave script's module dict that
            # it never owned, once per instantiation: give it one back, or after a few
            # instantiations the dict is freed under the module (a crash); a reset adds one
            # more than needed: the module dict lives as long as the process anyway
            module = sys.modules.get(type(self).__module__)
            if module is not None:
                ctypes.pythonapi.Py_IncRef(ctypes.py_object(vars(module)))
        super().__init__(**kwargs)
        self._init_core(native, 2)

    def get_real(self, vrs: list[int]) -> list[float]:
        """Values of Real variables (pythonfmu's own lookup, without its per-variable type
        check: the getters are collected at registration; another reference is refused)."""
        return self._get_reals(vrs, "fmi2GetReal")

    @fmi_call
    def setup_experiment(self, start_time: float, stop_time: float | None = None,
                         tolerance: float | None = None) -> None:
        """Start time (s) of the run and, if given, the solver's relative tolerance (the stop
        time changes nothing: the outputs at t never depend on what the master plans after t)."""
        if self._phase != "instantiated":
            raise InputError("setupExperiment is allowed only right after instantiation")
        if not math.isfinite(start_time):
            raise InputError(f"start time = {start_time!r} s: must be finite")
        self._start_time = float(start_time)
        self._tolerance = tolerance if tolerance is not None and tolerance > 0 else None


__all__ = ["FmuCallError", "GearDynSlave"]
