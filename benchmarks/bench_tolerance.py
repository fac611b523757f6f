"""Tolerance study: CPU time of a 200-sample Monte-Carlo study of a linear scene over 100 speeds.

Run:  python benchmarks/bench_tolerance.py [--repeats 3] [--out DIR] [--record]

Scene ``helicopter_tail`` (linear, ISO 6336 rectangular stiffness, z1 = 23, z2 = 64: a hunting
period of 1472 mesh cycles), random deviations of ISO 1328-1:2013 grade 6, speeds 1000-9000 rpm,
64 samples per mesh period (the scene's). Method (gear_dyn.analysis.tolerance): per speed the
periodic response to each unit deviation harmonic (44 orders: 11 pinion and 32 gear shaft
orders, one mesh harmonic) and to the load is computed once, exactly, by closed-form cell maps;
every sample is then a linear combination of them (one matrix product per speed for all
samples), and its peak and RMS over the hunting period are taken from the per-residue maxima
and means, at (z1 + z2) mesh cycles' cost instead of 1472.

Figures: CPU time (``time.process_time``, this process: BLAS single-threaded) and wall time of
``tolerance_scene`` for N = 200 and N = 50 samples; the cost per sample per speed is the slope
between them, the fixed cost (unit responses, quasi-static reference) the rest. Median of the
repeats (min..max). Also the time of the same study split over a Dask ``LocalCluster``
(1 worker, threads, started outside the figure), whose numbers are checked to equal the serial
ones.

Writes ``tolerance.md`` into ``--out`` (default ``benchmarks/out/``); ``--record`` writes into
``benchmarks/results/``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import platform  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
from _timing import bench_args, output_dir, spread  # noqa: E402

import gear_dyn as gd  # noqa: E402
from gear_dyn.scene.tolerance import tolerance_scene  # noqa: E402

SPEEDS = "1000 rpm:9000 rpm:100"


def study(n: int, executor=None):  # type: ignore[no-untyped-def]
    c0, w0 = time.process_time(), time.perf_counter()
    res = tolerance_scene(gd.load_scene("helicopter_tail"), SPEEDS, samples=n, grade=6,
                          executor=executor)
    return time.process_time() - c0, time.perf_counter() - w0, res


def main() -> None:
    args = bench_args(__doc__.splitlines()[0], repeats=3)
    study(4)  # imports, caches
    cpu: dict[int, list[float]] = {200: [], 50: []}
    wall: dict[int, list[float]] = {200: [], 50: []}
    per_sample: list[float] = []
    last = None
    for _ in range(args.repeats):
        c = {}
        for n in (200, 50):
            c[n], w, res = study(n)
            cpu[n].append(c[n])
            wall[n].append(w)
            if n == 200:
                last = res
        per_sample.append((c[200] - c[50]) / 150 / 100 * 1e3)
    assert last is not None
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=1, processes=False, threads_per_worker=2,
                      dashboard_address=":0") as cluster, Client(cluster) as client:
        _c, dask_wall, remote = study(200, client.get_executor())
    same = all(np.array_equal(last.values[k], remote.values[k]) for k in last.values)
    fixed = [c2 - 200 * p * 100 / 1e3 for c2, p in zip(cpu[200], per_sample, strict=True)]
    med = statistics.median(cpu[200])
    verdict = f"{'met' if med <= 10 else 'missed'} (median {med:.3g} s)"
    text = f"""# Tolerance study benchmark: 200 samples x 100 speeds of a linear scene

Command: `python benchmarks/bench_tolerance.py --repeats {args.repeats} --record`. Median of
{args.repeats} repeats (min..max).

Machine: {platform.machine()}, {os.cpu_count()} cores shared with other jobs (wall times
vary with them; CPU times much less), Python {platform.python_version()}; BLAS one thread.

Scene `helicopter_tail` (ISO 6336 rectangular stiffness, z1 = 23, z2 = 64, hunting period 1472
mesh cycles), ISO 1328-1:2013 grade 6, random deviations, speeds {SPEEDS}, 64 samples per mesh
period. Every figure covers the whole hunting period exactly (superposition of the unit-harmonic
responses computed once per speed; docs/tolerance.md).

| study | CPU time (s) | wall time (s) |
|---|---|---|
| N = 200 samples, 100 speeds | {spread(cpu[200])} | {spread(wall[200])} |
| N = 50 samples, 100 speeds | {spread(cpu[50])} | {spread(wall[50])} |

Cost per sample and speed (slope between N = 50 and 200): **{spread(per_sample)} ms CPU**;
fixed cost (unit responses of 100 speeds and the quasi-static reference):
{spread(fixed)} s CPU. Target: at most 10 s CPU for N = 200: **{verdict}**.

A study of N samples over S speeds costs about fixed + N x S x (cost per sample and speed); its
tasks are blocks of 10 speeds, each for all N samples (sizing a Dask cluster: one task holds
N x 10 x the figures, and its memory grows with N x (z1 + z2) x samples per period).

Dask `LocalCluster` (1 worker, 2 threads, processes=False), N = 200: wall time
{dask_wall:.3g} s; numbers equal to the serial run: {same}.
"""
    out = output_dir(args) / "tolerance.md"
    out.write_text(text)
    print(text)


if __name__ == "__main__":
    main()
