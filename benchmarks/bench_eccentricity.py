"""Figures of the eccentric pair (Liu et al. 2017) quoted in docs/eccentricity.md: costs, rigid
limit, mesh loss.

Usage: python benchmarks/bench_eccentricity.py [--repeats N] [--out FILE]
(default FILE: benchmarks/results/eccentricity.md)

1. Cost (median of --repeats runs): the excitation analysis of the eccentric scene (one hunting
   period, 64 samples per mesh period: kinematics, contact lines, friction, five spectra, peak
   labels), one scalar right-hand-side call of the torsional model (eccentricity + contact-line
   stiffness + friction), and a torsional run of 45 mesh periods (DOP853, rtol 1e-7).
2. Rigid limit: max |w2 - w2_kinematic| of the torsional model over 12..30 ms with a heavy input
   (I1 = 50 kg m^2) against the contact-line stiffness scale factor.
3. Mesh loss of the friction model (error-free pair): 1 - T2 w2 / (T1 w1) of the balanced load.
"""

from __future__ import annotations

import argparse
import platform
from pathlib import Path

import numpy as np
from _timing import median_time  # noqa: E402  (benchmarks/ is on sys.path)

from gear_dyn.analysis.study import simulate
from gear_dyn.cli.excitation import analyse
from gear_dyn.eccentricity import Eccentricity
from gear_dyn.models.torsional import ContactLineStiffness, TorsionalModel
from gear_dyn.scene import build_plan, load_scene
from gear_dyn.solvers import SolverSettings


def median_s(fn, repeats: int) -> float:  # type: ignore[no-untyped-def]
    """Median wall time of ``repeats`` calls in s."""
    return float(median_time(fn, repeats)[0])


ROOT = Path(__file__).resolve().parents[1]
SEED = ROOT / "examples" / "scenes" / "eccentric_helical.toml"
IDEAL = ROOT / "examples" / "scenes" / "eccentric_helical_ideal.toml"


def costs(repeats: int) -> list[str]:
    scene = load_scene(SEED)
    t_an = median_s(lambda: analyse(scene), repeats)
    plan = build_plan(scene, periods=45)
    model = plan.model
    y0 = model.initial_state()
    ts = np.linspace(1e-3, 2e-2, 2000)

    def rhs_loop() -> None:
        for t in ts:
            model.rhs(float(t), y0)
    t_rhs = median_s(rhs_loop, repeats) / ts.size
    stats: list[int] = []

    def run() -> None:
        r = simulate(model, plan.t_end, SolverSettings(method="DOP853", rtol=1e-7))
        stats.append(r.stats.nfev)
    t_run = median_s(run, repeats)
    return [
        "| task | median time |",
        "|---|---:|",
        f"| excitation analysis, 1 hunting period (1.4 s, 40320 samples, 5 spectra) | "
        f"{t_an:.3f} s |",
        f"| torsional rhs, one scalar call (eccentric, contact lines, friction) | "
        f"{t_rhs * 1e6:.1f} us |",
        f"| torsional run, 45 mesh periods (0.1 s), DOP853 rtol 1e-7, {stats[-1]} rhs calls | "
        f"{t_run:.2f} s |",
    ]


def rigid_limit() -> list[str]:
    scene = load_scene(SEED)
    base = build_plan(scene, periods=2).model
    assert isinstance(base, TorsionalModel)
    k_l = base.stiffness.per_length  # type: ignore[union-attr]
    lines = ["| stiffness factor | k_m (N/m) | f_n (Hz) | max abs(w2 - w2_kin) (rad/s) | "
             "ptp w2_kin (rad/s) |", "|---:|---:|---:|---:|---:|"]
    for factor in (0.3, 1.0, 3.0, 10.0):
        m = TorsionalModel(base.pair, base.speed, base.torque,
                           ContactLineStiffness(k_l * factor), (50.0, 0.069), damping_ratio=0.1,
                           eccentricity=Eccentricity(2e-4, 2e-4))
        r = simulate(m, 0.03, SolverSettings(method="DOP853", rtol=1e-8))
        sel = r.t > 0.012
        err = float(np.max(np.abs(r.outputs["w2"][sel] - r.outputs["w2_kinematic"][sel])))
        lines.append(f"| {factor:g} | {m.mean_stiffness:.3e} | {m.natural_frequency:.0f} | "
                     f"{err:.3e} | {np.ptp(r.outputs['w2_kinematic'][sel]):.3f} |")
    return lines


def mesh_loss() -> list[str]:
    m = build_plan(load_scene(IDEAL), periods=2).model
    assert isinstance(m, TorsionalModel)
    eff = m.load * m.speed * m.pair.z1 / m.pair.z2 / (m.torque * m.speed)
    return [f"mesh loss of the eccentric_helical_ideal pair, mu = {m.friction}: "
            f"{100 * (1 - eff):.3f} % "
            f"(W = {m.static_load:.2f} N, T2 = {m.load:.4f} N m vs T1 z2/z1 = "
            f"{m.torque * m.pair.z2 / m.pair.z1:.4f} N m)"]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", type=Path,
                    default=Path(__file__).resolve().parent / "out" / "eccentricity.md",
                    help="report file (default benchmarks/out/, git-ignored)")
    ap.add_argument("--record", action="store_true",
                    help="write the recorded results, benchmarks/results/eccentricity.md")
    args = ap.parse_args()
    text = "\n".join([
        "# Eccentric pair (Liu et al. 2017) / torsional model figures",
        "",
        f"Command: `python benchmarks/bench_eccentricity.py --repeats {args.repeats}`  ",
        f"Machine: {platform.machine()}, Python {platform.python_version()} (2 shared cores; "
        "times are medians and vary with the load of the machine)",
        "",
        "## Cost",
        "",
        *costs(args.repeats),
        "",
        "## Rigid limit (heavy input I1 = 50 kg m^2, I2 = 0.069 kg m^2, xi = 0.1, window "
        "12..30 ms)",
        "",
        *rigid_limit(),
        "",
        "## Friction",
        "",
        *mesh_loss(),
        "",
    ])
    if args.record:
        args.out = Path(__file__).resolve().parent / "results" / "eccentricity.md"
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text)
    print(text)


if __name__ == "__main__":
    main()
