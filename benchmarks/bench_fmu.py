"""FMU co-simulation overhead and agreement, quoted in docs/fmu.md.

Usage: python benchmarks/bench_fmu.py [--repeats N] [--out FILE]
(default FILE: benchmarks/results/fmu.md)
       python benchmarks/bench_fmu.py --per-step [--repeats N]
(per-step cost against a trivial pythonfmu FMU, and of the FMI 3 FMU against a trivial
pythonfmu3 FMU, side by side in one run; default FILE: benchmarks/results/fmu_per_step.md)

For the helicopter tail scene (single-DOF, exact propagation, 40 mesh periods) and the eccentric
helical scene (torsional, eccentricity + friction, DOP853 rtol 1e-7, 12 mesh periods), at 4, 16
and 64 communication steps per mesh period:

- ``direct``: one :func:`gear_dyn.solvers.integrate` call on the communication grid with the
  scene's own method (what the FMU runs inside);
- ``stepper``: the FMU's :class:`gear_dyn.fmu.stepper.Stepper` driven from Python step by step,
  with the outputs computed at each step (no FMI layer);
- ``FMU``: the built FMU through fmpy (instantiate, initialize, doStep + getReal per step,
  terminate; the one-time import of the FMU's Python code is done before timing);
- ``restart``: for ODE methods, a fresh solve_ivp set-up per communication step from the last
  state (what the FMU avoids), to show what keeping the solver alive saves.

Overhead per communication step = (FMU - direct) / steps. Times are medians of --repeats runs.
The agreement columns compare the FMU's DTE and mesh force with solve_ivp (the project's default
ODE method) at the scene's rtol, relative to each output's RMS.
"""

from __future__ import annotations

import argparse
import platform
import re
import statistics
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from _timing import median_time  # noqa: E402  (benchmarks/ is on sys.path)

from gear_dyn.fmu.build import build_fmu
from gear_dyn.fmu.cosim import FmuSession, compare, extracted
from gear_dyn.fmu.stepper import Stepper
from gear_dyn.scene import build_plan, load_scene
from gear_dyn.solvers import integrate


def median_s(fn, repeats: int) -> float:  # type: ignore[no-untyped-def]
    """Median wall time of ``repeats`` calls in s."""
    return float(median_time(fn, repeats)[0])


ROOT = Path(__file__).resolve().parents[1]
CASES = (("helicopter_tail", 40), ("eccentric_helical", 12))
PER_PERIOD = (4, 16, 64)


def scene_file(name: str) -> Path:
    """The example scene ``name``; the eccentric one with its solver pinned to DOP853 (the scene
    says auto, which a whole run integrates by Gauss-Legendre step maps, and an FMU by LSODA):
    the FMU keeps one DOP853 solver across communication steps, as these tables measure."""
    path = ROOT / "examples" / "scenes" / f"{name}.toml"
    if name != "eccentric_helical":
        return path
    pinned = re.sub(r'(?m)^method = "auto".*$', 'method = "DOP853"', path.read_text())
    if pinned == path.read_text():
        raise SystemExit(f"{path}: no 'method = \"auto\"' line to pin")
    out = Path(tempfile.gettempdir()) / "gear_dyn_bench_eccentric_dop853.toml"
    out.write_text(pinned)
    return out


