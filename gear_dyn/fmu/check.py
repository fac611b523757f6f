"""``gear-dyn fmu check``: a user's own check of an FMU built by gear_dyn (FMI 2 or 3, native or
pythonfmu; the outputs and the step come from the modelDescription, so any co-simulation FMU
can be checked).

Four checks, each a line of the report: fmpy's validation, a run in fmpy, stop-time
independence and a run in the C host of :func:`gear_dyn.fmu.hosts.c_host_rows` (skipped for a
pythonfmu FMU, which runs in Python hosts only); what each requires: docs/fmu.md, "Check an
FMU".
"""

from __future__ import annotations

import os
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from gear_dyn.errors import InputError
from gear_dyn.fmu.hosts import HostMissing, c_host_rows, describe, fmpy_rows

#: agreement required between hosts and between stop-time settings (relative to each
#: output's largest value): the same code runs, so only rounding may differ
AGREEMENT = 1e-12


@dataclass(frozen=True)
class CheckLine:
    """One check: its name, outcome (None: could not run here) and a one-line detail."""

    name: str
    ok: bool | None
    detail: str


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

    path = Path(fmu)
    facts = describe(path)
    names = facts.outputs
    if facts.step is None:
        raise InputError(f"{path}: no DefaultExperiment stepSize to check the FMU with")
    h = facts.step
    lines = []
    problems = list(validate_fmu(str(path)))
    lines.append(CheckLine("validation", not problems,
                           f"fmpy, FMI {facts.fmi}.0: no problems" if not problems
                           else "; ".join(problems)[:200]))
    try:
        free = fmpy_rows(path, names, h, n_steps)
        announced = fmpy_rows(path, names, h, n_steps, stop=n_steps * h)
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
    lines.append(_c_host_line(path, names, h, n_steps, free, facts.fmi))
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
    try:
        run = c_host_rows(path, names, h, n, env=numerics_environment())
    except HostMissing:
        return CheckLine("C host", None, "skipped: no C compiler (cc) to build the host")
    rows = run.rows
    if run.returncode != 0:
        tail = run.stderr.strip().splitlines()[-1:] or [""]
        return CheckLine("C host", False, f"exit code {run.returncode}: {tail[0][:160]}")
    if rows.shape != ref.shape:
        return CheckLine("C host", False, f"{rows.shape[0]} rows, expected {ref.shape[0]}")
    d_c = _rel(rows, ref)
    python = [x for x in run.mapped if "python" in x]
    return CheckLine("C host", d_c <= AGREEMENT and not python,
                     f"fmi{fmi}_host: empty environment, exit 0, "
                     + (f"libpython mapped ({python[0]})" if python
                        else "no libpython in the process")
                     + f"; vs fmpy max diff {d_c:.2e} (required <= {AGREEMENT:g})")


def verdict(lines: list[CheckLine]) -> bool:
    """True when no check failed (a check that could not run here does not fail)."""
    return all(line.ok is not False for line in lines)
