"""Per-speed sweep cost by stiffness method, and how fast Ctrl-C stops a sweep with workers.

Run:  python benchmarks/bench_sweep_stiffness.py [--repeats 3] [--record]

1. ``sweep_scene`` of the helicopter tail pair over 361 speeds (1000-10000 rpm), one process,
   with ``iso6336`` (the packaged scene), ``potential_energy`` (the same scene, its
   ``[stiffness] method`` replaced) and the tip-relief scene (loaded contact on
   ``potential_energy``). The per-speed cost is (time of 361 speeds - time of 37 speeds) / 324,
   so the fixed cost (building the model, the loaded contact) drops out; ratios against
   ``iso6336`` are formed within one repeat. Median (min..max) of the repeats.
2. Ctrl-C latency: ``gear-dyn sweep`` of the backlash scene with ``--workers 2`` (transient
   method, minutes of work), SIGINT sent 1 s after both workers run; the time to exit (130).

Writes ``sweep_stiffness.md`` into benchmarks/out/ (``--record``: benchmarks/results/).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import math
import platform
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from gear_dyn.scene import load_scene
from gear_dyn.scene.loader import Scene
from gear_dyn.scene.sweep import sweep_scene

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "gear_dyn" / "scenes"
RPM = 2 * math.pi / 60


def _scene(name: str, method: str | None = None) -> Scene:
    sc = load_scene(SCENES / f"{name}.toml")
    if method is None:
        return sc
    return Scene(source=sc.source,
                 tables={**sc.tables, "stiffness": {**sc.tables["stiffness"], "method": method}})


CASES = {"iso6336": lambda: _scene("helicopter_tail"),
         "potential_energy": lambda: _scene("helicopter_tail", "potential_energy"),
         "tip relief (potential_energy)": lambda: _scene("helicopter_tail_relief")}


def per_speed(scene: Scene) -> float:
    def timed(n: int) -> float:
        t0 = time.perf_counter()
        sweep_scene(scene, np.linspace(1000, 10000, n) * RPM, si=True)
        return time.perf_counter() - t0
    timed(2)  # the model built and cached, imports done
    return (timed(361) - timed(37)) / 324


def interrupt_latency() -> float:
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [str(Path(sys.executable).with_name("gear-dyn")), "sweep",
               str(SCENES / "helicopter_tail_backlash.toml"), "--speeds",
               "2000 rpm:12000 rpm:4000", "--workers", "2", "--sweep-method", "transient",
               "--out", f"{tmp}/o", "--quiet"]
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        kids = Path(f"/proc/{proc.pid}/task/{proc.pid}/children")
        while proc.poll() is None and not (kids.exists() and len(kids.read_text().split()) >= 2):
            time.sleep(0.1)
        time.sleep(1.0)
        t0 = time.perf_counter()
        os.kill(proc.pid, signal.SIGINT)
        rc = proc.wait(60)
        dt = time.perf_counter() - t0
        assert rc == 130, rc
        return dt


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--record", action="store_true")
    args = ap.parse_args()
    scenes = {k: f() for k, f in CASES.items()}
    cost: dict[str, list[float]] = {k: [] for k in scenes}
    ratio: dict[str, list[float]] = {k: [] for k in scenes}
    lat = []
    for _ in range(args.repeats):
        this = {k: per_speed(sc) for k, sc in scenes.items()}
        for k in scenes:
            cost[k].append(this[k])
            ratio[k].append(this[k] / this["iso6336"])
        lat.append(interrupt_latency())

    def fmt(v: list[float], scale: float = 1.0, f: str = ".3g") -> str:
        return (f"{statistics.median(v) * scale:{f}} ({min(v) * scale:{f}}.."
                f"{max(v) * scale:{f}})")
    lines = ["# Sweep cost per speed by stiffness method; Ctrl-C latency with workers", "",
             f"Command: `python benchmarks/bench_sweep_stiffness.py --repeats {args.repeats}"
             f"{' --record' if args.record else ''}`", "",
             f"Machine: {platform.machine()}, {os.cpu_count()} cores shared with other jobs "
             f"(load average at the end: {', '.join(f'{x:.1f}' for x in os.getloadavg())}), "
             f"Python {platform.python_version()}. Median (min..max) of {args.repeats} "
             "repeats.", "",
             "Before this change (issue 24, finding 4, on the issue's own 28/28 pair): 361 "
             "speeds took 0.17 s with iso6336, "
             "18.6 s with potential_energy and 107 s with tip relief (DOP853 per speed).", "",
             "| stiffness | per speed (ms) | vs iso6336 (target <= 5) |", "|---|---|---|"]
    for k in scenes:
        lines.append(f"| {k} | {fmt(cost[k], 1e3)} | {fmt(ratio[k], 1.0, '.2f')} x |")
    lines += ["", "Ctrl-C: SIGINT to `gear-dyn sweep helicopter_tail_backlash --workers 2` "
              f"(transient, 4000 speeds) 1 s after both workers run; exit 130 after "
              f"{fmt(lat, 1.0, '.2f')} s (before: 20-28 s).", ""]
    out = ROOT / "benchmarks" / ("results" if args.record else "out")
    out.mkdir(parents=True, exist_ok=True)
    (out / "sweep_stiffness.md").write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
