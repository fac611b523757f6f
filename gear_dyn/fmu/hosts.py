"""The hosts `gear-dyn fmu check` runs one FMU in, each the same way: start at 0, fixed
communication steps.

Each runner (``*_rows``: fmpy step by step, and the project's C host ``fmi_host.c`` run with an
empty environment) returns the rows ``(t, outputs...)`` after initialization and after each
step, so the hosts can be compared with each other and with a reference. A runner whose host is
missing raises :class:`HostMissing` with what to install. The runners of the other hosts the
tests use (fmpy's ``simulate_fmu``, fmutool, libcosim, Ecos, ``ldd``) are in
``tests/fmu/host_runners.py``.
"""

from __future__ import annotations

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
