"""Continuation of periodic orbits on the packaged backlash scene: time per point, against the
natural-parameter sweep and brute-force integration to the same accuracy.

Run:  python benchmarks/bench_continuation.py [--repeats 3] [--out DIR] [--record]

On ``helicopter_tail_backlash`` (packaged), pinion speeds 3000..9500 rpm, measured in one run,
interleaved per repeat:

1. ``continue_orbits`` (period-1, exact route, default settings): the whole response curve,
   stable and unstable, with detection on (folds, period doublings and grazing points located
   to ``locate_tol``, 1e-10 relative in speed: the default, and the issue's target) and off
   (the continuation alone); time per point = run time / points;
2. the natural-parameter sweep (``sweep_scene``, method ``steady``, up only) over as many
   speeds as the continuation has points: time per speed (it follows the stable orbits only,
   jumping at folds);
3. brute force: at every 5th of those speeds, iterate the exact flow one mesh period at a
   time from the previous speed's state until the orbit closes to the continuation's
   tolerance (``|P(y) - y| <= newton.tolerance`` in scaled units, the continuation's accuracy);
   time per speed, with the mesh periods it needed.

The model (scene plan, pint) is built before timing. Writes ``continuation.md`` into ``--out``
(default ``benchmarks/out/``); ``--record`` writes into ``benchmarks/results/``. Sections of
other measurements in that file (from a line ``## ...`` on) are kept after this one.
"""

from __future__ import annotations

import math
import os
import platform
import statistics
import time
from typing import Any

import numpy as np
from _timing import bench_args, output_dir, spread, timed  # noqa: E402  (benchmarks/ is on sys.path)

from gear_dyn.analysis.continuation import ContinuationSettings, continue_orbits
from gear_dyn.analysis.continuation.orbit import map_only
from gear_dyn.scene import load_scene
from gear_dyn.scene.sweep import SceneModels, sweep_scene

RPM = 2 * math.pi / 60
LO, HI = 3000.0, 9500.0
MAX_PERIODS = 20000
#: the speed target: CPU time per point, detection on (ms)
TARGET_MS = 1.0
KINDS = {"fold": "folds", "period_doubling": "period doublings", "grazing": "grazing points"}


def brute_force(factory: Any, speeds: np.ndarray, tol: float) -> tuple[float, list[int]]:
    """Iterate the one-period map at each speed until the orbit closes to ``tol`` (scaled)."""
    y = factory(speeds[0]).initial_state()
    periods = []
    t0 = time.perf_counter()
    for w in speeds:
        model = factory(float(w))
        scale = model.state_scale
        n = 0
        while n < MAX_PERIODS:
            y_new = map_only(model, y, 1, "exact", 1e-10)
            n += 1
            done = float(np.max(np.abs(y_new - y) / scale)) <= tol
            y = y_new
            if done:
                break
        periods.append(n)
    return time.perf_counter() - t0, periods


