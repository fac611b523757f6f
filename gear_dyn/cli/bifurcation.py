"""``gear-dyn bifurcation SCENE --speeds START:STOP:N --out DIR``: a bifurcation diagram."""

from __future__ import annotations

import argparse
import itertools
from typing import Any

from gear_dyn.cli.progress import add_quiet_flag, counter
from gear_dyn.cli.run import add_scene_and_out, add_solver_flags, overrides
from gear_dyn.cli.sweep import add_parallel_flags, dask_executor


def register(sub: Any) -> None:
    p = sub.add_parser(
        "bifurcation", help="bifurcation diagram: stroboscopic samples against speed, up and down",
        description="At N pinion speeds from START to STOP (each speed continuing from the "
        "previous one's final state, up and down), settle, sample the state once per mesh "
        "period and write into DIR: bifurcation.png (the samples against speed), samples.csv "
        "(every sample, SI units) and bifurcation.json (per speed: the period confirmed by "
        "shooting, with --classify the motion's label and Lyapunov exponent). DIR is replaced "
        "as a whole only on success. Single-DOF scenes.",
        epilog="example: gear-dyn bifurcation scene.toml --speeds '14000 rpm:18000 rpm:81' "
        "--out bif --classify",
    )
    add_scene_and_out(p)
    p.add_argument("--speeds", required=True, metavar="START:STOP:N",
                   help="pinion speeds: START and STOP with their units ('500 rpm'); N points")
    p.add_argument("--settle", type=int, default=200,
                   help="mesh periods run at each speed before sampling (default 200)")
    p.add_argument("--samples", type=int, default=64,
                   help="samples per speed, one per mesh period (default 64, at least 32)")
    p.add_argument("--classify", action="store_true",
                   help="where no orbit of 1..16 mesh periods is found, tell quasi-periodic "
                   "from chaotic motion by the largest Lyapunov exponent (slower)")
    p.add_argument("--direction", choices=("both", "up", "down"), default="both",
                   help="sweep directions (default both)")
    p.add_argument("--state", choices=("x", "v"), default="x",
                   help="state drawn: x (mesh deflection, default) or v (its rate)")
    add_parallel_flags(p, note=", the up and down chains side by side")
    p.add_argument("--block", type=int, default=None, help="speeds per block (default 8)")
    add_quiet_flag(p, "--no-progress")
    add_solver_flags(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from gear_dyn.analysis.motion import DiagramOptions
    from gear_dyn.io import save_figure, staged_output, write_json
    from gear_dyn.plots.bifurcation import plot_bifurcation
    from gear_dyn.scene import load_scene
    from gear_dyn.scene.bifurcation import bifurcation_scene
    from gear_dyn.scene.operating import parse_speed_range

    scene = load_scene(args.scene)
    speeds = parse_speed_range(args.speeds)
    solver = overrides(args)
    opts = DiagramOptions(settle=args.settle, samples=args.samples, classify=args.classify,
                          **({"rtol": solver["rtol"]} if "rtol" in solver else {}))
    with dask_executor(args.dask) as executor:
        diagram = bifurcation_scene(
            scene, speeds, si=True, options=opts, direction=args.direction,
            workers=args.workers, executor=executor, block=args.block,
            progress=counter("speed", args.quiet), **solver)
    summary = diagram.to_dict()
    with staged_output(args.out) as tmp:
        save_figure(plot_bifurcation(diagram, state=args.state), tmp / "bifurcation.png",
                    dpi=110)
        diagram.to_csv(tmp / "samples.csv")
        write_json(tmp / "bifurcation.json", summary)
    _print_summary(diagram)
    print(f"wrote {args.out}/")
    return 0


def _print_summary(diagram: Any) -> None:
    """Per direction: speed ranges (rpm) of each period or label, in sweep order."""
    from gear_dyn.analysis.motion.diagram import RPM

    print(repr(diagram))
    for c in diagram.curves:
        names = [lab.split(",")[0] if lab else (f"period-{p}" if p else "no orbit <= 16")
                 for lab, p in zip(c.label, c.period, strict=True)]
        parts = []
        for name, run in itertools.groupby(zip(names, c.speed / RPM, strict=True),
                                           key=lambda item: item[0]):
            rpm = [r for _, r in run]
            span = f"{rpm[0]:.0f}" if len(rpm) == 1 else f"{rpm[0]:.0f}-{rpm[-1]:.0f}"
            parts.append(f"{name} {span} rpm")
        print(f"  {c.direction}: " + "; ".join(parts))
