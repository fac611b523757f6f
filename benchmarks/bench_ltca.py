"""Slice-method loaded tooth contact analysis: run time and the discretisation it converges at.

The rail pair (23/79, m_n 6 mm, a_n 20 deg, helix 20 deg, B 70 mm, x = +0.3 / -0.1), potential-
energy structure + Hertz per slice, Pasternak coupling (default decay length), with the gear
handbook tip relief, 8 um pinion crowning and f_ma = 10 um (so the active set has work to do),
and unmodified for the convergence table.

Timed (wall clock, median of ``--repeats`` runs, (min..max) in brackets; the tooth tables are
built once beforehand, as every call after the first in a process finds them cached):
- one torque (2000 N m), 32 mesh positions, 30 slices;
- a ladder of 10 torques (200 .. 2000 N m), same discretisation.
Targets: 50 ms and 0.5 s.

Per-speed cost of the single-DOF model on the slice loaded contact (the relief study's dynamic
part), three routes over the same 10 speeds (1000 .. 6000 rpm) at 2000 N m, one design:
- the loaded contact rebuilt at every speed (a factory ``speed -> slice_sdof(...)``), steady;
- the model built once, ``at_mesh_frequency`` per speed, a transient run per speed (40 mesh
  periods, the last 20 read, as the rail scene's ``[solver]``);
- the model built once, ``at_mesh_frequency`` per speed, steady (the periodic orbit from one
  linear solve with the monodromy matrix: what ``relief_study(..., speeds=)`` does).
Then the whole study of the rail scene's 7 designs, 10 torques and 40 speeds.

Run:  python benchmarks/bench_ltca.py [--repeats 5] [--out DIR] [--record]

Writes ``ltca.md`` into ``--out`` (default ``benchmarks/out/``, git-ignored) and prints it;
``--record`` writes into ``benchmarks/results/``.
"""

from __future__ import annotations

import math
import statistics

import numpy as np
from _timing import bench_args, output_dir, spread, timed  # noqa: E402

from gear_dyn.analysis.relief_study import relief_study
from gear_dyn.analysis.sweep import SweepOptions, sweep
from gear_dyn.geometry import GearPair, mesh_frequency
from gear_dyn.models.relief import slice_sdof
from gear_dyn.modification import recommended_relief
from gear_dyn.modification.analysis import rule_modifications
from gear_dyn.modification.lead import FlankModification, LeadModification, Misalignment
from gear_dyn.modification.slice_contact import SliceOptions, slice_contact
from gear_dyn.stiffness.iso6336 import iso6336_stiffness

RAIL = GearPair(23, 79, 6e-3, math.radians(20), 70e-3, math.radians(20), x1=0.3, x2=-0.1)
TORQUE = 2000.0
LADDER = np.linspace(200.0, 2000.0, 10)


def main(argv: list[str] | None = None) -> str:
    args = bench_args(__doc__.splitlines()[0], argv, repeats=5)
    mod = FlankModification(
        profile=recommended_relief(RAIL, TORQUE, "handbook").modification(),
        lead_pinion=LeadModification(crowning=8e-6), misalignment=Misalignment(f_ma=10e-6))
    opts = SliceOptions(slices=30, positions=32)
    slice_contact(RAIL, TORQUE, mod, options=opts)  # tooth tables built and cached
    one, ladder = [], []
    r1 = rl = None
    for _ in range(args.repeats):
        dt, r1 = timed(lambda: slice_contact(RAIL, TORQUE, mod, options=opts))
        one.append(dt * 1e3)
        dt, rl = timed(lambda: slice_contact(RAIL, LADDER, mod, options=opts))
        ladder.append(dt)
    assert r1 is not None and rl is not None
    lines = [
        "# Slice loaded tooth contact analysis (benchmarks/bench_ltca.py)",
        "",
        f"Rail pair, eps_alpha = {RAIL.contact_ratio:.4f}, eps_beta = {RAIL.overlap_ratio:.4f}; "
        "handbook tip relief, 8 um pinion crowning, f_ma = 10 um; 30 slices, 32 mesh positions "
        f"(+ the {r1.phase.size - 32} one-sided phases at the corners of the field of contact); "
        f"median of {args.repeats} runs (min..max), tooth tables cached.",
        "",
        "| case | wall time | target | active-set iterations |",
        "|---|---|---|---|",
        f"| one torque (2000 N m) | {spread(one, '.3g')} ms | 50 ms | {r1.iterations} |",
        f"| 10-torque ladder (200..2000 N m) | {spread(ladder, '.3g')} s | 0.5 s | "
        f"{rl.iterations} |",
        "",
        f"At 2000 N m: p-p static TE {r1.peak_to_peak_te[0] * 1e6:.3f} um, mean secant stiffness "
        f"{r1.mean_secant_stiffness[0]:.4g} N/m, peak Hertz pressure "
        f"{r1.max_pressure[0] / 1e6:.0f} MPa.",
        "",
        "## Convergence (unmodified pair, 2000 N m)",
        "",
        "| slices | positions | p-p static TE (um) | mean secant stiffness (N/m) "
        "| / ISO c_gamma b |",
        "|---|---|---|---|---|",
    ]
    iso = iso6336_stiffness(RAIL).k_mesh
    for s, p in ((30, 32), (60, 64), (120, 128), (240, 256)):
        r = slice_contact(RAIL, TORQUE, options=SliceOptions(slices=s, positions=p))
        lines.append(f"| {s} | {p} | {r.peak_to_peak_te[0] * 1e6:.4f} | "
                     f"{r.mean_secant_stiffness[0]:.5g} | {r.mean_secant_stiffness[0] / iso:.3f} |")
    lines += ["", "## Coupling decay length (unmodified pair, 2000 N m, 30 x 32)", "",
              "| lambda (mm) | p-p static TE (um) | mean secant stiffness (N/m) |",
              "|---|---|---|"]
    h = (2 * RAIL.addendum_coef + RAIL.clearance_coef) * RAIL.module
    for lam in (0.0, 0.5 * h / math.sqrt(2), h / math.sqrt(2), 2 * h / math.sqrt(2)):
        r = slice_contact(RAIL, TORQUE, options=SliceOptions(coupling_length=lam))
        lines.append(f"| {lam * 1e3:.2f} | {r.peak_to_peak_te[0] * 1e6:.4f} | "
                     f"{r.mean_secant_stiffness[0]:.5g} |")
    lines += speed_costs(mod, opts, args.repeats)
    text = "\n".join(lines) + "\n"
    out = output_dir(args) / "ltca.md"
    out.write_text(text)
    print(text)
    print(f"median one torque {statistics.median(one):.3g} ms; wrote {out}")
    return text


