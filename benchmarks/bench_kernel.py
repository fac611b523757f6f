"""CPU time of the linear ``exact`` route and of ``run_scene`` before and after the compiled kernel.

Run:  python benchmarks/bench_kernel.py [--repeats 5] [--before REV] [--out DIR] [--record]

One run measures, side by side and interleaved (each round runs one child process per tree),
in CPU time (``time.process_time``) with one BLAS thread (``OPENBLAS_NUM_THREADS=1`` and its
peers, set before numpy loads), the medians over many calls in each child:

1. ``run_scene(helicopter_tail)`` (200 mesh periods, 64 samples per period, with its checks);
2. the ``exact`` route alone (``propagate_exact`` on the scene's model and grid) per mesh period,
   at 200 and 2000 periods, and the marginal cost of one more period (from the two);
3. ``run_scene(eccentric_helical)`` (not on the kernel's path yet: recorded for its target);

for this tree and for ``--before`` (default: the commit that moved the kernel, before it was
built into a library), checked out with ``git archive`` into a temporary folder. It also times
the floor of the linear scene: a C loop (``benchmarks/kernel_floor.c``, compiled here with
``-O2``) that applies the 64 step maps of one mesh period to a state and stores each sample.
Writes ``kernel.md`` (default benchmarks/out, ``--record``: benchmarks/results).
"""

from __future__ import annotations

import json
import os
import platform
import shutil
import statistics
import subprocess
import tempfile
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

from _timing import source_tree, tree_children  # noqa: E402  (benchmarks/ is on sys.path)

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
BEFORE = "b6e4209"  # "kernel: move ...": the kernel's C files at their new home, no library yet


def child(calls: int) -> dict[str, float]:
    """The measurements in this process (the gear_dyn on sys.path), medians in seconds."""

    from _timing import cpu_median as med

    import gear_dyn
    from gear_dyn import run_scene
    from gear_dyn.scene import build_plan, load_scene
    from gear_dyn.scene.packaged import resolve_scene
    from gear_dyn.solvers.exact import propagate_exact
    from gear_dyn.solvers.result import time_grid

    heli = load_scene(resolve_scene("helicopter_tail"))
    ecc = load_scene(resolve_scene("eccentric_helical"))
    plan = build_plan(heli)
    model, spp = plan.model, plan.settings.samples_per_period
    out = {"gear_dyn": str(Path(gear_dyn.__file__).parent)}
    out["run_scene_heli"] = med(lambda: run_scene(heli), calls)
    for periods in (200, 2000):
        t = time_grid(model.mesh_frequency, periods / model.mesh_frequency, spp)
        out[f"exact_{periods}"] = med(lambda t=t: propagate_exact(model, t), calls)
    out["run_scene_ecc"] = med(lambda: run_scene(ecc), max(2, calls // 10))
    return out  # type: ignore[return-value]


def floor_us_per_period(tmp: Path) -> float | None:
    """The C loop's time per mesh period (us), or None without a compiler."""
    cc = shutil.which(os.environ.get("CC", "cc")) or shutil.which("gcc")
    if cc is None:
        return None
    exe = tmp / "kernel_floor"
    subprocess.run([cc, "-std=c99", "-O2", str(HERE / "kernel_floor.c"), "-o", str(exe), "-lm"],
                   check=True)
    runs = [float(subprocess.run([str(exe), "64", "20000"], capture_output=True, text=True,
                                 check=True).stdout) for _ in range(5)]
    return statistics.median(runs)


def main(argv: list[str] | None = None) -> int:
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5, help="interleaved rounds")
    ap.add_argument("--calls", type=int, default=30, help="calls per child (median)")
    ap.add_argument("--before", default=BEFORE)
    ap.add_argument("--out", type=Path, default=HERE / "out")
    ap.add_argument("--record", action="store_true")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        print(json.dumps(child(args.calls)))
        return 0
    with tempfile.TemporaryDirectory() as tmpdir:
        tmp = Path(tmpdir)
        old = tmp / "before"
        old.mkdir()
        trees = {"before": source_tree(args.before, old), "after": ROOT}
        got = tree_children(Path(__file__).resolve(), trees, args.repeats,
                            ["--calls", str(args.calls)])
        floor = floor_us_per_period(tmp)

    def fig(name: str, key: str, scale: float) -> list[float]:
        return [g[key] * scale for g in got[name]]

    def row(label: str, key: str, scale: float, unit: str) -> str:
        b, a = fig("before", key, scale), fig("after", key, scale)
        return (f"| {label} | {statistics.median(b):.4g} {unit} | {statistics.median(a):.4g} "
                f"{unit} | {statistics.median(b) / statistics.median(a):.2f}x |")

    per200, per2000 = 1e6 / 200, 1e6 / 2000
    lines = [
        "# The compiled kernel: the linear exact route and run_scene, before and after",
        "",
        f"Command: `python benchmarks/bench_kernel.py --repeats {args.repeats} --calls "
        f"{args.calls}`. CPU time (`time.process_time`), one BLAS thread, medians over "
        f"{args.calls} calls in each of {args.repeats} interleaved child processes per tree "
        "(the figure is the median of those medians). *Before*: the code before the compiled "
        "kernel (`--before`, checked out by `git archive`; the exact route in numpy: an "
        "eigendecomposition per run, complex exponentials at "
        "every sample, a Python loop over the pieces); *after*: this tree (one period of exact "
        "step maps, the span filled by the C kernel). Python "
        f"{platform.python_version()}, {platform.machine()}.",
        "",
        "| figure | before | after | speed-up |",
        "|---|---|---|---|",
        row("`run_scene(helicopter_tail)`, CPU", "run_scene_heli", 1e3, "ms"),
        row("`exact` per mesh period, 200 periods", "exact_200", per200, "us"),
        row("`exact` per mesh period, 2000 periods", "exact_2000", per2000, "us"),
        row("`run_scene(eccentric_helical)`, CPU", "run_scene_ecc", 1e3, "ms"),
    ]
    marg = {k: statistics.median([(g["exact_2000"] - g["exact_200"]) / 1800 * 1e6
                                  for g in got[k]]) for k in trees}
    lines.append(f"| `exact`, marginal cost of one more mesh period | {marg['before']:.4g} us "
                 f"| {marg['after']:.4g} us | {marg['before'] / marg['after']:.2f}x |")
    lines.append("")
    if floor is not None:
        a200 = statistics.median(fig("after", "exact_200", per200))
        lines += [
            f"C loop floor (`benchmarks/kernel_floor.c`: 64 step maps per mesh period applied "
            f"and stored, 20000 periods, median of 5): {floor:.4g} us per mesh period. The "
            f"exact route after: {a200 / floor:.1f}x the floor at 200 periods (its fixed cost: "
            f"the pieces, the step maps and their products, once per run), "
            f"{marg['after'] / floor:.1f}x in its marginal cost per period.",
            "",
        ]
    lines.append("Raw medians per child (s): " + json.dumps(
        {k: [{kk: round(v, 7) for kk, v in g.items() if kk != "gear_dyn"} for g in got[k]]
         for k in trees}))
    text = "\n".join(lines) + "\n"
    out_dir = HERE / "results" if args.record else args.out
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "kernel.md").write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
