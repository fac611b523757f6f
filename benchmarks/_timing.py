"""Timing helpers shared by the benchmarks (run as scripts: ``benchmarks/`` is on sys.path)."""

from __future__ import annotations

import argparse
import compileall
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any, NamedTuple, TypeVar

T = TypeVar("T")

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


# ------------------------------------------------------------------ child processes
class ChildRun(NamedTuple):
    """One child process run to its end: wall and CPU time in s, its output."""

    wall: float
    cpu: float
    stdout: str
    stderr: str


def run_child(cmd: list[str], cwd: Path | None = None,
              env: Mapping[str, str] | None = None) -> ChildRun:
    """Run ``cmd`` to its end (a failure raises, with its stderr): wall time, CPU time (user +
    system of the child and of its own children, ``RUSAGE_CHILDREN``) and its output."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    done = subprocess.run(cmd, cwd=cwd, env=None if env is None else dict(env), check=True,
                          capture_output=True, text=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return ChildRun(wall, cpu, done.stdout, done.stderr)


def tree_env(tree: Path, env: Mapping[str, str] | None = None) -> dict[str, str]:
    """``env`` (default: this process's environment) with ``tree``'s gear_dyn first on the
    path."""
    return {**(os.environ if env is None else env), "PYTHONPATH": str(tree)}


def child_json(cmd: list[str], tree: Path, env: Mapping[str, str] | None = None) -> Any:
    """The JSON a child prints last (on its last line of stdout), run in ``tree`` with that
    tree's gear_dyn (:func:`tree_env`)."""
    out = run_child(cmd, cwd=tree, env=tree_env(tree, env)).stdout
    return json.loads(out.strip().splitlines()[-1])


def interleaved(trees: Mapping[str, Path], repeats: int,
                measure: Callable[[str, Path], T]) -> dict[str, list[T]]:
    """``repeats`` rounds, each measuring every tree once in turn (a change in the machine's
    load falls on all trees alike): ``measure(name, tree)`` per round, listed per tree."""
    got: dict[str, list[T]] = {name: [] for name in trees}
    for _ in range(repeats):
        for name, tree in trees.items():
            got[name].append(measure(name, tree))
    return got


def tree_children(script: Path, trees: Mapping[str, Path], repeats: int,
                  args: list[str]) -> dict[str, list[dict[str, Any]]]:
    """``python SCRIPT --child ARGS`` once per tree and round (:func:`interleaved`), the dict
    each child prints last; each child states the gear_dyn it imported (its ``gear_dyn``
    entry), checked to be its own tree's."""
    got = interleaved(trees, repeats, lambda _name, tree: child_json(
        [sys.executable, str(script), "--child", *args], tree))
    for name, tree in trees.items():
        if not all(Path(str(g["gear_dyn"])).resolve() == (tree / "gear_dyn").resolve()
                   for g in got[name]):
            raise RuntimeError(f"{name}: a child imported another gear_dyn than {tree}")
    return got


def source_tree(ref: str, dest: Path, kernel: str = "") -> Path:
    """The source tree of git ``ref`` in ``dest`` (``git archive``). ``kernel``: ``copy``
    this checkout's compiled kernel into it (sources that need one and cannot build it), or
    ``build`` the tree's own; "" neither."""
    archive = subprocess.run(["git", "archive", ref], cwd=ROOT, check=True,
                             capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(dest)], input=archive, check=True)
    if kernel == "copy":
        lib_dir = ROOT / "gear_dyn" / "solvers" / "kernel"
        for lib in lib_dir.glob("_gd_kernel*"):
            shutil.copy2(lib, dest / "gear_dyn" / "solvers" / "kernel" / lib.name)
    elif kernel == "build":
        subprocess.run([sys.executable, "setup.py", "build_ext", "--inplace", "-q"], cwd=dest,
                       check=True, capture_output=True)
    elif kernel:
        raise ValueError(f"kernel = {kernel!r}: valid choices are copy, build or ''")
    return dest
