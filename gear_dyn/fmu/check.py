"""``gear-dyn fmu check``: a user's own check of an FMU built by gear_dyn (FMI 2 or 3, native or
pythonfmu; the outputs and the step come from the modelDescription, so any co-simulation FMU
can be checked).

Four checks, each a line of the report, for FMI 2 and FMI 3 FMUs: fmpy's validation of the
modelDescription, a run in fmpy (a Python host), a run in a plain C host (``fmi2_host.c``,
or its FMI 3 twin ``fmi3_host.c``, compiled with the system compiler, loading the binary
``RTLD_LOCAL`` in an empty environment) that must give fmpy's outputs to 1e-12, and stop-time
independence (the same run with and without a stop time announced at initialization must
agree to 1e-12). For an FMU that needs no Python (native) the C host line also says that no
libpython was mapped into the host process; a pythonfmu FMU runs in Python hosts only, so its C
host line is skipped.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
import xml.etree.ElementTree as ET
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from gear_dyn.errors import InputError

HOST_SOURCE = Path(__file__).with_name("fmi2_host.c")
#: the FMI 3 twin (same arguments and output)
HOST3_SOURCE = Path(__file__).with_name("fmi3_host.c")
#: agreement required between hosts and between stop-time settings (relative to each
#: output's largest value): the same code runs, so only rounding may differ
AGREEMENT = 1e-12


@dataclass(frozen=True)
class CheckLine:
    """One check: its name, outcome (None: could not run here) and a one-line detail."""

    name: str
    ok: bool | None
    detail: str


def compile_host(dest: Path, fmi: int = 2) -> Path | None:
    """Compile the FMI 2 (or, ``fmi=3``, the FMI 3) C host into ``dest``; None when no C
    compiler is on PATH."""
    cc = shutil.which("cc") or shutil.which("gcc") or shutil.which("clang")
    if cc is None:
        return None
    exe = dest / f"fmi{fmi}_host"
    source = HOST3_SOURCE if fmi == 3 else HOST_SOURCE
    subprocess.run([cc, "-O1", "-o", str(exe), str(source), "-ldl"], check=True,
                   capture_output=True)
    return exe


#: environment variables that select the BLAS kernels and threads (not needed to run an FMU,
#: but they change the last bits of linear algebra: with OPENBLAS_CORETYPE set in the caller
#: and absent in the host, the eccentric scene's FMU differed from fmpy by 2e-12)
NUMERICS_VARIABLES = ("OPENBLAS_CORETYPE", "OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS",
                      "MKL_NUM_THREADS", "MKL_CBWR", "OPENBLAS_VERBOSE")


def numerics_environment() -> dict[str, str]:
    """The C host's environment: empty (no Python path, home or virtual environment: nothing a
    host needs) except the caller's BLAS kernel and thread settings, so that the C host and
    fmpy do the same arithmetic."""
    return {k: os.environ[k] for k in NUMERICS_VARIABLES if k in os.environ}


def run_c_host(exe: Path, unzipped: Path, names: list[str], stop: float | None, step: float,
               n: int) -> tuple[subprocess.CompletedProcess[str], np.ndarray]:
    """Run the C host (empty environment but the BLAS settings, :func:`numerics_environment`)
    on an unzipped FMU: the process and the printed rows (t, outputs...)."""
    root = ET.parse(unzipped / "modelDescription.xml").getroot()
    fmi3 = str(root.get("fmiVersion", "")).startswith("3")
    mv = root.find("ModelVariables")
    variables = list(mv if mv is not None else []) if fmi3 else root.iter("ScalarVariable")
    vr = {sv.get("name"): sv.get("valueReference") for sv in variables}
    cs = root.find("CoSimulation")
    if cs is None:
        raise InputError(f"{unzipped}: not a co-simulation FMU")
    token = root.get("instantiationToken") if fmi3 else root.get("guid")
    argv = [str(exe), str(unzipped.resolve()), str(cs.get("modelIdentifier")),
            str(token), "none" if stop is None else repr(stop), repr(step), str(n),
            ",".join(str(vr[k]) for k in names)]
    proc = subprocess.run(argv, capture_output=True, text=True, env=numerics_environment(),
                          timeout=600)
    rows = [[float(v) for v in line.split()] for line in proc.stdout.splitlines()]
    return proc, np.array(rows)


def fmpy_rows(fmu: Path, names: list[str], stop: float | None, step: float,
              n: int) -> np.ndarray:
    """The same run through fmpy (FMI 2 or 3): rows (t, outputs...) after initialization and
    each step."""
    from gear_dyn.fmu.session3 import open_session

    with open_session(fmu) as s:
        s.instantiate()
        s.initialize(0.0, stop)
        rows = [[0.0, *s.get(names)]]
        for k in range(n):
            s.step(k * step, step)
            rows.append([(k + 1) * step, *s.get(names)])
        s.terminate()
    return np.array(rows)


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    scale = np.max(np.abs(b), axis=0) + 1e-300
    return float(np.max(np.abs(a - b) / scale))


def check_fmu(fmu: str | Path, n_steps: int = 64) -> list[CheckLine]:
    """Run the four checks on a co-simulation FMU (``n_steps`` default-experiment steps).

    Raises
    ------
    InputError
        Not a readable co-simulation FMU, or one without a DefaultExperiment step size.
    """
    from fmpy.validation import validate_fmu

    from gear_dyn.fmu.hosts import describe
    from gear_dyn.fmu.session3 import fmi_version

    path = Path(fmu)
    facts = describe(path)
    version = fmi_version(path)
    names = facts.outputs
    if facts.step is None:
        raise InputError(f"{path}: no DefaultExperiment stepSize to check the FMU with")
    h = facts.step
    lines = []
    problems = list(validate_fmu(str(path)))
    lines.append(CheckLine("validation", not problems,
                           f"fmpy, FMI {version}: no problems" if not problems
                           else "; ".join(problems)[:200]))
    try:
        free = fmpy_rows(path, names, None, h, n_steps)
        announced = fmpy_rows(path, names, n_steps * h, h, n_steps)
    except Exception as exc:  # the report says why the run failed
        lines.append(CheckLine("fmpy run", False, str(exc)[:200]))
        return lines
    finite = bool(np.all(np.isfinite(free)))
    lines.append(CheckLine("fmpy run", finite, f"{n_steps} steps of {h:.6g} s, "
                           f"{len(names)} outputs" + ("" if finite else ", NOT finite")))
    d = _rel(announced, free)
    lines.append(CheckLine("stop-time independence", d <= AGREEMENT,
                           f"with vs without stop time: max diff {d:.2e} of each output's "
                           f"largest value (required <= {AGREEMENT:g})"))
    lines.append(_c_host_line(path, names, h, n_steps, free, 3 if version.startswith("3")
                              else 2))
    return lines


def _c_host_line(path: Path, names: list[str], h: float, n: int,
                 ref: np.ndarray, fmi: int) -> CheckLine:
    with zipfile.ZipFile(path) as z:
        files = z.namelist()
    python_fmu = any(x.startswith(("resources/pythonfmu", "resources/gear_dyn_fmu_"))
                     for x in files)
    if python_fmu:
        return CheckLine("C host", None, "skipped: a pythonfmu FMU runs in Python hosts only "
                         "(build the native FMU for other hosts)")
    with tempfile.TemporaryDirectory(prefix="gear_dyn_check_") as tmp:
        d = Path(tmp)
        exe = compile_host(d, fmi)
        if exe is None:
            return CheckLine("C host", None, "skipped: no C compiler (cc) to build the host")
        with zipfile.ZipFile(path) as z:
            z.extractall(d / "fmu")
        proc, rows = run_c_host(exe, d / "fmu", names, None, h, n)
    if proc.returncode != 0:
        tail = proc.stderr.strip().splitlines()[-1:] or [""]
        return CheckLine("C host", False, f"exit code {proc.returncode}: {tail[0][:160]}")
    if rows.shape != ref.shape:
        return CheckLine("C host", False, f"{rows.shape[0]} rows, expected {ref.shape[0]}")
    d_c = _rel(rows, ref)
    marker = f"fmi{fmi}_host: mapped "
    python = [x for x in proc.stderr.splitlines() if x.startswith(marker) and "python" in x]
    return CheckLine("C host", d_c <= AGREEMENT and not python,
                     f"fmi{fmi}_host: empty environment, exit 0, "
                     + (f"libpython mapped ({python[0][len(marker):]})" if python
                        else "no libpython in the process")
                     + f"; vs fmpy max diff {d_c:.2e} (required <= {AGREEMENT:g})")


def verdict(lines: list[CheckLine]) -> bool:
    """True when no check failed (a check that could not run here does not fail)."""
    return all(line.ok is not False for line in lines)
