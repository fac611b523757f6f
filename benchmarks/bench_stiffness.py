"""Time to build each mesh-stiffness curve (cold: caches cleared; median of repeated runs).

Also records two accuracy tables quoted in docs/stiffness.md: the shaft offset of Jiang et al. 2018
(contact ratio, single-contact share, backlash, mean stiffness per method) and the helical
thin-slice mean against ISO over the helix angle.

Usage: python benchmarks/bench_stiffness.py [--repeats N] [--out benchmarks/results/stiffness.md]

For each pair and method, the build is timed with every cache cleared first (tooth tables,
built curves), so the figure is the full cost of one new curve; the scalar evaluation cost k(p)
(what the solver pays per right-hand-side call) is timed too. Prints a Markdown table and writes it
to --out.
"""

from __future__ import annotations

import argparse
import math
import platform
import statistics
import sys
import time
from pathlib import Path

from gear_dyn.geometry import GearPair
from gear_dyn.stiffness import build_stiffness, iso6336_stiffness
from gear_dyn.stiffness.select import METHODS, _build_cached
from gear_dyn.stiffness.tooth import tooth_table

PAIRS = {
    "classic 19/48, m 3.2, b 16 (spur)": GearPair(19, 48, 3.2e-3, math.radians(20), 16e-3,
                                                 youngs_modulus1=206.8e9,
                                                 youngs_modulus2=206.8e9),
    "helicopter tail 23/64, m 6, b 50 (spur)": GearPair(23, 64, 6e-3, math.radians(22.5), 50e-3,
                                                       youngs_modulus1=207e9,
                                                       youngs_modulus2=207e9),
    "helical 25/60, m 3, b 30, beta 15 deg": GearPair(25, 60, 3e-3, math.radians(20), 30e-3,
                                                      helix_angle=math.radians(15)),
}


def _clear() -> None:
    _build_cached.cache_clear()
    tooth_table.cache_clear()


def bench(repeats: int) -> str:
    lines = [
        "| pair | method | build (ms, median) | k(p) scalar (us) | mean (N/m) "
        "| mean / ISO c_gamma b |",
        "|---|---|---:|---:|---:|---:|",
    ]
    for label, pair in PAIRS.items():
        iso = iso6336_stiffness(pair).k_mesh
        for method in METHODS:
            times = []
            for _ in range(repeats):
                _clear()
                t0 = time.perf_counter()
                k = build_stiffness(pair, method)
                times.append(time.perf_counter() - t0)
            n = 20000
            t0 = time.perf_counter()
            for i in range(n):
                k(i / n)
            call = (time.perf_counter() - t0) / n
            lines.append(f"| {label} | {method} | {statistics.median(times) * 1e3:.3g} | "
                         f"{call * 1e6:.2g} | {k.mean:.4g} | {k.mean / iso:.3f} |")
    return "\n".join(lines)


def offset_table() -> str:
    """The shaft offset of Jiang et al. (2018): operating geometry and means of every method
    (helicopter tail)."""
    from gear_dyn.stiffness.summary import operating_summary

    def tail(a_w: float | None = None) -> GearPair:
        return GearPair(23, 64, 6e-3, math.radians(22.5), 50e-3, youngs_modulus1=207e9,
                        youngs_modulus2=207e9, center_distance=a_w)

    base = tail()
    methods = ("iso6336", "potential_energy", "weber", "contact_line")
    lines = ["| offset | eps_a | single-contact share | backlash (um) | mean k (1e8 N/m): "
             + " / ".join(methods) + " |", "|---|---:|---:|---:|---|"]
    for da in (0.0, 0.1e-3, 0.3e-3, 0.5e-3):
        pair = tail(base.a_w + da)
        op = operating_summary(pair)
        means = " / ".join(f"{build_stiffness(pair, m).mean / 1e8:.3f}" for m in methods)
        lines.append(f"| {da * 1e3:.1f} mm | {op['contact_ratio']:.4f} | "
                     f"{op['single_contact_share']:.3f} | {op['backlash_m'] * 1e6:.1f} | "
                     f"{means} |")
    return "\n".join(lines)


