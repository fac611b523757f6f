"""What pint's on-disk cache buys a new process (gear_dyn.units.registry).

Run:  python benchmarks/bench_units.py [--repeats 15] [--record]

Whole processes, interleaved in each repeat: the bare interpreter; importing pint, building a
``UnitRegistry()`` and converting one text (``"3319 rpm"``), without the cache and with
``cache_folder=":auto:"`` (pint's own option, as gear_dyn.units builds it; the cache warmed
once before timing); and loading the packaged helicopter tail scene (every field read through
pint) as ``gear-dyn`` does. Medians of the repeats (min..max); the ratio is formed inside each
repeat. Writes ``units.md`` into ``--out`` (default ``benchmarks/out/``); ``--record`` into
``benchmarks/results/``.
"""

from __future__ import annotations

import argparse
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

from _timing import as_installed, spread  # benchmarks/ is on sys.path

ROOT = Path(__file__).resolve().parents[1]
CONVERT = "import pint; u = pint.UnitRegistry({}); u.Quantity('3319 rpm').to('rad/s')"
CASES = {
    "bare interpreter (`python -c pass`)": "pass",
    "pint registry, no cache": CONVERT.format(""),
    "pint registry, `cache_folder=\":auto:\"`": CONVERT.format("cache_folder=':auto:'"),
    "`load_scene('helicopter_tail')` (gear_dyn.units)":
        "from gear_dyn.scene import load_scene; load_scene('helicopter_tail')",
}


def wall(code: str, env: dict[str, str]) -> float:
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-c", code], check=True, env=env)
    return time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=15)
    ap.add_argument("--out", type=Path, default=ROOT / "benchmarks" / "out")
    ap.add_argument("--record", action="store_true", help="write into benchmarks/results/")
    args = ap.parse_args()
    env = as_installed(ROOT / "gear_dyn")
    for code in CASES.values():  # warm pint's cache and the file-system caches
        wall(code, env)
    times: dict[str, list[float]] = {k: [] for k in CASES}
    for _ in range(args.repeats):
        for name, code in CASES.items():
            times[name].append(wall(code, env))
    plain, cached = list(CASES)[1:3]
    ratio = [a / b for a, b in zip(times[plain], times[cached], strict=True)]
    saved = [a - b for a, b in zip(times[plain], times[cached], strict=True)]
    lines = [
        "# pint's on-disk cache in a new process", "",
        f"Command: `python benchmarks/bench_units.py --repeats {args.repeats} --record`. Whole "
        f"processes, median of {args.repeats} interleaved repeats (min..max), seconds.", "",
        f"Machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores shared "
        f"with other jobs (load average at the end: "
        f"{', '.join(f'{x:.1f}' for x in os.getloadavg())}), Python "
        f"{platform.python_version()}, pint {_pint_version()}.", "",
        "| process | wall time (s) |", "|---|---|",
        *(f"| {name} | {spread(t)} |" for name, t in times.items()), "",
        f"The cache saves **{spread(saved)} s** per process; registry without / with it: "
        f"**{spread(ratio, '.2f')}** (same repeat).", "",
    ]
    text = "\n".join(lines)
    print(text)
    out = ROOT / "benchmarks" / "results" if args.record else args.out
    out.mkdir(parents=True, exist_ok=True)
    (out / "units.md").write_text(text)
    print(f"wrote {out / 'units.md'}")


def _pint_version() -> str:
    from importlib.metadata import version

    return version("pint")


if __name__ == "__main__":
    main()
