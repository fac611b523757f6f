"""Tip relief: accuracy of the linearised single-DOF forms against the nonlinear contact model,
and run times of the loaded-contact analysis and of the dynamic runs.

Helicopter tail pair (Jiang et al. 2018, as spur), 3319 rpm, 1474.4 N m, potential-energy pair
stiffness, damping 0.06, 40 mesh periods (20 steady), DOP853 rtol 1e-7. Dynamic factor by:
- tangent: tangent stiffness k_t + the relief's transmission error e (the default);
- secant: K_TPM = F / delta (Wang et al. 2024), no e;
- contact: the nonlinear force sum K_j max(0, x - g_j) (reference).
Run times (wall clock, 2 shared cores): loaded contact, median of ``REPEATS`` runs; a dynamic
run, median over the 5 reliefs (one run each); (min..max) in brackets.

Run:  python benchmarks/bench_relief.py [--repeats 3] [--out DIR] [--record]

Writes ``relief.md`` into ``--out`` (default ``benchmarks/out/``, git-ignored) and prints it;
``--record`` writes into ``benchmarks/results/`` (the figures the README and the tests' comments
quote).
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

from gear_dyn.analysis.study import simulate
from gear_dyn.geometry import GearPair
from gear_dyn.models.relief import ContactSDOFModel, pair_stiffness_function, relief_sdof
from gear_dyn.modification import RULES, loaded_contact, recommended_relief
from gear_dyn.solvers import SolverSettings

PAIR = GearPair(23, 64, 6e-3, math.radians(22.5), 50e-3, youngs_modulus1=207e9,
                youngs_modulus2=207e9)
SPEED = 3319 * 2 * math.pi / 60
TORQUE = 1474.4
SETTINGS = SolverSettings(method="DOP853", rtol=1e-7, samples_per_period=64)
from _timing import spread  # noqa: E402  (benchmarks/ is on sys.path)

ROOT = Path(__file__).resolve().parents[1]




def timed(func, repeats: int):  # type: ignore[no-untyped-def]
    times, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = func()
        times.append(time.perf_counter() - t0)
    return out, times


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3, help="loaded-contact runs (default 3)")
    ap.add_argument("--out", type=Path, default=ROOT / "benchmarks" / "out",
                    help="output folder (default benchmarks/out/, git-ignored)")
    ap.add_argument("--record", action="store_true",
                    help="write into benchmarks/results/ (the recorded figures)")
    args = ap.parse_args()
    out_dir = ROOT / "benchmarks" / "results" if args.record else args.out
    lines: list[str] = []

    def say(text: str = "") -> None:
        """One line of the report, echoed."""
        lines.append(text)
        print(text, flush=True)

    fn = pair_stiffness_function(PAIR)
    say("# Tip relief: linearisation accuracy and run times\n")
    say(f"Command: `python benchmarks/bench_relief.py --repeats {args.repeats}` (helicopter "
          "tail pair, 3319 rpm, 1474.4 N m, potential-energy pair stiffness, xi = 0.06, 40 mesh "
          "periods, DOP853 rtol 1e-7; wall-clock times on 2 shared cores: the loaded contact is "
          f"the median of {args.repeats} runs, a dynamic run the median over the 5 reliefs of one "
          "run each; (min..max) in brackets).\n")
    say("| relief | K_v tangent | K_v secant | K_v contact (ref.) | tangent error | "
          "secant error |")
    say("|---|---|---|---|---|---|")
    cases = {"unmodified": None}
    for rule in RULES:
        cases[rule] = recommended_relief(PAIR, TORQUE, rule).modification("linear")
    sim_times: dict[str, list[float]] = {"tangent": [], "secant": [], "contact": []}
    for name, mod in cases.items():
        kv = {}
        for lin in ("tangent", "secant"):
            model, _ = relief_sdof(PAIR, SPEED, TORQUE, mod, fn, linearisation=lin)
            fm = model.mesh_frequency
            t0 = time.perf_counter()
            kv[lin] = simulate(model, 40 / fm, SETTINGS, 20 / fm).peak_force_ratio
            sim_times[lin].append(time.perf_counter() - t0)
        ref = ContactSDOFModel(PAIR, SPEED, TORQUE, mod, fn)
        fm = ref.mesh_frequency
        t0 = time.perf_counter()
        kv["contact"] = simulate(ref, 40 / fm, SETTINGS, 20 / fm).peak_force_ratio
        sim_times["contact"].append(time.perf_counter() - t0)
        e_t = (kv["tangent"] - kv["contact"]) / kv["contact"]
        e_s = (kv["secant"] - kv["contact"]) / kv["contact"]
        say(f"| {name} | {kv['tangent']:.4f} | {kv['secant']:.4f} | {kv['contact']:.4f} | "
              f"{e_t * 100:+.2f} % | {e_s * 100:+.2f} % |")
    say("\n| step | median time (s) |")
    say("|---|---|")
    mod = recommended_relief(PAIR, TORQUE, "niemann").modification("linear")
    _, t_lc = timed(lambda: loaded_contact(PAIR, fn, TORQUE, mod), args.repeats)
    say(f"| loaded contact over one mesh cycle (Niemann relief, 48 samples/segment) | "
          f"{spread(t_lc)} |")
    for lin, ts in sim_times.items():
        say(f"| 40-period single-DOF run, {lin} (median over the {len(ts)} reliefs) | "
              f"{spread(ts)} |")
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "relief.md").write_text("\n".join(lines) + "\n")
    print(f"wrote {out_dir / 'relief.md'}")


if __name__ == "__main__":
    main()
