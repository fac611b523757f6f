"""Step cost of the native gear FMU against the trivial C FMU (the floor) and the pythonfmu FMU.

    python benchmarks/bench_native_fmu.py [--repeats 7] [--out benchmarks/results/native_fmu.md]

All FMUs are built in this run (FMI 2 co-simulation) and measured in one process, the repeats
taking turns over the FMUs:

- C host (benchmarks/step_timer.c, compiled with cc -O2): one fmi2DoStep, at 16 steps per mesh
  period of the helicopter_tail scene (of its own scene for the torsional FMUs: 450 Hz mesh
  frequency), no output read (target of issue 23: <= 1 us for the exact single-DOF FMU);
- fmpy (FMU2Slave): one doStep + one getReal of all the gear FMU's outputs; the trivial FMU
  reads its one output as many times, so both move the same number of values (target: the
  native FMU within 1.3x of the trivial FMU);
- the FMU file sizes (target: <= 500 KB).

The native rows are absent while the native build (gear_dyn.fmu.export_fmu) is not in the
tree. The torsional FMUs are built without the size limit (both are within it now):
their size is reported.
"""

from __future__ import annotations

import argparse
import importlib.util
import statistics
import subprocess
import sys
import tempfile
import time
import zipfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

from gear_dyn.fmu import hosts
from gear_dyn.fmu.toolchain import linux_compiler

HERE = Path(__file__).resolve().parent
SCENES = HERE.parent / "examples" / "scenes"
MESH_HZ = 23 * 3319 / 60  # helicopter_tail: 23 teeth at 3319 rpm
H = 1 / (16 * MESH_HZ)  # 16 steps per mesh period
#: the torsional scenes' step: 16 per mesh period at 18 teeth, 1500 rpm (450 Hz)
H_TORSIONAL = 1 / (16 * 18 * 1500 / 60)
TORSIONAL = ("eccentric_helical", "eccentric_helical_ideal")
C_STEPS, FMPY_STEPS = 200_000, 4000


