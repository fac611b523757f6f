"""What bifurcation.png of ``gear-dyn response`` costs: the orbits' stroboscopic samples, and
the brute-force diagram of ``--diagram N``, against the continuation itself, in one run.

Run:  python benchmarks/bench_response_diagram.py [--repeats 3] [--out DIR] [--record]

On ``helicopter_tail_backlash`` (packaged), pinion speeds 9500..17000 rpm (the period-1 branch,
its two period doublings and the period-2 branch between them), interleaved per repeat:

1. ``continue_orbits`` (``doublings=1``, as the command runs it): wall time and n-period maps;
2. ``branch_samples`` of that branch: the extra runs for bifurcation.png (one run of n-1 mesh
   periods per point of a period-n branch, n > 1; none for period 1);
3. ``bifurcation_scene`` over N = 32 and 128 speeds, up and down, serially (the default
   ``DiagramOptions``: 200 settling periods, 64 samples, periods confirmed by shooting): the
   cost of ``--diagram N``, per speed and direction.

The model (scene plan, pint) is built before timing. Writes ``response_diagram.md`` into
``--out`` (default ``benchmarks/out/``); ``--record`` writes into ``benchmarks/results/``.
"""

from __future__ import annotations

import math
import os
import platform

import numpy as np
from _timing import bench_args, output_dir, spread, timed  # noqa: E402  (benchmarks/ is on sys.path)

from gear_dyn.analysis.continuation import branch_samples, continue_orbits
from gear_dyn.scene import load_scene
from gear_dyn.scene.bifurcation import bifurcation_scene
from gear_dyn.scene.sweep import SceneModels

RPM = 2 * math.pi / 60
LO, HI = 9500.0 * RPM, 17000.0 * RPM
SIZES = (32, 128)


def main(argv: list[str] | None = None) -> int:
    args = bench_args(__doc__.splitlines()[0], argv)
    scene = load_scene("helicopter_tail_backlash")
    family = SceneModels.of(scene)
    family(LO)  # build the scene's model once, outside the timing
    t_branch: list[float] = []
    t_samples: list[float] = []
    t_diag: dict[int, list[float]] = {n: [] for n in SIZES}
    br = strobe = None
    for _ in range(args.repeats):
        tb, br = timed(lambda: continue_orbits(family, LO, HI, doublings=1))
        ts, strobe = timed(lambda b=br: branch_samples(b, family))
        t_branch.append(tb)
        t_samples.append(ts)
        for n in SIZES:
            td, _d = timed(lambda n=n: bifurcation_scene(scene, np.linspace(LO, HI, n),
                                                         si=True))
            t_diag[n].append(td)
    assert br is not None and strobe is not None
    points = sum(len(b.points) for b in br.walk())
    per_speed = [t / (2 * n) * 1e3 for n in SIZES for t in t_diag[n]]
    ratio = [t_diag[SIZES[-1]][i] / t_branch[i] for i in range(args.repeats)]
    lines = [
        "# bifurcation.png of gear-dyn response: cost", "",
        f"Produced by `python benchmarks/bench_response_diagram.py --repeats {args.repeats}` on "
        f"{platform.machine()} (Python {platform.python_version()}); {args.repeats} "
        "interleaved runs, median (min..max) (shared 2-core machine: other jobs ran beside "
        f"it; load average {os.getloadavg()[0]:.1f} at the end).", "",
        f"Scene `helicopter_tail_backlash` (packaged), pinion speed 9500..17000 rpm: "
        f"{len(br.walk())} branches (period-1 and the period-2 branch between its two "
        f"doublings), {points} points.", "",
        "| path | wall time (s) | runs of the flow |",
        "|---|---|---|",
        f"| continue_orbits, doublings=1 (what `gear-dyn response` runs) | {spread(t_branch)} "
        f"| {sum(b.n_maps for b in br.walk())} n-period maps |",
        f"| branch_samples: the orbits' stroboscopic samples for bifurcation.png | "
        f"{spread(t_samples)} | {strobe.n_maps} (one per period-2 orbit: points and "
        "located folds) |",
        *(f"| bifurcation_scene, {n} speeds up and down, serial (`--diagram {n}`) | "
          f"{spread(t_diag[n])} | {2 * n} settle-and-sample runs |" for n in SIZES),
        "", f"`--diagram N` costs {spread(per_speed, fmt='.2g')} ms per speed and direction "
        f"(200 settling periods, 64 samples, the period confirmed by shooting; exact flow), "
        f"{spread(ratio, unit='x')} the continuation at N = 128 (ratio within each repeat). "
        "The continued orbits' samples cost "
        f"{spread([a / b for a, b in zip(t_samples, t_branch, strict=True)], unit='x')} the "
        "continuation.",
    ]
    out_dir = output_dir(args)
    (out_dir / "response_diagram.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
