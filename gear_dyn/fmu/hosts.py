"""Run one FMU in several FMI hosts, each the same way: start at 0, fixed communication steps.

Every runner (``*_rows``: fmpy step by step and fmpy's ``simulate_fmu``, libcosim, Ecos, and the
project's C host ``fmi_host.c`` run with an empty environment) returns the rows
``(t, outputs...)`` after initialization and after each step, so the hosts can be compared with
each other and with a reference; :func:`fmutool_check` and :func:`binary_libraries` return a
verdict with its text. The Python hosts are test extras (``pip install 'gear_dyn[test]'``); a
runner whose host is missing raises :class:`HostMissing` with what to install.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
import xml.etree.ElementTree as ET
import zipfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from gear_dyn.errors import InputError
from gear_dyn.fmu.toolchain import linux_compiler

#: the C host's source, compiled for FMI 2 (``fmi2_host``) or, with ``-DFMI_VERSION=3``, FMI 3
HOST_SOURCE = Path(__file__).with_name("fmi_host.c")
#: the Linux binaries folder, by FMI version
LINUX_DIR = {2: "linux64", 3: "x86_64-linux"}
#: what a native FMU binary may need (besides the loader and the kernel's vDSO)
ALLOWED_LIBRARIES = ("libc.so", "libm.so")


class HostMissing(RuntimeError):
    """The host is not installed here (the message says what to install)."""


@dataclass(frozen=True)
class FmuFacts:
    """What a host needs to know of an FMU, read from its modelDescription.xml.

    ``variables`` maps each name to its value reference, ``outputs`` lists the output names in
    file order, ``step`` is the DefaultExperiment step size (s; None if absent).
    """

    path: Path
    fmi: int
    model_identifier: str
    token: str
    variables: dict[str, int]
    outputs: list[str]
    step: float | None


def describe(fmu: str | Path) -> FmuFacts:
    """Read the facts of a co-simulation FMU.

    Raises
    ------
    InputError
        Not a readable FMU, or no co-simulation interface.
    """
    path = Path(fmu)
    try:
        with zipfile.ZipFile(path) as z:
            root = ET.fromstring(z.read("modelDescription.xml"))
    except (OSError, KeyError, zipfile.BadZipFile, ET.ParseError) as exc:
        raise InputError(f"{path}: not a readable FMU ({exc})") from None
    fmi = 3 if str(root.get("fmiVersion", "")).startswith("3") else 2
    cs = root.find("CoSimulation")
    if cs is None:
        raise InputError(f"{path}: not a co-simulation FMU (no <CoSimulation>)")
    mv = root.find("ModelVariables")
    elements = [] if mv is None else (list(mv) if fmi == 3 else mv.findall("ScalarVariable"))
    variables = {str(e.get("name")): int(str(e.get("valueReference"))) for e in elements}
    outputs = [str(e.get("name")) for e in elements if e.get("causality") == "output"]
    de = root.find("DefaultExperiment")
    step = de.get("stepSize") if de is not None else None
    return FmuFacts(path, fmi, str(cs.get("modelIdentifier")),
                    str(root.get("instantiationToken" if fmi == 3 else "guid")), variables,
                    outputs, None if step is None else float(step))


# ------------------------------------------------------------------------------ fmpy
def fmpy_rows(fmu: str | Path, names: Sequence[str], step: float, n: int,
              stop: float | None = None,
              start_values: Mapping[str, float] | None = None) -> np.ndarray:
    """fmpy, step by step (FMI 2 or 3): instantiate, set ``start_values`` in initialization
    mode, ``n`` steps of ``step`` seconds; the stop time is announced when given."""
    from gear_dyn.fmu.session3 import open_session

    with open_session(fmu) as s:
        s.instantiate()
        s.initialize(0.0, stop, values=dict(start_values or {}))
        rows = [[0.0, *s.get(list(names))]]
        for k in range(n):
            s.step(k * step, step)
            rows.append([(k + 1) * step, *s.get(list(names))])
        s.terminate()
    return np.array(rows)


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


# ------------------------------------------------------------------------------ C hosts
def compile_c_host(dest: str | Path, fmi: int = 2) -> Path:
    """Compile the FMI 2 or FMI 3 C host into ``dest``.

    Raises
    ------
    HostMissing
        No C compiler on PATH.
    """
    cc = linux_compiler()
    if cc is None:
        raise HostMissing("no C compiler (cc, gcc or clang) on PATH to build the C host")
    exe = Path(dest) / f"fmi{fmi}_host"
    subprocess.run([cc, "-O1", f"-DFMI_VERSION={fmi}", "-o", str(exe), str(HOST_SOURCE), "-ldl"],
                   check=True, capture_output=True)
    return exe


@dataclass(frozen=True)
class CHostRun:
    """A C host run: exit code, rows ``(t, outputs...)``, the libraries mapped into the host
    process and the host's stderr without those lines."""

    returncode: int
    rows: np.ndarray
    mapped: tuple[str, ...]
    stderr: str


def c_host_rows(fmu: str | Path, names: Sequence[str], step: float, n: int,
                stop: float | None = None, start_values: Mapping[str, float] | None = None,
                exe: Path | None = None, env: Mapping[str, str] | None = None) -> CHostRun:
    """The project's C host (compiled unless ``exe`` is given) on the unzipped FMU, with the
    environment ``env`` (default: empty)."""
    facts = describe(fmu)
    with tempfile.TemporaryDirectory(prefix="gear_dyn_host_") as tmp:
        d = Path(tmp)
        exe = exe or compile_c_host(d, facts.fmi)
        with zipfile.ZipFile(facts.path) as z:
            z.extractall(d / "fmu")
        argv = [str(exe), str((d / "fmu").resolve()), facts.model_identifier, facts.token,
                "none" if stop is None else repr(stop), repr(step), str(n),
                ",".join(str(facts.variables[k]) for k in names),
                *(f"r{facts.variables[k]}={float(v)!r}" for k, v in (start_values or {}).items())]
        proc = subprocess.run(argv, capture_output=True, text=True, env=dict(env or {}),
                              timeout=600)
    marker = f"fmi{facts.fmi}_host: mapped "
    mapped = tuple(line[len(marker):] for line in proc.stderr.splitlines()
                   if line.startswith(marker))
    rest = "\n".join(line for line in proc.stderr.splitlines() if not line.startswith(marker))
    rows = np.array([[float(v) for v in line.split()] for line in proc.stdout.splitlines()])
    return CHostRun(proc.returncode, rows, mapped, rest)


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