def _trivial(out: Path) -> Path:
    spec = importlib.util.spec_from_file_location("trivial_build",
                                                  HERE / "trivial_fmu" / "build.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return Path(mod.build_trivial_fmu(out, 2))


def step_of(name: str) -> float:
    """The communication step of an FMU row, s."""
    return H_TORSIONAL if name.removeprefix("native ") in TORSIONAL else H


def _builds(d: Path) -> dict[str, tuple[Path, str]]:
    """name -> (fmu, kind); kind: trivial, native, python."""
    fmus = {"trivial C FMU": (_trivial(d / "trivial.fmu"), "trivial")}
    if importlib.util.find_spec("gear_dyn.fmu.export_fmu") is not None:
        from gear_dyn.fmu.export_fmu import build_native_fmu

        for scene in ("helicopter_tail", "helicopter_tail_backlash", "helicopter_tail_relief",
                      *TORSIONAL):
            try:
                built = build_native_fmu(SCENES / f"{scene}.toml", d / f"{scene}.fmu",
                                         max_size=None if scene in TORSIONAL else 500_000)
            except Exception as exc:  # reported in the table
                print(f"native {scene}: not built ({exc})", file=sys.stderr)
                continue
            fmus[f"native {scene}"] = (built.path, "native")
    from gear_dyn.fmu.build import build_fmu

    fmus["pythonfmu helicopter_tail"] = (build_fmu("helicopter_tail", d / "py.fmu").path,
                                         "python")
    return fmus


def _c_timer(d: Path) -> Path:
    cc = linux_compiler()
    if cc is None:
        raise SystemExit("no C compiler: the C-host timing needs cc")
    exe = d / "step_timer"
    subprocess.run([cc, "-O2", "-o", str(exe), str(HERE / "step_timer.c"), "-ldl"], check=True)
    return exe


def _c_host_ns(exe: Path, fmu: Path, d: Path, h: float) -> float:
    """Median ns per fmi2DoStep over 5 loops of C_STEPS steps in one process."""
    facts = hosts.describe(fmu)
    unz = d / f"u_{fmu.stem}"
    if not unz.exists():
        with zipfile.ZipFile(fmu) as z:
            z.extractall(unz)
    out = subprocess.run([str(exe), str(unz.resolve()), facts.model_identifier, facts.token,
                          repr(h), str(C_STEPS), "5"], capture_output=True, text=True, env={},
                         check=True).stdout
    return statistics.median(float(x) for x in out.split())


def _fmpy_us(fmu: Path, d: Path, n_values: int, h: float) -> float:
    """us per doStep + getReal of n_values values through fmpy (one run of FMPY_STEPS)."""
    from fmpy import read_model_description
    from fmpy.fmi2 import FMU2Slave

    unz = d / f"u_{fmu.stem}"
    if not unz.exists():
        with zipfile.ZipFile(fmu) as z:
            z.extractall(unz)
    md = read_model_description(str(unz))
    outs = [v.valueReference for v in md.modelVariables if v.causality == "output"]
    vrs = (outs * n_values)[:n_values]
    s = FMU2Slave(guid=md.guid, unzipDirectory=str(unz),
                  modelIdentifier=md.coSimulation.modelIdentifier, instanceName="bench")
    s.instantiate()
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    do_step: Callable[..., Any] = s.doStep
    get: Callable[..., Any] = s.getReal
    t0 = time.perf_counter()
    for k in range(FMPY_STEPS):
        do_step(k * h, h)
        get(vrs)
    us = (time.perf_counter() - t0) / FMPY_STEPS * 1e6
    s.terminate()
    s.freeInstance()
    return us


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--out", type=Path, default=HERE / "results" / "native_fmu.md")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="bench_native_") as tmp:
        d = Path(tmp)
        fmus = _builds(d)
        exe = _c_timer(d)
        native = [f for f, (_, kind) in fmus.items() if kind == "native"]
        n_values = max((len(hosts.describe(fmus[f][0]).outputs) for f in native
                        if f.removeprefix("native ") not in TORSIONAL), default=1)
        c_ns: dict[str, list[float]] = {f: [] for f in fmus}
        py_us: dict[str, list[float]] = {f: [] for f in fmus}
        for _ in range(args.repeats):
            for name, (fmu, kind) in fmus.items():
                if kind != "python":  # the pythonfmu FMU runs in Python hosts only
                    c_ns[name].append(_c_host_ns(exe, fmu, d, step_of(name)))
                n = n_values if kind == "trivial" else len(hosts.describe(fmu).outputs)
                py_us[name].append(_fmpy_us(fmu, d, n, step_of(name)))
        sizes = {name: fmu.stat().st_size for name, (fmu, _) in fmus.items()}
        outputs = {name: len(hosts.describe(fmu).outputs) for name, (fmu, _) in fmus.items()}
    floor_c = statistics.median(c_ns["trivial C FMU"])
    floor_py = statistics.median(py_us["trivial C FMU"])
    lines = [
        "# Native FMU: step cost against the trivial C FMU",
        "",
        f"Command: `python benchmarks/bench_native_fmu.py --repeats {args.repeats}` "
        "(all FMUs built and measured in this one run, repeats taking turns; medians, range "
        "in brackets). Step h = 1/(16 f_mesh) of helicopter_tail = "
        f"{H:.6g} s; of the torsional scenes 1/(16 x 450 Hz) = {H_TORSIONAL:.6g} s. "
        f"C host: benchmarks/step_timer.c, {C_STEPS} x fmi2DoStep per loop, "
        f"median of 5 loops per repeat; fmpy: {FMPY_STEPS} x (doStep + getReal) per repeat, "
        f"the trivial FMU reading its output {n_values} times (the gear FMUs' output count).",
        "",
        "| FMU | outputs | C host per doStep | / trivial | fmpy per step | / trivial | size |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    for name in fmus:
        c = c_ns[name]
        cs = (f"{statistics.median(c):.0f} ns [{min(c):.0f}-{max(c):.0f}]" if c else
              "- (needs Python)")
        cr = f"{statistics.median(c) / floor_c:.2f}x" if c else "-"
        p = py_us[name]
        ps = f"{statistics.median(p):.2f} us [{min(p):.2f}-{max(p):.2f}]"
        pr = f"{statistics.median(p) / floor_py:.2f}x"
        lines.append(f"| {name} | {outputs[name]} | {cs} | {cr} | {ps} | {pr} | "
                     f"{sizes[name] / 1000:.0f} KB |")
    if not native:
        lines += ["", "No native FMU in this tree (gear_dyn.fmu.export_fmu absent): floor only."]
    text = "\n".join(lines) + "\n"
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text)
    print(text)


if __name__ == "__main__":
    main()
