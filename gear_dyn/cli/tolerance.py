"""``gear-dyn tolerance SCENE --samples N --speeds START:STOP:N --out DIR``: a Monte-Carlo
tolerance study over random manufacturing deviations, with CSV, JSON and a figure."""

from __future__ import annotations

import argparse
from typing import Any

from gear_dyn.cli.run import add_scene_and_out
from gear_dyn.cli.sweep import add_parallel_flags, dask_executor


def register(sub: Any) -> None:
    p = sub.add_parser(
        "tolerance", help="Monte-Carlo tolerance study: spread of peak force, K_dyn and RMS DTE "
        "over random deviations within an ISO 1328-1 grade",
        description="Draw N random sets of pitch and profile deviations within the grade "
        "(ISO 1328-1:2013; sample i from the seed pair [SEED, i]) and evaluate SCENE (a linear "
        "single-DOF scene with piecewise-constant stiffness) at every speed, exactly over the "
        "hunting period. Writes into DIR: tolerance.png (median and 5-95 % band against speed, "
        "the response without deviations and ISO 6336-1 K_v at the same grade), tolerance.csv "
        "(one row per speed) and tolerance.json (every figure's band with its Monte-Carlo "
        "standard error, the seeds, definitions). DIR is replaced as a whole only on success.",
        epilog="example: gear-dyn tolerance helicopter_tail --samples 200 --speeds "
        "'1000 rpm:9000 rpm:100' --grade 6 --out tol",
    )
    add_scene_and_out(p)
    p.add_argument("--samples", type=int, default=100, metavar="N",
                   help="Monte-Carlo samples (default 100)")
    p.add_argument("--speeds", required=True, metavar="START:STOP:N",
                   help="pinion speeds: START and STOP with their units; N points")
    p.add_argument("--grade", type=int, default=None,
                   help="ISO 1328-1:2013 grade 1..11 (default: the scene's [deviations], "
                   "else [iso] accuracy_grade)")
    p.add_argument("--seed", type=int, default=None,
                   help="base seed (default: [deviations] seed, else 1)")
    p.add_argument("--samples-per-period", type=int, default=None,
                   help="output samples per mesh period (default the scene's [solver])")
    add_parallel_flags(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from gear_dyn.io import save_figure, staged_output, write_json
    from gear_dyn.plots.tolerance import plot_tolerance
    from gear_dyn.scene import load_scene
    from gear_dyn.scene.iso import like_for_like_note, scene_iso_kv
    from gear_dyn.scene.operating import parse_speed_range
    from gear_dyn.scene.tolerance import tolerance_scene

    scene = load_scene(args.scene)
    speeds = parse_speed_range(args.speeds)
    with dask_executor(args.dask) as executor:
        res = tolerance_scene(scene, speeds, si=True, samples=args.samples, seed=args.seed,
                              grade=args.grade, samples_per_period=args.samples_per_period,
                              workers=args.workers, executor=executor)
    summary = res.to_dict()
    kv = None
    if scene.get("operating")["torque"] > 0:
        study_scene = _with_grade(scene, args.grade)
        kv = scene_iso_kv(study_scene, res.speeds)[0].k_v
        summary["iso_6336_kv"] = {"k_v": np.asarray(kv).tolist(),
                                  "like_for_like": like_for_like_note(study_scene)}
    extra = {} if kv is None else {"iso_6336_kv": np.asarray(kv, dtype=float)}
    with staged_output(args.out) as tmp:
        res.to_csv(tmp / "tolerance.csv", extra)
        write_json(tmp / "tolerance.json", summary)
        save_figure(plot_tolerance(res, iso_kv=kv), tmp / "tolerance.png", dpi=110)
    k = res.stats("k_dyn")
    i = int(np.nanargmax(k["median"]))
    rpm = res.speeds * 60 / (2 * np.pi)
    print(f"{res.name}: {res.n_samples} samples x {res.speeds.size} speeds in "
          f"{res.run_time_s:.3g} s ({res.executor}); exact over the hunting period "
          f"({res.hunting_period} mesh cycles)")
    print(f"  largest median K_dyn {k['median'][i]:.4f} +- {k['median_stderr'][i]:.2g} "
          f"(1 s.e.) at {rpm[i]:.0f} rpm; 5-95 %: {k['p05'][i]:.4f}-{k['p95'][i]:.4f}; "
          f"without deviations {res.baseline['k_dyn'][i]:.4f}"
          + ("" if kv is None else f"; ISO 6336-1 K_v {np.asarray(kv)[i]:.4f}"))
    for note in res.notes:
        print(f"  note: {note}")
    print(f"wrote {args.out}/")
    return 0


def _with_grade(scene: Any, grade: int | None) -> Any:
    """The scene with the study's deviations as its ``[deviations]`` table (K_v alike)."""
    from gear_dyn.scene import parse_scene

    dev = dict(scene.tables.get("deviations", {}), pattern="random")
    if grade is not None:
        dev = {"grade": grade, "pattern": "random"}
    tables = {k: {kk: vv for kk, vv in v.items() if vv is not None}
              for k, v in {**scene.tables, "deviations": dev}.items()}
    return parse_scene(tables, source=scene.source, si=True)
