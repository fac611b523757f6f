"""CPU time of ``run_scene`` before and after the ``kernel`` method (the native FMU's stepper).

Run:  python benchmarks/bench_kernel_method.py [--repeats 3] [--calls 5] [--before REV] [--record]

One run measures, side by side and interleaved (each round runs one child process per tree), in
CPU time (``time.process_time``) with one BLAS thread (``OPENBLAS_NUM_THREADS=1`` and its peers,
set before numpy loads), the medians over ``--calls`` calls in each child of

1. ``run_scene(eccentric_helical)`` (one hunting period, 630 mesh periods; before: ``gauss``);
2. ``run_scene(helicopter_tail_backlash, speed="7600 rpm")`` (at its mesh resonance, the teeth
   separating; before: ``exact_contact``);

for this tree and for ``--before`` (default: the commit before the kernel method), checked out
with ``git archive`` into a temporary folder and its kernel library built there. In this tree it
also times the parts of the kernel route for both scenes: the table (built once per model; the
eccentric pair's once per pair, whatever the speed, so the calls after the first in a process
reuse it, and the first call's time is reported apart) and one kernel run over the scene's
grid, and a short run of the eccentric scene (4 mesh periods) by method, with the method
``auto`` runs there with and without the pair's table. Writes ``kernel_method.md`` (default
benchmarks/out, ``--record``: benchmarks/results).
"""

from __future__ import annotations

import json
import os
import platform
import statistics
import tempfile
import time
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

from _timing import source_tree, tree_children  # noqa: E402  (benchmarks/ is on sys.path)

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
BEFORE = "e74ede4"  # the commit before the kernel method
CASES = {"ecc": ("eccentric_helical", None), "bl": ("helicopter_tail_backlash", "7600 rpm")}


def child(calls: int) -> dict[str, object]:
    """The measurements in this process (the gear_dyn on sys.path), medians in seconds."""

    from _timing import cpu_median as med

    import gear_dyn
    from gear_dyn import run_scene
    from gear_dyn.scene import load_scene

    out: dict[str, object] = {"gear_dyn": str(Path(gear_dyn.__file__).parent)}
    for key, (name, speed) in CASES.items():
        sc = load_scene(name)
        start = time.process_time()
        res = run_scene(sc, speed=speed)  # the first call: builds the tables it keeps
        out[f"{key}_first"] = time.process_time() - start
        out[f"{key}_method"] = res.stats.method
        out[f"{key}_error"] = float(res.extra["estimated_error"]["max_rel"])
        out[f"{key}_run_scene"] = med(lambda sc=sc, speed=speed: run_scene(sc, speed=speed),
                                      calls)
        try:
            from gear_dyn.scene.build import build_plan
            from gear_dyn.scene.operating import with_operating
            from gear_dyn.solvers.kernel.run import kernel_model, run
            from gear_dyn.solvers.kernel_method import kernel_tolerance
            from gear_dyn.solvers.result import time_grid
        except ImportError:  # the tree before the kernel method
            continue
        plan = build_plan(with_operating(sc, speed, None, function="bench"))
        model = plan.model
        t = time_grid(model.mesh_frequency, plan.t_end, plan.settings.samples_per_period)
        out[f"{key}_table"] = med(lambda model=model: kernel_model(model), calls)
        km = kernel_model(model)
        tol = kernel_tolerance(model, km, plan.settings.rtol)
        y0 = model.initial_state()
        out[f"{key}_kernel_run"] = med(lambda km=km, t=t, y0=y0, tol=tol: run(km, t, y0, tol),
                                       calls)
        if key == "ecc":  # a short run (4 mesh periods) of a model built in the call
            from gear_dyn.solvers import SolverSettings, integrate
            from gear_dyn.solvers import kernel_method as kmod

            short = t[: 4 * plan.settings.samples_per_period + 1]

            def fresh(method: str, keep: bool, short=short, sc=sc) -> None:
                if not keep:
                    kmod._CACHE.clear()
                    kmod._TABLES.clear()
                m = build_plan(with_operating(sc, None, None, function="bench")).model
                integrate(m, short, SolverSettings(method=method))

            for method, keep, label in (("gauss", True, "gauss"), ("kernel", False, "cold"),
                                        ("kernel", True, "kept")):
                out[f"short_{label}"] = med(lambda m=method, k=keep: fresh(m, k), calls)
            for keep, label in ((False, "cold"), (True, "kept")):  # what auto runs there
                if not keep:
                    kmod._CACHE.clear()
                    kmod._TABLES.clear()
                m = build_plan(with_operating(sc, None, None, function="bench")).model
                picked = integrate(m, short, SolverSettings(method="auto"))[1]["method"]
                out[f"short_auto_{label}"] = picked
    return out


