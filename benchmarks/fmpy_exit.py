"""Does fmpy exit cleanly after running a gear_dyn FMU? Fresh processes, counted by variant.

Usage: python benchmarks/fmpy_exit.py [--runs N] [--variants a,b,...] [--fmi 2,3]
                                      [--fmu FILE] [--malloc-check] [--no-pymalloc] [--record]
(--record writes the table to benchmarks/results/fmpy_exit.md)

Each run is a fresh Python process that loads the FMU with fmpy, initializes it, does 20
communication steps, terminates, then ends in one of these ways (the variants):

- ``full``: fmi2FreeInstance (fmi3FreeInstance) and fmpy's unloading of the binary
  (``FMU2Slave.freeInstance``, which dlcloses the library) - what ``fmpy.simulate_fmu`` does;
- ``no-dlclose``: fmi2FreeInstance (fmi3FreeInstance) only (the binary stays loaded until exit);
- ``no-free``: neither (the instance is still alive when the interpreter shuts down);
- ``plain-exit``: ``full``, then ``os._exit(0)`` after flushing (no interpreter shutdown, no C
  exit handlers): tells whether the crash is in the shutdown;
- ``simulate``: ``fmpy.simulate_fmu`` on the .fmu file (extracts, runs, frees, unloads and
  removes the extracted copy), as a user runs it;
- ``scipy-only``: no FMU at all, only numpy and scipy imported and used as the FMU does
  (the baseline of the interpreter's own shutdown).

``--fmi`` picks the FMUs: the helicopter_tail scene built as FMI 2 (pythonfmu) and/or FMI 3
(pythonfmu3), one table row per FMI version and variant; ``--fmu FILE`` runs a given FMU
instead (e.g. one built by an older gear_dyn, to measure a fix against what it fixed).

A run is clean when the process exits with code 0 and prints nothing on stderr. The table
gives the number of unclean runs per variant and the first lines of one failure.
``--malloc-check`` runs with ``MALLOC_CHECK_=3`` (glibc aborts at the first heap inconsistency
it sees, closer to its cause) and the fault handler on (the Python stack at the abort);
``--no-pymalloc`` with ``PYTHONMALLOC=malloc`` (every Python object from glibc's malloc, so a
Python object freed twice is caught by glibc too).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

CHILD = r'''
import os, sys
variant, unzipped = sys.argv[1], sys.argv[2]
if variant == "simulate":
    from fmpy import simulate_fmu
    simulate_fmu(sys.argv[3], stop_time=20 * float(sys.argv[4]), output_interval=float(sys.argv[4]))
    sys.exit(0)
if variant == "scipy-only":
    import numpy as np
    from scipy.linalg import expm, matrix_balance
    from scipy.integrate import DOP853
    expm(np.eye(3)); matrix_balance(np.eye(3))
    sys.exit(0)
from fmpy import read_model_description
md = read_model_description(unzipped)
fmi3 = md.fmiVersion.startswith("3")
if fmi3:
    from fmpy.fmi3 import FMU3Slave as Slave
else:
    from fmpy.fmi2 import FMU2Slave as Slave
fmu = Slave(guid=md.guid, unzipDirectory=unzipped,
            modelIdentifier=md.coSimulation.modelIdentifier, instanceName="exit")
fmu.instantiate()
if not fmi3:
    fmu.setupExperiment(startTime=0.0)
fmu.enterInitializationMode()
fmu.exitInitializationMode()
vrs = [v.valueReference for v in md.modelVariables if v.causality == "output"]
h = float(md.defaultExperiment.stepSize)
get = fmu.getFloat64 if fmi3 else fmu.getReal
for k in range(20):
    fmu.doStep(k * h, h)
    get(vrs)
fmu.terminate()
if variant in ("full", "plain-exit"):
    fmu.freeInstance()
elif variant == "no-dlclose":
    (fmu.fmi3FreeInstance if fmi3 else fmu.fmi2FreeInstance)(fmu.component)
if variant == "plain-exit":
    sys.stdout.flush(); sys.stderr.flush()
    os._exit(0)
'''

VARIANTS = ("full", "no-dlclose", "no-free", "plain-exit", "simulate", "scipy-only")


def run(variant: str, fmu: Path, unzipped: Path, step: float, runs: int,
        malloc_check: bool, no_pymalloc: bool) -> tuple[int, str]:
    """Unclean runs out of ``runs`` and the stderr tail of the first unclean one."""
    env = dict(os.environ)
    if malloc_check:
        env.update(MALLOC_CHECK_="3", PYTHONFAULTHANDLER="1")
    if no_pymalloc:
        env["PYTHONMALLOC"] = "malloc"
    bad, first = 0, ""
    for _ in range(runs):
        proc = subprocess.run([sys.executable, "-c", CHILD, variant, str(unzipped), str(fmu),
                               repr(step)],
                              capture_output=True, text=True, env=env, timeout=300)
        if proc.returncode != 0 or proc.stderr.strip():
            bad += 1
            if not first:
                tail = proc.stderr.strip().splitlines()[-12 if malloc_check else -3:]
                first = f"exit {proc.returncode}: " + " / ".join(tail)
    return bad, first


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--runs", type=int, default=40)
    ap.add_argument("--variants", default=",".join(VARIANTS))
    ap.add_argument("--fmi", default="2,3", help="FMI versions of the FMUs built (2, 3 or 2,3)")
    ap.add_argument("--fmu", type=Path, default=None,
                    help="run this FMU instead of building them")
    ap.add_argument("--malloc-check", action="store_true")
    ap.add_argument("--no-pymalloc", action="store_true")
    ap.add_argument("--record", action="store_true",
                    help="also write the table to benchmarks/results/fmpy_exit.md")
    args = ap.parse_args()
    from gear_dyn.fmu.build import build_fmu, read_spec

    with tempfile.TemporaryDirectory() as tmp:
        fmus: list[tuple[str, Path]] = []
        if args.fmu is not None:
            fmus.append((str(args.fmu), args.fmu.resolve()))
        else:
            for fmi in (int(v) for v in args.fmi.split(",")):
                built = build_fmu("helicopter_tail", Path(tmp) / f"heli{fmi}.fmu", fmi=fmi)
                fmus.append((f"FMI {fmi}", built.path))
        flags = "".join(f" --{k.replace('_', '-')}" for k in ("malloc_check", "no_pymalloc")
                        if getattr(args, k))
        which = f" --fmu {args.fmu}" if args.fmu is not None else f" --fmi {args.fmi}"
        lines = ["# fmpy exits after running the FMU", "",
                 f"Command: `python benchmarks/fmpy_exit.py --runs {args.runs} --variants "
                 f"{args.variants}{which}{flags}`", "",
                 "| FMU | variant | unclean exits | first failure |", "|---|---|---:|---|"]
        print("\n".join(lines), flush=True)
        for label, fmu in fmus:
            step = float(read_spec(fmu)["experiment"]["step_size"])
            unzipped = Path(tmp) / f"unzipped_{len(lines)}"
            with zipfile.ZipFile(fmu) as z:
                z.extractall(unzipped)
            for variant in args.variants.split(","):
                bad, first = run(variant, fmu, unzipped, step, args.runs, args.malloc_check,
                                 args.no_pymalloc)
                lines.append(f"| {label} | {variant} | {bad}/{args.runs} | {first or '-'} |")
                print(lines[-1], flush=True)
    if args.record:
        (ROOT / "benchmarks" / "results" / "fmpy_exit.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