def _row(name: str, model, settings, fmu: Path, unzipdir: str, per: int, periods: int,  # type: ignore[no-untyped-def]
         repeats: int) -> str:
    h = 1 / (model.mesh_frequency * per)
    n = periods * per
    grid = np.arange(n + 1) * h
    t_direct = median_s(lambda: integrate(model, grid, settings), repeats)

    def stepper() -> None:
        st = Stepper(model, settings)
        for t in grid[1:]:
            st.advance(float(t))
            model.outputs(np.array([st.t]), st.y[:, None])

    def fmu_run() -> None:
        with FmuSession(fmu, unzipdir=unzipdir) as s:
            s.run(h, float(grid[-1]) + 0.5 * h, ["dte", "mesh_force"], stop_time=float(grid[-1]))

    t_step = median_s(stepper, repeats)
    t_fmu = median_s(fmu_run, repeats)
    restart = "-"
    method = Stepper(model, settings).method
    if method != "exact":
        ode = replace(settings, method=method)

        def naive() -> None:
            y = model.initial_state()
            for k in range(n):
                y = integrate(model, grid[k:k + 2], ode, y)[0][:, -1]
        restart = f"{median_s(naive, 1):.3g} s"
    return (f"| {name} | {method} | {per} | {n} | {t_direct:.3g} s | {t_step:.3g} s | "
            f"{t_fmu:.3g} s | {restart} | {(t_fmu - t_direct) / n * 1e6:.0f} us | "
            f"{(t_fmu - t_step) / n * 1e6:.0f} us |")


def overhead(name: str, periods: int, fmu: Path, repeats: int) -> list[str]:
    plan = build_plan(load_scene(scene_file(name)))
    tmp = extracted(fmu)
    with FmuSession(fmu, unzipdir=tmp.name) as s:
        s.instantiate()  # import the FMU's code once
    rows = [_row(name, plan.model, plan.settings, fmu, tmp.name, per, periods, repeats)
            for per in PER_PERIOD]
    tmp.cleanup()
    return rows


def agreement(name: str, periods: int, fmu: Path) -> list[str]:
    scene = load_scene(scene_file(name))
    f_m = build_plan(scene).model.mesh_frequency
    steps = [1 / (f_m * per) for per in sorted(PER_PERIOD, reverse=True)]
    rep = compare(fmu, steps=steps, stop_time=periods / f_m)
    rows = []
    for s in rep.steps:
        rows.append(
            f"| {name} | {rep.fmu_method} | solve_ivp {rep.reference_method} | {rep.rtol:g} | "
            f"{round(1 / (s.step * f_m))} | {s.fmu_run_time_s:.3g} s | "
            f"{rep.reference_run_time_s:.3g} s | "
            f"{s.max_diff['dte'] / rep.scales['dte']:.2e} | "
            f"{s.rms_diff['dte'] / rep.scales['dte']:.2e} | "
            f"{s.max_diff['mesh_force'] / rep.scales['mesh_force']:.2e} |")
    return rows


TRIVIAL = '''
from pythonfmu import Fmi2Causality, Fmi2Slave, Real


class TrivialBench(Fmi2Slave):
    """One output, y = t: the floor of a pythonfmu FMU's per-step cost."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.y = 0.0
        self.register_variable(Real("y", causality=Fmi2Causality.output))

    def do_step(self, current_time, step_size):
        self.y = current_time + step_size
        return True
'''


TRIVIAL3 = '''
from pythonfmu3 import Fmi3Causality, Fmi3Slave, Fmi3Variability, Float64


class TrivialBench3(Fmi3Slave):
    """One output, y = t: the floor of a pythonfmu3 FMU's per-step cost."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.y = 0.0
        self.time = 0.0
        self.register_variable(Float64("time", causality=Fmi3Causality.independent,
                                       variability=Fmi3Variability.continuous))
        self.register_variable(Float64("y", causality=Fmi3Causality.output))

    def do_step(self, current_time, step_size):
        self.y = self.time = current_time + step_size
        return True
'''


