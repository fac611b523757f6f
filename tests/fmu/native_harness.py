"""What the native FMU tests (test_native_fmu, _inputs, _kernel and _torsional.py) drive the
native FMU with: its C kernel through ctypes, one FMU instance through fmpy, and the
error the FMU states in its modelDescription. fmpy is imported where used: the callers skip
without it."""

from __future__ import annotations

import ctypes
import functools
import re
from pathlib import Path
from typing import Any

from gear_dyn.fmu.export_c import KERNEL_DIR, KERNEL_SOURCES, compile_shared, model_data_c


def kernel(tmp: Path, nm: Any) -> ctypes.CDLL:
    """The kernel with the model data of ``nm`` (a native model, single-DOF or torsional),
    compiled into ``tmp`` and loaded."""
    (tmp / "model_data.c").write_text(model_data_c(nm, "test"))
    so = compile_shared([*(KERNEL_DIR / k for k in KERNEL_SOURCES), tmp / "model_data.c"],
                        tmp / "kernel.so")
    lib = ctypes.CDLL(str(so))
    lib.gd_advance.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_double]
    lib.gd_start.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_double]
    lib.gd_outputs.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p]
    return lib


def stated_error(path: Path) -> float:
    """The stated DTE error (relative to W/k_m) from the FMU's description."""
    import fmpy

    desc = fmpy.read_model_description(str(path)).description or ""
    found = re.search(r"Stated error of the DTE: ([0-9.e+-]+) of the static deflection", desc)
    assert found, desc
    return float(found[1])


@functools.cache
def _unzipped(path: Path) -> str:
    import fmpy

    return str(fmpy.extract(str(path)))


class Slave:
    """One instance of a native FMU driven through fmpy's FMU2Slave / FMU3Slave, with the log
    messages it sends collected in :attr:`log` as (status, message)."""

    def __init__(self, path: Path, fmi: int) -> None:
        import fmpy

        self.fmi = fmi
        md = fmpy.read_model_description(str(path))
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.log: list[tuple[int, str]] = []
        kw = dict(guid=md.guid, unzipDirectory=_unzipped(path),
                  modelIdentifier=md.coSimulation.modelIdentifier, instanceName="a")
        if fmi == 2:
            from fmpy.fmi2 import (
                FMU2Slave,
                fmi2CallbackAllocateMemoryTYPE,
                fmi2CallbackFreeMemoryTYPE,
                fmi2CallbackFunctions,
                fmi2CallbackLoggerTYPE,
            )
            from fmpy.fmi2 import calloc as c_calloc
            from fmpy.fmi2 import free as c_free

            cb = fmi2CallbackFunctions()
            cb.logger = fmi2CallbackLoggerTYPE(
                lambda env, name, status, cat, msg: self.log.append((status, msg.decode())))
            cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(c_calloc)
            cb.freeMemory = fmi2CallbackFreeMemoryTYPE(c_free)
            self.fmu: Any = FMU2Slave(**kw)
            self.fmu.instantiate(callbacks=cb, loggingOn=True)
        else:
            from fmpy.fmi3 import FMU3Slave

            self.fmu = FMU3Slave(**kw)
            self.fmu.instantiate(loggingOn=True, logMessage=lambda env, status, cat, msg:
                                 self.log.append((status, msg.decode())))

    def set(self, name: str, value: float) -> None:
        setter = self.fmu.setReal if self.fmi == 2 else self.fmu.setFloat64
        setter([self.vr[name]], [value])

    def get(self, name: str) -> float:
        getter = self.fmu.getReal if self.fmi == 2 else self.fmu.getFloat64
        return float(getter([self.vr[name]])[0])

    def start(self, stop: float | None) -> None:
        if self.fmi == 2:
            self.fmu.setupExperiment(startTime=0.0, stopTime=stop)
            self.fmu.enterInitializationMode()
        else:
            self.fmu.enterInitializationMode(startTime=0.0, stopTime=stop)
        self.fmu.exitInitializationMode()

    def steps(self, h: float, n: int, k0: int = 0, name: str = "dte") -> list[float]:
        """``name`` after each of n steps from k0 h (times k h computed as such: no accumulated
        rounding)."""
        out = []
        for k in range(k0, k0 + n):
            self.fmu.doStep(k * h, (k + 1) * h - k * h)
            out.append(self.get(name))
        return out

    def close(self) -> None:
        self.fmu.terminate()
        self.fmu.freeInstance()
