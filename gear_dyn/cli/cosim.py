"""``gear-dyn cosim FILE.fmu [SCENE] --out DIR``: the FMU through fmpy against solve_ivp, with a
verdict (exit 3 on FAIL): the DTE difference within the FMU's and the reference's errors."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from gear_dyn.cli.progress import Stages, add_quiet_flag


def register(sub: Any) -> None:
    p = sub.add_parser(
        "cosim", help="co-simulate an FMU with fmpy and compare it with solve_ivp",
        description="Run FILE.fmu through fmpy at several communication steps and the same "
        "scene with solve_ivp, and write into DIR: overlay.png (FMU over solve_ivp, difference "
        "below), convergence.png (difference and run time against the step), steps.csv, "
        "timeseries.csv and summary.json. The verdict (exit 3 on FAIL): at every step the DTE "
        "difference is within the FMU's error (a native FMU's stated error, else gear_dyn's "
        "estimate for the solver the FMU runs) plus solve_ivp's estimated error. SCENE "
        "(optional) is the reference scene: a pythonfmu FMU gets its values set, a native FMU "
        "(geometry and tables fixed at build) runs as built; without SCENE the scene the FMU "
        "was built from runs.",
    )
    p.add_argument("fmu", type=Path, help="FMU built by `gear-dyn fmu build` (FMI 2.0, native "
                   "or pythonfmu)")
    p.add_argument("scene", nargs="?", type=Path, help="scene file (default: the FMU's own)")
    p.add_argument("--out", type=Path, required=True, help="output folder")
    p.add_argument("--step", type=float, action="append",
                   help="communication step in s (repeat for several; each an integer multiple "
                   "of the smallest). Default: the FMU's DefaultExperiment step x 8, 4, 2, 1")
    p.add_argument("--stop", type=float, help="end time in s (default: DefaultExperiment)")
    p.add_argument("--periods", type=int, help="end time in mesh periods (instead of --stop)")
    p.add_argument("--output", action="append",
                   help="FMU output to compare (repeatable; default dte and mesh_force)")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="set an FMU parameter for this check, e.g. damping.ratio=0.1 or "
                   "solver.method=DOP853 (a scene key: the reference uses the same value)")
    add_quiet_flag(p)
    p.set_defaults(func=run)


def _parse_set(items: list[str]) -> dict[str, Any]:
    from gear_dyn.errors import InputError

    out: dict[str, Any] = {}
    for item in items:
        name, sep, raw = item.partition("=")
        if not sep or not name:
            raise InputError(f"--set {item!r}: expected NAME=VALUE")
        value: Any = raw
        for conv in (int, float):
            try:
                value = conv(raw)
                break
            except ValueError:
                continue
        out[name.strip()] = value
    return out


def run(args: argparse.Namespace) -> int:
    with Stages(["read FMU and scene", "FMU (fmpy) and reference (solve_ivp)", "write"],
                args.quiet) as st:
        return _run(args, st)


def _run(args: argparse.Namespace, st: Stages) -> int:
    from gear_dyn.errors import InputError
    from gear_dyn.fmu.cosim import compare
    from gear_dyn.fmu.fmu_info import read_fmu
    from gear_dyn.io import save_figure, staged_output, write_csv, write_json
    from gear_dyn.plots.cosim import convergence_figure, overlay_figure
    from gear_dyn.scene import load_scene

    spec = read_fmu(args.fmu).spec
    scene = load_scene(args.scene) if args.scene is not None else None
    if args.stop is not None and args.periods is not None:
        raise InputError("--stop and --periods: give one of them")
    stop = args.stop
    if args.periods is not None:
        if args.periods < 1:
            raise InputError(f"--periods = {args.periods}: valid range >= 1")
        stop = args.periods / spec["mesh_frequency"]
    outputs = tuple(args.output) if args.output else ("dte", "mesh_force")
    st.next()
    report = compare(args.fmu, scene, steps=args.step, stop_time=stop, outputs=outputs,
                     fmu_values=_parse_set(args.set))
    steps = [s.as_dict() for s in report.steps]
    rows = {key: [d[key] for d in steps]
            for key in ("step_s", "n_steps", "fmu_run_time_s", "fmu_time_per_step_s")}
    for name in report.outputs:
        rows[f"max_diff_{name}"] = [d["max_diff"][name] for d in steps]
        rows[f"rms_diff_{name}"] = [d["rms_diff"][name] for d in steps]
    series: dict[str, Any] = {"t_s": report.t}
    for i, name in enumerate(report.outputs):
        series[f"{name}_fmu"] = report.fmu_y[i]
        series[f"{name}_solve_ivp"] = report.ref_y[i]
    st.next()
    with staged_output(args.out) as tmp:
        write_json(tmp / "summary.json", report.as_dict())
        write_csv(tmp / "steps.csv", rows)
        write_csv(tmp / "timeseries.csv", series)
        save_figure(overlay_figure(report), tmp / "overlay.png", dpi=110)
        save_figure(convergence_figure(report), tmp / "convergence.png", dpi=110)
    print(f"{report.scene_name}: FMU ({report.fmu_method}) against solve_ivp "
          f"{report.reference_method} (rtol {report.rtol:g}), {report.stop_time:.4g} s; "
          f"solve_ivp {report.reference_run_time_s:.3g} s")
    for s in report.steps:
        diffs = ", ".join(f"{n} max {s.max_diff[n]:.3g} RMS {s.rms_diff[n]:.3g}"
                          for n in report.outputs)
        print(f"  step {s.step:.4g} s ({s.n_steps} steps): FMU {s.fmu_run_time_s:.3g} s; "
              f"{diffs}")
    b = report.bounds
    if b is not None:
        print(f"  allowed DTE difference {b.total:.3g} m = FMU {b.fmu:.3g} m ({b.fmu_basis}) "
              f"+ solve_ivp {b.reference:.3g} m ({b.reference_basis})")
        if not b.conclusive:
            print("  note: the reference's error is not below the FMU's: a PASS does not "
                  "confirm the FMU's error")
    print(f"verdict: {'PASS' if report.passed else 'FAIL'}")
    print(f"wrote {args.out}/")
    return 0 if report.passed else 3
