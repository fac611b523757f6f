"""The jump map (folds followed in speed and torque) on the packaged backlash scene: its cost
against one speed branch with detection on, measured in one run.

Run:  python benchmarks/bench_fold_map.py [--repeats 3] [--out DIR] [--record]

On ``helicopter_tail_backlash`` (packaged), pinion speeds 3000..9500 rpm, interleaved per
repeat:

1. ``fold_map`` over torques 200, 368.6 and 600 N m (default settings, 4 cusp bisections):
   wall time, speed branches followed (the requested torques plus the cusp bisections) and
   n-period maps;
2. ``continue_orbits`` at the scene torque (detection on, no doublings): one speed branch,
   the unit the fold map is made of.

The ratio (fold map time / one branch's time) per repeat says how many branches' worth of work
the map costs. The model (scene plan, pint) is built before timing. Writes ``fold_map.md`` into
``--out`` (default ``benchmarks/out/``); ``--record`` writes into ``benchmarks/results/``.
"""

from __future__ import annotations

import math
import os
import platform

from _timing import bench_args, output_dir, spread, timed  # noqa: E402  (benchmarks/ is on sys.path)

from gear_dyn.analysis.continuation import SpeedTorqueFamily, continue_orbits, fold_map
from gear_dyn.scene import load_scene
from gear_dyn.scene.sweep import SceneModels

RPM = 2 * math.pi / 60
LO, HI = 3000.0 * RPM, 9500.0 * RPM
TORQUES = [200.0, 368.6, 600.0]


def main(argv: list[str] | None = None) -> int:
    args = bench_args(__doc__.splitlines()[0], argv)
    scene = load_scene("helicopter_tail_backlash")
    speeds = SceneModels.of(scene)
    speeds(LO)  # build the scene's model once, outside the timing
    family = SpeedTorqueFamily(speeds, 368.6)
    t_map, t_branch, ratios = [], [], []
    fm = br = None
    for _ in range(args.repeats):
        tm, fm = timed(lambda: fold_map(family, (LO, HI), TORQUES, reference_torque=368.6))
        tb, br = timed(lambda: continue_orbits(speeds, LO, HI, doublings=0))
        t_map.append(tm)
        t_branch.append(tb)
        ratios.append(tm / tb)
    assert fm is not None and br is not None
    n_branches = fm.torques.size
    lines = [
        "# Jump map: folds in speed and torque, cost", "",
        f"Produced by `python benchmarks/bench_fold_map.py --repeats {args.repeats}` on "
        f"{platform.machine()} (Python {platform.python_version()}); {args.repeats} "
        "interleaved runs, median (min..max) (shared 2-core machine: other jobs ran beside "
        f"it; load average {os.getloadavg()[0]:.1f} at the end).", "",
        f"Scene `helicopter_tail_backlash` (packaged), pinion speed 3000..9500 rpm, torques "
        f"{', '.join(f'{t:g}' for t in TORQUES)} N m: {n_branches} speed branches (with the "
        f"cusp bisections), {len(fm.regions)} jump regions, {len(fm.cusps)} cusp"
        f"{'s' if len(fm.cusps) != 1 else ''}.", "",
        "| path | wall time (s) | n-period maps |",
        "|---|---|---|",
        f"| **fold_map**, {len(TORQUES)} torques | **{spread(t_map)}** | {fm.n_maps} |",
        f"| continue_orbits, one speed branch (detection on) | {spread(t_branch)} | "
        f"{br.n_maps} |",
        f"| ratio fold map / one branch | {spread(ratios, unit='x')} | "
        f"{fm.n_maps / br.n_maps:.3g}x |", "",
        "The map costs about one speed branch per torque it visits (requested and bisection "
        "torques); the maps count does not depend on the machine's load.",
    ]
    out_dir = output_dir(args)
    (out_dir / "fold_map.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
