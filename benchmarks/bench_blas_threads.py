"""CPU time of ``run_scene`` from Python with the API's one-BLAS-thread limit and without it.

Run:  python benchmarks/bench_blas_threads.py [--repeats 3] [--out DIR] [--record]

The analysis layer's entry points run inside :func:`gear_dyn.analysis.threads.one_blas_thread`
(one BLAS thread, scoped to the call). Without it OpenBLAS keeps its default threads, which on
a busy machine cost CPU for nothing on gear_dyn's 2x2..8x8 matrices. Each repeat times 15 runs
of ``run_scene(helicopter_tail)`` (``exact``, error estimate included) both ways, interleaved;
CPU time of this process (all its threads), per run. Run it without OPENBLAS_NUM_THREADS &
co. set (a user's choice disables the limit).
"""

from __future__ import annotations

import os
import platform
import time

from _timing import bench_args, output_dir, spread

import gear_dyn.analysis.threads as threads
from gear_dyn.scene import load_scene, run_scene

RUNS = 15


def cpu_per_run(scene: object) -> float:
    t0 = time.process_time()
    for _ in range(RUNS):
        run_scene(scene)  # type: ignore[arg-type]
    return (time.process_time() - t0) / RUNS


def main() -> None:
    args = bench_args(__doc__.splitlines()[0])
    assert not any(os.environ.get(v) for v in threads.USER_CHOICE), "unset the BLAS variables"
    scene = load_scene("helicopter_tail")
    run_scene(scene)  # warm
    limited, default = [], []
    for _ in range(args.repeats):
        threads._state["controller"] = None  # the limit (its controller made again)
        limited.append(cpu_per_run(scene))
        threads._state["controller"] = False  # as without threadpoolctl: no limit
        default.append(cpu_per_run(scene))
    threads._state["controller"] = None
    ratio = [d / lim for d, lim in zip(default, limited, strict=True)]
    load = ", ".join(f"{x:.1f}" for x in os.getloadavg())
    text = "\n".join([
        "# BLAS threads: the Python API's one-thread limit", "",
        f"Command: `python benchmarks/bench_blas_threads.py --repeats {args.repeats}"
        f"{' --record' if args.record else ''}`. CPU time of the process per "
        f"`run_scene(helicopter_tail)` (exact, error estimate included), {RUNS} runs per "
        f"repeat, median of {args.repeats} interleaved repeats (min..max).", "",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores shared with other jobs (load "
        f"average at the end: {load}), Python {platform.python_version()}.", "",
        "| BLAS threads | CPU per run (ms) |", "|---|---|",
        f"| one, scoped to the call (the API's default) | {spread([1e3 * x for x in limited])} |",
        f"| OpenBLAS default | {spread([1e3 * x for x in default])} |", "",
        f"Default over limited: {spread(ratio, '.2f', 'x')}.", ""])
    print(text)
    out = output_dir(args) / "blas_threads.md"
    out.write_text(text)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
