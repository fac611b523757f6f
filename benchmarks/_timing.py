"""Timing helpers shared by the benchmarks (run as scripts: ``benchmarks/`` is on sys.path)."""

from __future__ import annotations

import argparse
import compileall
import os
import statistics
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]


def bench_args(description: str, argv: list[str] | None = None,
               repeats: int = 3) -> argparse.Namespace:
    """The options every timing script takes: ``--repeats``, ``--out`` (default
    ``benchmarks/out``) and ``--record`` (write into ``benchmarks/results/`` instead)."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--repeats", type=int, default=repeats)
    ap.add_argument("--out", type=Path, default=ROOT / "benchmarks" / "out")
    ap.add_argument("--record", action="store_true", help="write into benchmarks/results/")
    return ap.parse_args(argv)


def output_dir(args: argparse.Namespace) -> Path:
    """Where a script writes its result (:func:`bench_args`' choice), created if missing."""
    out: Path = ROOT / "benchmarks" / "results" if args.record else args.out
    out.mkdir(parents=True, exist_ok=True)
    return out


def spread(values: list[float], fmt: str = ".3g", unit: str = "") -> str:
    """``median (min..max)`` of repeated figures, e.g. ``1.23 (1.2..1.3)`` or with
    ``unit="x"`` ``117.2x (114.7..142.9)``."""
    return (f"{statistics.median(values):{fmt}}{unit} ({min(values):{fmt}}.."
            f"{max(values):{fmt}})")


def timed(fn: Callable[[], Any]) -> tuple[float, Any]:
    """Wall time of one call in s, and its result."""
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def median_time(fn: Callable[[], Any], repeats: int) -> tuple[float, Any]:
    """Median wall time of ``repeats`` calls in s, and the last result."""
    times, out = [], None
    for _ in range(repeats):
        dt, out = timed(fn)
        times.append(dt)
    return statistics.median(times), out


def cpu_median(fn: Callable[[], Any], calls: int) -> float:
    """Median CPU time (``time.process_time``) of ``calls`` calls in s, after one warm-up call
    (first-use caches and imports left out)."""
    fn()
    times = []
    for _ in range(calls):
        t0 = time.process_time()
        fn()
        times.append(time.process_time() - t0)
    return statistics.median(times)


def as_installed(package_dir: Any) -> dict[str, str]:
    """The environment for timing whole processes as a user runs them after ``pip install``:
    the package's bytecode compiled beforehand (pip does so at install; an editable install
    with ``PYTHONDONTWRITEBYTECODE`` set would compile every module in every process), and
    that variable left out of the children's environment."""
    compileall.compile_dir(str(package_dir), quiet=1)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["MPLBACKEND"] = "Agg"
    return env