def _per_step_us(fmu: Path, unzipdir: str, outputs: list[str], h: float, n: int,
                 values: dict[str, object] | None = None) -> float:
    """Microseconds per doStep + getReal(outputs) (FMI 3: getFloat64) through fmpy (one run
    of n steps)."""
    from fmpy import read_model_description

    md = read_model_description(unzipdir)
    vrs = [v.valueReference for name in outputs
           for v in md.modelVariables if v.name == name]
    if md.fmiVersion.startswith("3"):
        from fmpy.fmi3 import FMU3Slave

        fmu3 = FMU3Slave(guid=md.guid, unzipDirectory=unzipdir,
                         modelIdentifier=md.coSimulation.modelIdentifier, instanceName="bench")
        fmu3.instantiate()
        fmu3.enterInitializationMode()
        for name, value in (values or {}).items():
            v = next(x for x in md.modelVariables if x.name == name)
            items = {i.name: int(i.value) for i in v.declaredType.items}
            fmu3.setInt64([v.valueReference], [items[str(value)]])
        fmu3.exitInitializationMode()
        us = _time_steps(fmu3.doStep, fmu3.getFloat64, vrs, h, n)
        fmu3.terminate()
        fmu3.freeInstance()
        return us
    with FmuSession(fmu, unzipdir=unzipdir) as s:
        s.instantiate()
        s.initialize(0.0, None, None, values)
        us = _time_steps(s.fmu.doStep, s.fmu.getReal, vrs, h, n)
        s.terminate()
    return us


def _time_steps(do_step, get, vrs: list[int], h: float, n: int) -> float:  # type: ignore[no-untyped-def]
    t0 = time.perf_counter()
    for k in range(n):
        do_step(k * h, h)
        get(vrs)
    return (time.perf_counter() - t0) / n * 1e6


