"""``gear-dyn bench SCENE --out DIR``: error against run time for every solver and tolerance."""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import asdict
from typing import Any

from gear_dyn.cli.progress import add_quiet_flag, counter
from gear_dyn.cli.run import add_budget_flag, add_scene_and_out, overrides
from gear_dyn.errors import InputError

TARGETS = (1e-4, 1e-6, 1e-8)


def register(sub: Any) -> None:
    p = sub.add_parser(
        "bench", help="work-precision benchmark of the solvers on a scene",
        description="Run SCENE with every solve_ivp method (RK45, DOP853, Radau, BDF, LSODA; "
        "restarted at each switching instant) over a range of rtol, the exact propagator where "
        "it applies and RK45 once over the whole span (the hand-written baseline). Writes into "
        "DIR: work_precision.png (error vs time, log-log), bench.csv, bench.md (table and the "
        "recommended method per target error) and bench.json. Errors are max and RMS of "
        "|x - x_ref| relative to the static deflection; times are medians of repeats.",
    )
    add_scene_and_out(p)
    p.add_argument("--periods", type=int, help="mesh periods to simulate (default: the scene's)")
    p.add_argument("--methods", default="RK45,DOP853,Radau,BDF,LSODA",
                   help="comma-separated solve_ivp methods (default: all five)")
    p.add_argument("--rtols", default="1e-4,1e-6,1e-8,1e-10",
                   help="comma-separated relative tolerances (default 1e-4,1e-6,1e-8,1e-10)")
    p.add_argument("--repeats", type=int, default=3, help="runs per case, median reported")
    p.add_argument("--budget", type=float, default=20.0,
                   help="seconds: a slower case is run once and tighter rtols of its method "
                   "are skipped (default 20)")
    p.add_argument("--target", type=float, default=1e-6,
                   help="target max error for the headline recommendation (default 1e-6)")
    add_budget_flag(p)
    add_quiet_flag(p)
    p.set_defaults(func=run)


def _floats(text: str, name: str) -> list[float]:
    try:
        vals = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise InputError(f"--{name} = {text!r}: expected comma-separated numbers") from None
    if not vals or any(not (1e-13 <= v <= 1e-2) for v in vals):
        raise InputError(f"--{name} = {text!r}: each value must be in 1e-13..1e-2")
    return vals


def run(args: argparse.Namespace) -> int:
    from gear_dyn.analysis.bench import COLUMNS, markdown_table, run_bench, summary_dict
    from gear_dyn.io import save_figure, staged_output, write_json, write_rows, write_text
    from gear_dyn.plots.bench import plot_work_precision
    from gear_dyn.scene import build_plan, load_scene

    methods = [m.strip() for m in args.methods.split(",") if m.strip()]
    if not methods:
        raise InputError(f"--methods = {args.methods!r}: give at least one solve_ivp method")
    if not (math.isfinite(args.budget) and args.budget > 0):
        raise InputError(f"--budget = {args.budget!r} s: valid range > 0 s")
    if args.repeats < 1:
        raise InputError(f"--repeats = {args.repeats}: valid range >= 1")
    rtols = _floats(args.rtols, "rtols")
    ov = overrides(args)  # --periods, --max-nfev
    if not (0 < args.target < 1):
        raise InputError(f"--target = {args.target!r}: valid range 0..1 (relative error)")
    scene = load_scene(args.scene)
    plan = build_plan(scene, **ov)
    show = counter("case", args.quiet)
    report = run_bench(plan.model, plan.t_end, name=scene.name, methods=methods, rtols=rtols,
                       repeats=args.repeats, samples_per_period=plan.settings.samples_per_period,
                       budget_s=args.budget, progress=show,
                       max_nfev=plan.settings.max_nfev)
    targets = tuple(sorted({*TARGETS, args.target}, reverse=True))
    md = markdown_table(report, targets)
    rows = [{k: f"{v:.6g}" if isinstance(v, float) else v for k, v in asdict(c).items()}
            for c in report.cases]
    cmd = "gear-dyn bench " + " ".join(sys.argv[2:]) if len(sys.argv) > 2 else "gear-dyn bench"
    with staged_output(args.out) as tmp:
        write_text(tmp / "bench.md", md + f"\nProduced by `{cmd}`.\n")
        write_rows(tmp / "bench.csv", rows, empty=COLUMNS)
        write_json(tmp / "bench.json", summary_dict(report, targets))
        fig = plot_work_precision(report, targets=(args.target,))
        save_figure(fig, tmp / "work_precision.png", dpi=110)
    best = report.recommend(args.target)
    if best is None:
        print(f"{scene.name}: no case reached max error {args.target:.0e}")
    else:
        rtol = "" if best.mode == "exact" else f" rtol {best.rtol:.0e}"
        print(f"{scene.name}: for max error <= {args.target:.0e} use {best.label}{rtol} "
              f"({best.run_time_s:.3g} s, error {best.err_max:.2g})")
    print(f"wrote {args.out}/")
    return 0
