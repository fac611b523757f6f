"""The solve_ivp driver and the period maps: CPU per call, against another source tree.

Run:  python benchmarks/bench_flow.py [--repeats 5] [--before DIR [--before-label TEXT]] [--record]

Each case runs in a child process that imports gear_dyn from the tree under test (this one and,
with ``--before``, another), interleaved over the repeats; the figure is the child's CPU time
(user + system) of the case alone, so machine load moves it little. Median (min..max).

1. ``flow_on_grid``: 50 mesh periods at 64 samples of the parametric backlash pair of
   docs/motion.md at f_m / f_n = 2.0 (contact changes every period), DOP853 at rtol 1e-10:
   the driver with the stiffness frozen per piece and the contact restarts.
2. ``integrate_with_sensitivity`` by the variational equations (augmented state), one mesh
   period from 100 states of that run, rtol 1e-8.
3. ``integrate`` with LSODA (the settings' path: the model's own right-hand side), 40 mesh
   periods of helicopter_tail with ``potential_energy`` stiffness, rtol 1e-8.
4. ``sweep_charts`` of helicopter_tail (both charts, 300 x 120 cells each): the cells'
   closed-form 2x2 exponentials.

With ``--before`` the table also gives the largest difference of the results between the trees,
relative to each result's largest magnitude (the same arithmetic gives 0; a reordered sum
rounding-level values).

Writes ``flow.md`` into benchmarks/out/ (``--record``: benchmarks/results/).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import json
import platform
import sys
from pathlib import Path

from _timing import child_json, spread  # noqa: E402  (benchmarks/ is on sys.path)

ROOT = Path(__file__).resolve().parents[1]
CASES = ("flow_on_grid", "variational", "integrate_lsoda", "sweep_charts")


def _worker(case: str) -> None:
    """Run one case; print its CPU time and result as JSON (child process)."""
    import math
    import time
    import tomllib

    import numpy as np

    from gear_dyn.scene import load_scene, parse_scene
    from gear_dyn.scene.packaged import scene_path
    from gear_dyn.scene.sweep import SceneModels

    def backlash_model():  # the parametric backlash pair of docs/motion.md (bench_motion.py)
        data = tomllib.loads(scene_path("helicopter_tail_backlash").read_text())
        data["stiffness"] = {"method": "rectangular", "single": "0.5e9 N/m",
                             "double": "1.5e9 N/m"}
        data["damping"] = {"ratio": 0.02}
        data["scene"]["name"] = "parametric_backlash"
        factory = SceneModels.of(parse_scene(data, "parametric_backlash.toml"))
        fn = factory(100.0).natural_frequency
        return factory(2.0 * fn * 2 * math.pi / 23)

    from gear_dyn.analysis.stability import flow_on_grid
    from gear_dyn.solvers.sensitivity import integrate_with_sensitivity

    if case in ("flow_on_grid", "variational"):
        model = backlash_model()
        t = np.arange(50 * 64 + 1) / (64 * model.mesh_frequency)
        y0 = model.initial_state()
        start = time.process_time()
        y = flow_on_grid(model, y0, t, rtol=1e-10)
        cpu = time.process_time() - start
        out = y
        if case == "variational":
            starts = y[:, ::32][:, :100]
            start = time.process_time()
            out = np.array([np.concatenate([a, b.ravel()]) for a, b in (
                integrate_with_sensitivity(model, s, 1 / model.mesh_frequency, 1e-8,
                                           "variational") for s in starts.T)])
            cpu = time.process_time() - start
    elif case == "integrate_lsoda":
        from gear_dyn.solvers import SolverSettings, integrate

        data = tomllib.loads((ROOT / "examples" / "scenes" / "helicopter_tail.toml").read_text())
        data["stiffness"]["method"] = "potential_energy"
        model = SceneModels.of(parse_scene(data, "pe.toml"))(7000 * 2 * math.pi / 60)
        t = np.arange(40 * 64 + 1) / (64 * model.mesh_frequency)
        start = time.process_time()
        out, _ = integrate(model, t, SolverSettings(method="LSODA", estimate_error=False))
        cpu = time.process_time() - start
    else:
        from gear_dyn.analysis.chart import sweep_charts

        sc = load_scene(ROOT / "examples" / "scenes" / "helicopter_tail.toml")
        model = SceneModels.of(sc)(7000 * 2 * math.pi / 60)
        start = time.process_time()
        charts = sweep_charts(model, 0.1, 2.0)
        cpu = time.process_time() - start
        out = np.stack([c.spectral_radius for c in charts])
    print(json.dumps({"cpu": cpu, "result": np.asarray(out, dtype=float).ravel().tolist()}))


def _run(case: str, tree: Path) -> dict:
    return child_json([sys.executable, str(Path(__file__).resolve()), "--worker", case], tree)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--before", type=Path, default=None, metavar="DIR",
                    help="another source tree to compare with (its gear_dyn, same cases)")
    ap.add_argument("--before-label", default="the source tree given by --before",
                    metavar="TEXT", help="what the --before tree is, for the table's note")
    ap.add_argument("--record", action="store_true", help="write into benchmarks/results/")
    ap.add_argument("--worker", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        _worker(args.worker)
        return
    import numpy as np

    trees = [ROOT] + ([args.before.resolve()] if args.before else [])
    cpu: dict[tuple[str, int], list[float]] = {}
    last: dict[tuple[str, int], list[float]] = {}
    for _ in range(args.repeats):
        for case in CASES:
            for k, tree in enumerate(trees):
                got = _run(case, tree)
                cpu.setdefault((case, k), []).append(got["cpu"])
                last[(case, k)] = got["result"]
    rows = []
    for case in CASES:
        row = f"| {case} | {spread(cpu[(case, 0)])} |"
        if args.before:
            ratio = [b / a for a, b in zip(cpu[(case, 0)], cpu[(case, 1)], strict=True)]
            a, b = np.array(last[(case, 0)]), np.array(last[(case, 1)])
            diff = float(np.max(np.abs(a - b)) / np.max(np.abs(b))) if a.shape == b.shape \
                else float("nan")
            row += f" {spread(cpu[(case, 1)])} | {spread(ratio, '.2f', 'x')} | {diff:.1e} |"
        rows.append(row)
    load = ", ".join(f"{x:.1f}" for x in os.getloadavg())
    head = "| case | CPU now (s) |" + (" CPU before (s) | before / now | result difference |"
                                       if args.before else "")
    text = "\n".join([
        "# The solve_ivp driver and the period maps: CPU per case",
        "",
        f"Command: `python benchmarks/bench_flow.py --repeats {args.repeats}"
        f"{' --before DIR --before-label TEXT' if args.before else ''}"
        f"{' --record' if args.record else ''}`. "
        f"CPU time of each case in its own child process, median of {args.repeats} "
        "interleaved repeats (min..max); one BLAS thread. Cases: the module docstring.",
        "",
        f"Machine: {platform.machine()}, 2 cores shared with other jobs (load average at the "
        f"end: {load}), Python {platform.python_version()}.",
        "",
        *([f"`before`: the same cases on {args.before_label} (`--before DIR`).", ""]
          if args.before else []),
        head, "|---|---|" + ("---|---|---|" if args.before else ""), *rows, ""])
    out = ROOT / "benchmarks" / ("results" if args.record else "out")
    out.mkdir(parents=True, exist_ok=True)
    (out / "flow.md").write_text(text)
    print(text)
    print(f"wrote {out / 'flow.md'}")


if __name__ == "__main__":
    main()