def speed_costs(mod: FlankModification, opts: SliceOptions, repeats: int) -> list[str]:
    """The per-speed table (see the module docstring)."""
    speeds = np.linspace(1000.0, 6000.0, 10) * math.pi / 30
    model, _ = slice_sdof(RAIL, float(speeds[0]), TORQUE, mod, options=opts)

    def at_speed(w: float):  # noqa: ANN202
        return model.at_mesh_frequency(mesh_frequency(RAIL, w))

    routes = {
        "loaded contact rebuilt per speed, steady":
            lambda: sweep(lambda w: slice_sdof(RAIL, w, TORQUE, mod, options=opts)[0], speeds),
        "built once, transient per speed (40 periods)":
            lambda: sweep(at_speed, speeds, options=SweepOptions(method="transient"),
                          periods=40, steady_periods=20),
        "built once, steady (periodic orbit)": lambda: sweep(at_speed, speeds),
        "built once, steady, 40 speeds": lambda: sweep(at_speed, fine),
    }
    fine = np.linspace(1000.0, 6000.0, 40) * math.pi / 30
    lines = ["", "## Single-DOF speed sweep on the slice loaded contact (2000 N m, 30 x 32)", "",
             f"10 speeds 1000..6000 rpm (40 in the last row), one design (handbook relief, "
             f"crowning, f_ma); median of {repeats} runs (min..max). A model rebuilt per speed "
             "has equal but not the same stiffness and TE objects, so the sweep cannot batch "
             "its speeds over one phase table (the vectorised Magnus step maps) and solves each "
             "orbit by a per-speed step map with sensitivities.", "",
             "| route | per speed | F_max / W at 6000 rpm |", "|---|---|---|"]
    for name, fn in routes.items():
        times, res = [], None
        for _ in range(repeats):
            dt, res = timed(fn)
            times.append(dt / (fine.size if "40" in name else speeds.size) * 1e3)
        lines.append(f"| {name} | {spread(times, '.3g')} ms | "
                     f"{res.curves[0].peak_force_ratio[-1]:.5f} |")
    designs = rule_modifications(RAIL, TORQUE)
    designs = {"scene relief": designs["handbook"], **designs}
    lead = FlankModification(lead_pinion=mod.lead_pinion, misalignment=mod.misalignment)
    study_speeds = np.linspace(1000.0, 6000.0, 40) * math.pi / 30
    times, study = [], None
    for _ in range(repeats):
        dt, study = timed(lambda: relief_study(RAIL, LADDER, designs, lead, options=opts,
                                               speeds=study_speeds, torque=TORQUE))
        times.append(dt)
    assert study is not None and study.dynamics is not None
    lines += ["", f"Whole relief study, {len(designs)} designs x 10 torques x 40 speeds: "
              f"{spread(times, '.3g')} s; lowest peak mesh force over the range: "
              f"{study.dynamics.best} (F_max / W = {study.dynamics.peak_over_range.min():.4f})."]
    return lines


if __name__ == "__main__":
    main()