def helix_table() -> str:
    """Potential-energy mean over ISO c_gamma b against the helix angle (thin-slice model)."""
    lines = ["| helix angle | PEM mean / ISO c_gamma b | contact_line / ISO |", "|---:|---:|---:|"]
    for beta in (0, 10, 15, 20, 25, 30):
        pair = GearPair(25, 60, 3e-3, math.radians(20), 30e-3, helix_angle=math.radians(beta))
        iso = iso6336_stiffness(pair).k_mesh
        lines.append(f"| {beta} deg | {build_stiffness(pair, 'potential_energy').mean / iso:.3f} "
                     f"| {build_stiffness(pair, 'contact_line').mean / iso:.3f} |")
    return "\n".join(lines)


# the pairs of tests/physics/test_stiffness_potential_energy.py::test_pem_mean_within_band
BAND_PAIRS = (
    (19, 48, 3.2e-3, 20.0, 16e-3, 0.0, 0.0),
    (23, 64, 6e-3, 22.5, 50e-3, 0.0, 0.0),
    (25, 25, 4e-3, 20.0, 20e-3, 0.0, 0.0),
    (18, 80, 2e-3, 20.0, 20e-3, 0.0, 0.0),
    (30, 90, 5e-3, 20.0, 40e-3, 0.0, 0.0),
    (40, 40, 3e-3, 25.0, 30e-3, 0.0, 0.0),
    (15, 40, 3e-3, 20.0, 20e-3, 0.25, 0.1),
    (60, 120, 2e-3, 20.0, 20e-3, 0.0, 0.0),
)


def band_table() -> str:
    """Mean of each geometric method over ISO c_gamma b for the spur pairs of the band test."""
    lines = ["| z1/z2 | m (mm) | a_n (deg) | b (mm) | x1, x2 | eps_a | PEM / ISO | Weber / ISO |",
             "|---|---:|---:|---:|---|---:|---:|---:|"]
    for z1, z2, m, a, b, x1, x2 in BAND_PAIRS:
        pair = GearPair(int(z1), int(z2), m, math.radians(a), b, x1=x1, x2=x2)
        iso = iso6336_stiffness(pair).k_mesh
        lines.append(
            f"| {z1}/{z2} | {m * 1e3:g} | {a:g} | {b * 1e3:g} | {x1:g}, {x2:g} | "
            f"{pair.contact_ratio:.3f} | {build_stiffness(pair, 'potential_energy').mean / iso:.3f}"
            f" | {build_stiffness(pair, 'weber').mean / iso:.3f} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=15)
    ap.add_argument("--out", type=Path,
                    default=Path(__file__).resolve().parent / "out" / "stiffness.md",
                    help="report file (default benchmarks/out/, git-ignored)")
    ap.add_argument("--record", action="store_true",
                    help="write the recorded results, benchmarks/results/stiffness.md")
    args = ap.parse_args(argv)
    table = bench(args.repeats)
    head = (
        "# Mesh-stiffness build times\n\n"
        f"Command: `python benchmarks/bench_stiffness.py --repeats {args.repeats}`  \n"
        f"Machine: {platform.machine()}, Python {platform.python_version()}, "
        f"{platform.system()} (shared 2-core runner; medians of {args.repeats} cold builds)\n\n"
        "Cold build: tooth tables and curve caches cleared before each run; defaults "
        "(200 samples per cycle, continuous face slicing for helical pairs, 3001-point tooth grid, "
        "20 Weber slices). A cached rebuild costs a dictionary lookup.\n\n"
    )
    text = (head + table + "\n\n## Centre-distance offset (helicopter tail pair)\n\n"
            + offset_table() + "\n\n## Helix angle (25/60, m 3 mm, b 30 mm, 20 deg)\n\n"
            + helix_table() + "\n\n## Mean against ISO 6336 for spur pairs\n\n"
            + band_table() + "\n")
    if args.record:
        args.out = Path(__file__).resolve().parent / "results" / "stiffness.md"
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text)
    sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