def main(argv: list[str] | None = None) -> int:
    args = bench_args(__doc__.splitlines()[0], argv)
    scene = load_scene("helicopter_tail_backlash")
    factory = SceneModels.of(scene)
    factory(LO * RPM)  # build the plan (pint, scene) before timing
    settings = ContinuationSettings()
    quiet = ContinuationSettings(detect=False)
    load_start = os.getloadavg()[0]
    t_on, t_off, t_sweep, t_brute = [], [], [], []
    cpu_on: list[float] = []
    cpu_off: list[float] = []
    n_pts = n_special = 0
    kinds = ""
    worst_error = 0.0
    maps_off = maps_on = math.nan
    periods: list[int] = []
    worst_residual = 0.0
    iters = math.nan
    for _ in range(args.repeats):
        c0 = time.process_time()
        dt, br = timed(lambda: continue_orbits(factory, LO * RPM, HI * RPM, settings=quiet))
        t_off.append(dt / len(br))
        cpu_off.append((time.process_time() - c0) / len(br))
        n_pts = len(br)
        maps_off = br.n_maps / len(br)
        worst_residual = max(p.residual for p in br.points)
        iters = statistics.mean(p.iterations for p in br.points[1:])
        c0 = time.process_time()
        dt, brd = timed(lambda: continue_orbits(factory, LO * RPM, HI * RPM, settings=settings))
        t_on.append(dt / len(brd))
        cpu_on.append((time.process_time() - c0) / len(brd))
        n_special = len(brd.bifurcations)
        kinds = ", ".join(f"{len(brd.of_kind(k))} {name}" for k, name in KINDS.items()
                          if brd.of_kind(k))
        worst_error = max(b.parameter_error / b.parameter for b in brd.bifurcations)
        maps_on = brd.n_maps / len(brd)
        speeds = np.linspace(LO, HI, n_pts) * RPM
        dt, _sw = timed(lambda s=speeds: sweep_scene(scene, s, si=True, direction="up"))
        t_sweep.append(dt / n_pts)
        dt, periods = brute_force(factory, speeds[::5], settings.newton.tolerance)
        t_brute.append(dt / len(periods))
    ms = [1e3 * x for x in t_off]
    ms_on = [1e3 * x for x in t_on]
    ratios = [a / b for a, b in zip(t_on, t_off, strict=True)]
    lines = [
        "# Continuation of periodic orbits: time per point", "",
        f"Produced by `python benchmarks/bench_continuation.py --repeats {args.repeats}` on "
        f"{platform.machine()} (Python {platform.python_version()}); {args.repeats} "
        "interleaved runs, times per point as median (min..max) in ms (shared 2-core "
        f"machine: other jobs ran beside it; load average {load_start:.1f} at the start, "
        f"{os.getloadavg()[0]:.1f} at the end).", "",
        f"Scene `helicopter_tail_backlash` (packaged), pinion speed {LO:.0f}..{HI:.0f} rpm, "
        f"period-1 orbits, exact route. The continuation has {n_pts} points (the whole curve: "
        f"stable and unstable branches, 6 folds), worst scaled closing residual "
        f"{worst_residual:.1e} (newton_tol {settings.newton.tolerance:g}); with detection on, "
        f"{n_special} special points are located as well ({kinds}), each to "
        f"locate_tol {settings.locate_tol:g} relative in speed (largest stated error "
        f"{worst_error:.1e} relative, the corrector's included): bracketed with Brent's step "
        "by the tolerance, by secant steps on det(M + I) for period doublings and on the gap "
        "margin of the extremum that touches a contact boundary for grazing, and for folds at "
        "the stationary point of the speed's cubic Hermite interpolant from the exact "
        "tangents. The speed column of the Jacobian is exact (the walk's mesh-frequency "
        "derivative), so the corrector is Newton's method with the exact Jacobian: "
        f"{iters:.2f} maps per point on average (the Hermite predictor's and each Newton "
        "iterate's).", "",
        "| path | per point (ms) | mesh-period maps per point |",
        "|---|---|---|",
        f"| **continue_orbits**, detection on (all special points located) | "
        f"**{spread(ms_on)}** | {maps_on:.1f} |",
        f"| continue_orbits, detection off | {spread(ms)} | {maps_off:.1f} |",
        f"| natural-parameter sweep (`sweep_scene`, steady, up), same number of speeds | "
        f"{spread([1e3 * x for x in t_sweep])} | - |",
        f"| brute force: one-period exact flow iterated to the same closing residual | "
        f"{spread([1e3 * x for x in t_brute])} | {statistics.median(periods):.0f} "
        f"(max {max(periods)}) |", "",
        "Maps: n-period maps computed per point (with or without the sensitivity; each "
        "point's response measures and contact pattern come from its map's walk, not from "
        "another map): a cost measure that does not depend on the machine's load.", "",
        f"Detection on costs {spread(ratios, '.2f', 'x')} the time of detection off (the "
        "ratio of each interleaved pair, so the machine's load mostly cancels): "
        f"{maps_on - maps_off:.1f} maps per point more, "
        f"{(maps_on - maps_off) * n_pts / max(n_special, 1):.0f} per located point.", "",
        "CPU time of this process per point (`time.process_time`: the time the other jobs "
        "took the cores from it is left out, not their effect on its caches): detection on "
        f"{spread([1e3 * x for x in cpu_on])} ms, off {spread([1e3 * x for x in cpu_off])} "
        "ms.", "",
        f"Target: <= {TARGET_MS:g} ms CPU per period-1 continuation point with detection on: "
        f"**{'met' if statistics.median(cpu_on) * 1e3 <= TARGET_MS else 'NOT met'}** "
        f"(CPU median {1e3 * statistics.median(cpu_on):.2f} ms; "
        f"{1e3 * statistics.median(cpu_off):.2f} ms with detection off).", "",
        "The sweep and the brute force find only the stable orbits (the sweep jumps at the "
        "folds); the continuation also follows the unstable branch between them.",
    ]
    out_dir = output_dir(args)
    path = out_dir / "continuation.md"
    kept = ""  # sections of other measurements recorded in the same file ("## ..."), kept
    if path.exists():
        text = path.read_text()
        at = text.find("\n## ")
        kept = text[at:] if at >= 0 else ""
    path.write_text("\n".join(lines) + "\n" + kept)
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
