"""The host runners only the tests use (tests/fmu/test_hosts.py, test_hosts_native.py): fmpy's
``simulate_fmu``, fmutool, libcosim and Ecos run one FMU as :mod:`gear_dyn.fmu.hosts` runs it
in fmpy and the C host (start at 0, fixed communication steps, rows ``(t, outputs...)``), and
the shared libraries ``ldd`` lists for a binary. The Python hosts are test extras
(``pip install 'gear_dyn[test]'``); a runner whose host is missing raises
:class:`~gear_dyn.fmu.hosts.HostMissing` with what to install.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from gear_dyn.errors import InputError
from gear_dyn.fmu.hosts import HostMissing, describe

#: what a native FMU binary may need (besides the loader and the kernel's vDSO)
ALLOWED_LIBRARIES = ("libc.so", "libm.so")



def fmpy_simulate_rows(fmu: str | Path, names: Sequence[str], step: float, n: int,
                       start_values: Mapping[str, float] | None = None) -> np.ndarray:
    """fmpy's ``simulate_fmu`` with communication step = output interval = ``step``."""
    from fmpy import simulate_fmu

    result = simulate_fmu(str(fmu), stop_time=n * step, step_size=step, output_interval=step,
                          output=list(names), start_values=dict(start_values or {}))
    return np.column_stack([result["time"], *(result[name] for name in names)])


# ------------------------------------------------------------------------------ fmutool
def fmutool_check(fmu: str | Path) -> tuple[bool, str]:
    """``fmutool -input FMU -check`` (fmu-manipulation-toolbox): passed, and its output.

    Raises
    ------
    HostMissing
        fmutool is not installed.
    """
    exe = shutil.which("fmutool")
    if exe is None:
        raise HostMissing("fmutool not found (pip install fmu-manipulation-toolbox)")
    proc = subprocess.run([exe, "-input", str(fmu), "-check"], capture_output=True, text=True,
                          timeout=300)
    text = (proc.stdout + proc.stderr).strip()
    failed = proc.returncode != 0 or re.search(r"^ERROR\b", text, re.MULTILINE) is not None
    return not failed, text


# ------------------------------------------------------------------------------ libcosim
def libcosimpy_rows(fmu: str | Path, names: Sequence[str], step: float, n: int,
                    start_values: Mapping[str, float] | None = None) -> np.ndarray:
    """libcosim through libcosimpy (FMI 2): one slave, ``n`` steps; rows after each step only
    (libcosim initializes and takes its first step in one call, so there is no row at t = 0),
    their times the execution's own (it counts integer nanoseconds).

    Raises
    ------
    HostMissing
        libcosimpy is not installed.
    InputError
        An FMI 3 FMU, or a step that is not a whole number of nanoseconds.
    RuntimeError
        libcosim refused the FMU or a step (with its message).
    """
    try:
        from libcosimpy.CosimExecution import CosimExecution
        from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
        from libcosimpy.CosimObserver import CosimObserver
        from libcosimpy.CosimSlave import CosimLocalSlave
    except ImportError as exc:
        raise HostMissing(f"libcosimpy not importable ({exc}; pip install libcosimpy)") from None
    facts = describe(fmu)
    if facts.fmi != 2:
        raise InputError(f"{facts.path}: libcosim runs FMI 1 and 2 FMUs, this one is FMI 3")
    ns = round(step * 1e9)
    if ns <= 0 or abs(ns - step * 1e9) > 1e-6 * ns:
        raise InputError(f"step = {step!r} s: libcosim needs a whole number of nanoseconds")
    log_output_level(CosimLogLevel.ERROR)  # FMI Library's debug lines otherwise
    execution = CosimExecution.from_step_size(step_size=ns)
    slave = CosimLocalSlave(fmu_path=str(Path(fmu).resolve()), instance_name="fmu")
    index = execution.add_local_slave(local_slave=slave)
    if index < 0:
        raise RuntimeError(f"libcosim could not load {fmu}")
    for name, value in (start_values or {}).items():
        execution.real_initial_value(index, facts.variables[name], float(value))
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer=observer)
    refs = [facts.variables[name] for name in names]
    rows = []
    for k in range(n):
        if not execution.step(1):  # the first call initializes, then steps
            raise RuntimeError(f"libcosim step {k + 1} failed")
        status = execution.status()
        rows.append([status.current_time * 1e-9, *observer.last_real_values(index, refs)])
    execution.stop()
    return np.array(rows)


# ------------------------------------------------------------------------------ Ecos
def ecospy_rows(fmu: str | Path, names: Sequence[str], step: float, n: int,
                start_values: Mapping[str, float] | None = None) -> np.ndarray:
    """Ecos through ecospy (FMI 2 and 3): one model instance, fixed step ``step``.

    Raises
    ------
    HostMissing
        ecospy is not installed or its library cannot load (it needs libtbb.so.12:
        ``apt-get install libtbb12``).
    RuntimeError
        Ecos refused the FMU or a value (with its message).
    """
    try:
        from ecospy import EcosSimulation, EcosSimulationStructure
    except (ImportError, OSError) as exc:
        raise HostMissing(f"ecospy not usable ({exc}; pip install ecospy, and libtbb12)") from None
    rows = []
    with EcosSimulationStructure() as ss:
        ss.add_model("fmu", str(Path(fmu).resolve()))
        if start_values:
            ss.add_parameter_set("start", {f"fmu::{k}": float(v) for k, v in
                                           start_values.items()})
        with EcosSimulation(structure=ss, step_size=step) as sim:
            sim.init(parameter_set="start" if start_values else None)
            for k in range(n + 1):
                if k:
                    sim.step(1)
                rows.append([sim.get_time(), *(sim.get_real(f"fmu::{name}")
                                               for name in names)])
            sim.terminate()
    return np.array(rows)


def binary_libraries(binary: str | Path) -> list[str]:
    """The shared libraries ``ldd`` lists for a binary (names, e.g. ``libm.so.6``), without the
    loader and the vDSO.

    Raises
    ------
    HostMissing
        ldd is not on PATH (not a glibc Linux system).
    """
    ldd = shutil.which("ldd")
    if ldd is None:
        raise HostMissing("ldd not found (a glibc Linux tool)")
    out = subprocess.run([ldd, str(binary)], capture_output=True, text=True,
                         env={**os.environ, "LC_ALL": "C"}).stdout
    names = [line.split()[0] for line in out.splitlines() if line.strip()]
    return [Path(x).name for x in names
            if not x.startswith(("linux-vdso", "linux-gate")) and "ld-linux" not in x]


def foreign_libraries(libraries: Sequence[str]) -> list[str]:
    """Those of ``libraries`` that are neither libc nor libm nor the loader."""
    return [lib for lib in libraries
            if not Path(lib).name.startswith(ALLOWED_LIBRARIES) and "ld-linux" not in lib]
