"""``gear-dyn response SCENE --speeds LO:HI --out DIR``: the response curve by continuation.

A thin layer over :func:`gear_dyn.analysis.continuation.continue_orbits` with the scene's model
factory (:class:`gear_dyn.scene.sweep.SceneModels`); docs/response.md describes the method.
"""

from __future__ import annotations

import argparse
from typing import Any

from gear_dyn.cli.progress import Stages, add_quiet_flag
from gear_dyn.cli.run import add_scene_and_out
from gear_dyn.cli.sweep import add_parallel_flags, dask_executor
from gear_dyn.errors import InputError


def register(sub: Any) -> None:
    p = sub.add_parser(
        "response", help="response curve by continuation: stable and unstable periodic orbits, "
        "folds, period doubling",
        description="Follow the periodic orbits of SCENE (single-DOF model) over pinion speeds "
        "LO..HI by pseudo-arclength continuation, through folds, and write into DIR: "
        "response.png (RMS DTE against speed: stable solid, unstable dashed, folds and period "
        "doublings marked with their speeds), bifurcation.png (the orbits' stroboscopic "
        "samples, one per mesh period, against speed; with --diagram a brute-force diagram "
        "behind them), branch.csv (every point with its Floquet "
        "multipliers, stability, Liouville check and contact pattern) and branch.json (the "
        "located folds, period doublings and grazing points, and every point). DIR is replaced "
        "as a whole only on success.",
        epilog="example: gear-dyn response helicopter_tail_backlash --speeds '3000 rpm:9500 rpm' "
        "--out resp",
    )
    add_scene_and_out(p)
    p.add_argument("--speeds", required=True, metavar="LO:HI",
                   help="pinion speed range with units, e.g. '3000 rpm:9500 rpm' (the branch "
                   "starts at LO)")
    p.add_argument("--doublings", type=int, default=1,
                   help="levels of period doubling to switch branches at (default 1: the "
                   "period-2 branches; 0: none)")
    p.add_argument("--torques", metavar="LO:HI:N", default=None,
                   help="also the jump map: folds followed over N pinion torques LO..HI with "
                   "units, e.g. '100 N*m:600 N*m:11' (writes jump_map.png, fold_curve.csv "
                   "and fold_map.json)")
    p.add_argument("--max-points", type=int, default=2000, help="points per branch (default "
                   "2000)")
    p.add_argument("--sweep", type=int, default=0, metavar="N",
                   help="also sweep N speeds over the range, up and down, and draw the sweep's "
                   "periodic points and its jumps over the branch (default 0: no sweep)")
    p.add_argument("--diagram", type=int, default=0, metavar="N",
                   help="also the brute-force bifurcation diagram over N speeds, up and down "
                   "(gear-dyn bifurcation's defaults: 200 mesh periods settled, 64 samples), "
                   "drawn in grey dots behind the orbits on bifurcation.png (default 0: none)")
    add_parallel_flags(p, what="the sweep and the diagram")
    add_quiet_flag(p)
    p.set_defaults(func=run)


def _speeds(text: str) -> tuple[float, float]:
    """``LO:HI`` in rad/s (the units rules of ``--speeds`` of ``gear-dyn sweep``)."""
    from gear_dyn.scene.operating import parse_speed_range

    parts = text.split(":")
    if len(parts) != 2:
        raise InputError(f"--speeds {text!r}: expected LO:HI, e.g. '3000 rpm:9500 rpm'")
    lo, hi = (float(v) for v in parse_speed_range(f"{parts[0]}:{parts[1]}:2"))
    if lo == hi:
        raise InputError(f"--speeds {text!r}: LO and HI are the same speed")
    return lo, hi


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from gear_dyn.analysis.continuation import (
        ContinuationSettings,
        branch_samples,
        continue_orbits,
    )
    from gear_dyn.analysis.sweep import RPM
    from gear_dyn.io import save_figure, staged_output, write_json
    from gear_dyn.plots.bifurcation import plot_branch_samples
    from gear_dyn.plots.continuation import plot_branch
    from gear_dyn.scene import load_scene
    from gear_dyn.scene.sweep import SceneModels

    scene = load_scene(args.scene)
    lo, hi = _speeds(args.speeds)
    torques = None
    if args.torques is not None:
        from gear_dyn.cli.jump_map import parse_torques, write_jump_map

        torques = parse_torques(args.torques)
    settings = ContinuationSettings(max_points=args.max_points)
    if args.sweep == 1 or not 0 <= args.sweep <= 100_000:
        raise InputError(f"--sweep {args.sweep}: valid range 2..100000 speeds, or 0 (no sweep)")
    if args.diagram == 1 or not 0 <= args.diagram <= 100_000:
        raise InputError(f"--diagram {args.diagram}: valid range 2..100000 speeds, or 0 (no "
                         "diagram)")
    if args.workers is not None and not 1 <= args.workers <= 4096:
        raise InputError(f"--workers = {args.workers}: valid range 1..4096 processes")
    stages = ["continue the speed branch",
              "write response.png, bifurcation.png, branch.csv/json"]
    if args.diagram:
        stages.insert(1, f"bifurcation diagram over {args.diagram} speeds up and down")
    if args.sweep:
        stages.insert(1, f"sweep {args.sweep} speeds up and down")
    if torques is not None:
        stages.append(f"jump map over {len(torques)} torques")
    family = SceneModels.of(scene)
    with dask_executor(args.dask if args.sweep or args.diagram else None) as executor:
        where = {"workers": args.workers, "executor": executor}
        with Stages(stages, args.quiet) as st:
            branch = continue_orbits(family, lo, hi, settings=settings,
                                     doublings=args.doublings)
            swept = diagram = None
            if args.sweep:
                from gear_dyn.scene.sweep import sweep_scene

                st.next()
                swept = sweep_scene(scene, np.linspace(lo, hi, args.sweep), si=True, **where)
            if args.diagram:
                from gear_dyn.scene.bifurcation import bifurcation_scene

                st.next()
                diagram = bifurcation_scene(scene, np.linspace(lo, hi, args.diagram), si=True,
                                            **where)
            st.next()
            strobe = branch_samples(branch, family, settings.rtol)
            with staged_output(args.out) as tmp:
                save_figure(plot_branch(branch, sweep=swept), tmp / "response.png", dpi=120)
                title = (f"{scene.name}: the continued orbits' states once per mesh period"
                         + (f"\ngrey: brute force at {args.diagram} speeds" if diagram else ""))
                save_figure(plot_branch_samples(strobe, diagram=diagram, title=title),
                            tmp / "bifurcation.png", dpi=120)
                branch.to_csv(tmp / "branch.csv")
                write_json(tmp / "branch.json", {"scene": scene.name, **branch.to_dict()})
                if torques is not None:
                    st.next()
                    fm = write_jump_map(scene, (lo, hi), torques, settings, tmp)
    for i, b in enumerate(branch.walk()):
        print(f"branch {i}: {b!r}")
        for x in b.bifurcations:
            if x.kind != "grazing":
                print(f"  {x.kind} at {x.parameter / RPM:.10g} rpm ({x.before} -> {x.after})")
    if torques is not None:
        print(repr(fm))
    print(f"wrote {args.out}/")
    return 0