def main(argv: list[str] | None = None) -> int:
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3, help="interleaved rounds")
    ap.add_argument("--calls", type=int, default=5, help="calls per child (median)")
    ap.add_argument("--before", default=BEFORE)
    ap.add_argument("--out", type=Path, default=HERE / "out")
    ap.add_argument("--record", action="store_true")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        print(json.dumps(child(args.calls)))
        return 0
    load = os.getloadavg()
    with tempfile.TemporaryDirectory() as tmpdir:
        old = Path(tmpdir) / "before"
        old.mkdir()
        trees = {"before": source_tree(args.before, old, kernel="build"), "after": ROOT}
        got = tree_children(Path(__file__).resolve(), trees, args.repeats,
                            ["--calls", str(args.calls)])

    def m(name: str, key: str) -> float:
        return statistics.median(float(g[key]) for g in got[name])

    lines = [
        "# The kernel method: run_scene before and after",
        "",
        f"Command: `python benchmarks/bench_kernel_method.py --repeats {args.repeats} --calls "
        f"{args.calls}`. CPU time (`time.process_time`), one BLAS thread, medians over "
        f"{args.calls} calls in each of {args.repeats} interleaved child processes per tree (the "
        "figure is the median of those medians). *Before*: the code before the kernel method "
        "(`--before`, checked out by `git archive`, its library built); *after*: this tree. "
        f"Python {platform.python_version()}, {platform.machine()}; load average before / "
        f"after the measurement: {load[0]:.2f} / {os.getloadavg()[0]:.2f} "
        f"({os.cpu_count()} cores).",
        "",
        "| run_scene | before: method | before | after: method | after | speed-up | "
        "stated error before / after (of W/k_m) |",
        "|---|---|---|---|---|---|---|",
    ]
    for key, (name, speed) in CASES.items():
        b, a = m("before", f"{key}_run_scene"), m("after", f"{key}_run_scene")
        label = f"`{name}`" + (f" at {speed}" if speed else "")
        lines.append(f"| {label} | {got['before'][0][f'{key}_method']} | {b * 1e3:.4g} ms | "
                     f"{got['after'][0][f'{key}_method']} | {a * 1e3:.4g} ms | {b / a:.2f}x | "
                     f"{float(got['before'][0][f'{key}_error']):.2g} / "
                     f"{float(got['after'][0][f'{key}_error']):.2g} |")
    lines += ["", "The kernel route's parts in this tree (the scene's model and grid), and the "
              "first `run_scene` call in each child (it builds the table the later calls of the "
              "same pair reuse; it also pays first-call costs of the process):", "",
              "| scene | table (once per pair) | one kernel run over the grid | first run_scene "
              "call: before / after |", "|---|---|---|---|"]
    for key, (name, _) in CASES.items():
        lines.append(f"| `{name}` | {m('after', f'{key}_table') * 1e3:.4g} ms | "
                     f"{m('after', f'{key}_kernel_run') * 1e3:.4g} ms | "
                     f"{m('before', f'{key}_first') * 1e3:.4g} ms / "
                     f"{m('after', f'{key}_first') * 1e3:.4g} ms |")
    lines += ["", "A short run, 4 mesh periods of `eccentric_helical` (its model built in the "
              "call), by method: `gauss` "
              f"{m('after', 'short_gauss') * 1e3:.4g} ms; `kernel` with its table built "
              f"{m('after', 'short_cold') * 1e3:.4g} ms, with the pair's table kept "
              f"{m('after', 'short_kept') * 1e3:.4g} ms. `auto` runs "
              f"`{got['after'][0]['short_auto_cold']}` there without the pair's table and "
              f"`{got['after'][0]['short_auto_kept']}` with it.",
              "", "Raw medians per child (s): " + json.dumps(
        {k: [{kk: (float(f"{v:.4g}") if isinstance(v, float) else v) for kk, v in g.items()
              if kk != "gear_dyn"} for g in got[k]] for k in trees})]
    text = "\n".join(lines) + "\n"
    out_dir = HERE / "results" if args.record else args.out
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "kernel_method.md").write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