def per_step(repeats: int, out: Path) -> None:
    """Per-step cost of the helicopter tail FMU (exact, LSODA, DOP853; 16 steps per mesh period)
    and of the eccentric helical FMU (DOP853) against a trivial pythonfmu FMU, and of the
    helicopter tail FMI 3 FMU (exact, LSODA) against a trivial pythonfmu3 FMU, in one run; the
    repeats go round the FMUs (a change of the machine's load hits every row alike)."""
    from pythonfmu import FmuBuilder
    from pythonfmu3 import FmuBuilder as FmuBuilder3

    n = 2000
    lines = ["# FMU per-step cost against a trivial pythonfmu FMU", "",
             f"Command: `python benchmarks/bench_fmu.py --per-step --repeats {repeats}`  ",
             f"Machine: {platform.machine()}, Python {platform.python_version()} (2 shared "
             f"cores). {n} x (doStep + getReal of the outputs) through fmpy, after "
             "initialization (FMI 3: doStep + getFloat64); median and range of the repeats, "
             "which take turns over the FMUs, all measured in this one run. The ratio is "
             "against the trivial FMU of the same exporter (pythonfmu for FMI 2, pythonfmu3 "
             "for FMI 3) with its one output read.",
             "", "| FMU | method | outputs read | per step (median) | range | / trivial |",
             "|---|---|---:|---:|---:|---:|"]
    with tempfile.TemporaryDirectory() as tmp:
        script = Path(tmp) / "trivial_bench.py"
        script.write_text(TRIVIAL)
        trivial = Path(FmuBuilder.build_FMU(script, dest=tmp))
        script3 = Path(tmp) / "trivial_bench3.py"
        script3.write_text(TRIVIAL3)
        trivial3 = Path(FmuBuilder3.build_FMU(script3, dest=Path(tmp) / "t3"))
        heli3 = build_fmu("helicopter_tail", Path(tmp) / "heli3.fmu", fmi=3)
        heli = build_fmu("helicopter_tail", Path(tmp) / "heli.fmu")
        ecc = build_fmu(scene_file("eccentric_helical"), Path(tmp) / "ecc.fmu")
        h_heli = 1 / (16 * heli.spec["mesh_frequency"])
        h_ecc = 1 / (16 * ecc.spec["mesh_frequency"])

        def outs(spec: dict[str, object]) -> list[str]:
            return [v["name"] for v in spec["variables"]  # type: ignore[attr-defined]
                    if v["causality"] == "output"]
        # (name, method, fmu, outputs, step, values)
        cases: list[tuple[str, str, Path, list[str], float, dict[str, object] | None]] = [
            ("trivial pythonfmu", "-", trivial, ["y"], 1e-5, None),
            ("trivial pythonfmu (y read 6 times)", "-", trivial, ["y"] * 6, 1e-5, None)]
        for method in ("exact", "LSODA", "DOP853"):
            cases.append(("helicopter_tail", method, heli.path, outs(heli.spec), h_heli,
                          {"solver.method": method}))
        cases.append(("eccentric_helical", "DOP853", ecc.path, outs(ecc.spec), h_ecc, None))
        cases.append(("trivial pythonfmu3 (FMI 3)", "-", trivial3, ["y"], 1e-5, None))
        cases.append(("trivial pythonfmu3 (y read 6 times)", "-", trivial3, ["y"] * 6, 1e-5,
                      None))
        for method in ("exact", "LSODA"):
            cases.append(("helicopter_tail FMI 3", method, heli3.path, outs(heli3.spec), h_heli,
                          {"solver.method": method}))
        dirs = {c[2]: extracted(c[2]) for c in cases}
        runs: list[list[float]] = [[] for _ in cases]
        for _ in range(repeats):
            for case, got in zip(cases, runs, strict=True):
                _, _, fmu, names, h, values = case
                got.append(_per_step_us(fmu, dirs[fmu].name, names, h, n, values))
        for d in dirs.values():
            d.cleanup()
    floor = statistics.median(runs[0])
    for (name, method, _, names, _, _), got in zip(cases, runs, strict=True):
        if name == "trivial pythonfmu3 (FMI 3)":
            floor = statistics.median(got)  # the FMI 3 rows against the pythonfmu3 floor
        med = statistics.median(got)
        lines.append(f"| {name} | {method} | {len(names)} | {med:.1f} us | {min(got):.1f}-"
                     f"{max(got):.1f} us | {med / floor:.1f}x |")
    text = "\n".join(lines) + "\n"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text)
    print(text)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", type=Path, default=None,
                    help="report file (default benchmarks/out/, git-ignored)")
    ap.add_argument("--record", action="store_true",
                    help="write the recorded results in benchmarks/results/")
    ap.add_argument("--per-step", action="store_true",
                    help="per-step cost against a trivial pythonfmu FMU only")
    args = ap.parse_args()
    results = ROOT / "benchmarks" / ("results" if args.record else "out")
    results.mkdir(parents=True, exist_ok=True)
    if args.per_step:
        per_step(args.repeats, args.out or results / "fmu_per_step.md")
        return
    args.out = args.out or results / "fmu.md"
    lines = [
        "# FMU co-simulation: overhead and agreement",
        "",
        f"Command: `python benchmarks/bench_fmu.py --repeats {args.repeats}`  ",
        f"Machine: {platform.machine()}, Python {platform.python_version()} (2 shared cores; "
        "times are medians and vary with the load of the machine)",
        "",
        "## Overhead per communication step (FMU through fmpy against a direct solve)",
        "",
        "| scene | method | steps per mesh period | steps | direct | stepper (Python) | "
        "FMU (fmpy) | fresh solve_ivp per step | overhead per step | FMI layer per step |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    agree = [
        "## Difference against solve_ivp as the communication step shrinks",
        "",
        "| scene | FMU method | reference | rtol | steps per mesh period | FMU run | "
        "reference run | max diff DTE / RMS | RMS diff DTE / RMS | max diff force / RMS |",
        "|---|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    with tempfile.TemporaryDirectory() as tmp:
        for name, periods in CASES:
            fmu = build_fmu(scene_file(name), Path(tmp) / f"{name}.fmu").path
            lines += overhead(name, periods, fmu, args.repeats)
            agree += agreement(name, periods, fmu)
    text = "\n".join(lines + [""] + agree) + "\n"
    if args.record:
        args.out = Path(__file__).resolve().parent / "results" / "fmu.md"
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text)
    print(text)


if __name__ == "__main__":
    main()
