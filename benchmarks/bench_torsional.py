"""Eccentric torsional scene in process: the toolkit's path against a hand-written RK45 script.

Run:  python benchmarks/bench_torsional.py [--repeats 3] [--periods 630] [--out DIR] [--record]

On ``examples/scenes/eccentric_helical.toml`` (Liu et al. 2017: eccentric helical pair, contact
lines, friction, two-DOF torsional model; 630 mesh periods = one hunting period, 64 samples per
period), measured in one run and interleaved (hand, ours, hand, ours, ...):

1. what a user writes by hand: one ``solve_ivp(RK45)`` call over the whole span with a plain
   Python right-hand side that evaluates the eccentric kinematics and the contact lines at every
   call (``EccentricMesh.kinematics(t)``, ``line_state_scalar``), at its loosest rtol (of
   1e-9..1e-12) reaching max error <= 1e-6 of the static deflection;
2. the toolkit with ``method = "auto"`` (``gear-dyn run --method auto``): ``simulate`` picks
   ``gauss`` (Gauss-Legendre step maps of every output interval at once, coefficients from the
   table), incl. outputs and the stated error (a second run at rtol/100);
3. the same integration without the stated error (``integrate``);
4. DOP853 at the scene's rtol 1e-7 (``--method DOP853``; coefficients tabulated, restarted at
   every switching instant), incl. outputs and the stated error (the scene itself says auto);

and the ratios hand / ours pair by pair, as median (min..max). The reference is DOP853 at rtol
1e-13 restarted at every switching instant (contact lines entering, leaving and crossing the
pitch line), with the coefficients evaluated directly (no table) and steps <= 1/32 of the
natural period; its own error is its difference from the same run at rtol 1e-12. A convergence
table (DOP853 with the table, rtol 1e-7..1e-11) shows the error falling with rtol. Writes
``torsional.md`` into ``--out`` (default ``benchmarks/out/``, git-ignored); ``--record`` writes
into ``benchmarks/results/``.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import platform
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from _timing import spread, timed  # noqa: E402  (benchmarks/ is on sys.path)
from scipy.integrate import solve_ivp

from gear_dyn.analysis.accuracy import relative_errors
from gear_dyn.analysis.study import simulate
from gear_dyn.eccentricity.friction import line_state_scalar
from gear_dyn.scene import load_scene
from gear_dyn.scene.build import build_plan
from gear_dyn.solvers import SolverSettings, integrate, output_grid

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "examples" / "scenes" / "eccentric_helical.toml"
TARGET = 1e-6
HAND_RTOLS = (1e-9, 1e-10, 1e-11, 1e-12)
CONVERGENCE_RTOLS = (1e-7, 1e-8, 1e-9, 1e-10, 1e-11)






def hand_rhs(model: Any) -> Callable[[float, np.ndarray], list[float]]:
    """The right-hand side a user writes from the package's kinematics and contact lines."""
    mesh, lay, mu = model.mesh, model._layout, float(model.friction)
    k_l = model.stiffness.per_length
    rb1, rb2 = model.pair.rb1, model.pair.rb2
    i1, i2 = model.inertias
    t1, t2, c = model.torque, model.load, model.damping

    def rhs(t: float, y: np.ndarray) -> list[float]:
        kin = mesh.kinematics(float(t))
        total, _, p1, p2 = line_state_scalar(lay, kin, mu)
        d = rb1 * y[0] - rb2 * y[1] + kin.e_ecc
        dd = rb1 * y[2] - rb2 * y[3] + kin.e_ecc_rate
        f = k_l * total * d + c * dd
        n = max(f, 0.0)
        return [y[2], y[3], (t1 - rb1 * f + n * p1) / i1, (rb2 * f - t2 + n * p2) / i2]
    return rhs


def hand_solve(model: Any, t: np.ndarray, rtol: float) -> np.ndarray:
    sol = solve_ivp(hand_rhs(model), (0.0, float(t[-1])), model.initial_state(), method="RK45",
                    t_eval=t, rtol=rtol, atol=rtol * np.asarray(model.state_scale))
    return np.asarray(sol.y)


def reference(model: Any, t: np.ndarray) -> tuple[np.ndarray, float]:
    """DOP853 rtol 1e-13 (direct coefficients, steps <= T_n / 32) and its own error."""
    direct = dataclasses.replace(model, tabulate=False)
    cap = 1.0 / (32 * model.natural_frequency)
    y13 = integrate(direct, t, SolverSettings(method="DOP853", rtol=1e-13, max_step=cap))[0]
    y12 = integrate(direct, t, SolverSettings(method="DOP853", rtol=1e-12, max_step=cap))[0]
    return y13, relative_errors(model, t, y12, y13)[0]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--periods", type=int, default=630, help="mesh periods (scene: 630)")
    ap.add_argument("--out", type=Path, default=ROOT / "benchmarks" / "out")
    ap.add_argument("--record", action="store_true", help="write into benchmarks/results/")
    args = ap.parse_args(argv)
    plan = build_plan(load_scene(SCENE))
    model, settings = plan.model, plan.settings
    t_end = args.periods / model.mesh_frequency
    t = output_grid(model, t_end, settings)
    y_ref, ref_own = reference(model, t)

    def err(y: np.ndarray) -> float:
        return relative_errors(model, t, y, y_ref)[0]

    hand_rtol, hand_err = math.nan, math.nan
    for r in HAND_RTOLS:
        hand_err = err(hand_solve(model, t, r))
        print(f"hand RK45 rtol {r:g}: error {hand_err:.2e}", flush=True)
        if hand_err <= TARGET:
            hand_rtol = r
            break
    if not math.isfinite(hand_rtol):
        raise SystemExit(f"the hand-written RK45 does not reach {TARGET:g}")
    conv = []
    for r in CONVERGENCE_RTOLS:
        dt, (y, st) = timed(lambda r=r: integrate(model, t, SolverSettings(method="DOP853",
                                                                          rtol=r)))
        conv.append((r, err(y), int(st["nfev"]), dt))
        print(f"DOP853 + table rtol {r:g}: error {conv[-1][1]:.2e}", flush=True)
    auto = dataclasses.replace(settings, method="auto")
    dop = dataclasses.replace(settings, method="DOP853")
    res = simulate(model, t_end, auto)
    ours_err, stated = err(res.y), res.extra["estimated_error"]["max_rel"]
    res_d = simulate(model, t_end, dop)
    dop_err, dop_stated = err(res_d.y), res_d.extra["estimated_error"]["max_rel"]
    times: dict[str, list[float]] = {"hand": [], "ours": [], "solve": [], "dop": []}
    for _ in range(args.repeats):
        times["hand"].append(timed(lambda: hand_solve(model, t, hand_rtol))[0])
        times["ours"].append(timed(lambda: simulate(model, t_end, auto))[0])
        times["solve"].append(timed(lambda: integrate(model, t, auto))[0])
        times["dop"].append(timed(lambda: simulate(model, t_end, dop))[0])
    ratio = {k: [a / b for a, b in zip(times["hand"], times[k], strict=True)]
             for k in ("ours", "solve", "dop")}
    print(f"hand RK45 / simulate auto = {spread(ratio['ours'])}x, / integrate auto = "
          f"{spread(ratio['solve'])}x, / simulate DOP853 = {spread(ratio['dop'])}x "
          f"(errors {hand_err:.1e} / {ours_err:.1e} / {dop_err:.1e})")
    cmd = "python benchmarks/bench_torsional.py" + "".join(f" {a}" for a in
                                                          (argv or sys.argv[1:]))
    tab = model.coefficients
    lines = [
        "# Eccentric torsional scene: tabulated coefficients vs hand-written RK45", "",
        f"Produced by `{cmd}` on {platform.machine()} (Python {platform.python_version()}); "
        f"{args.repeats} interleaved runs, times as median (min..max); the ratios, pair by "
        "pair, are the figures to quote (shared 2-core machine).", "",
        f"Scene `examples/scenes/eccentric_helical.toml`, {args.periods} mesh periods "
        f"({t_end:.4g} s, {t.size} samples). Reference: DOP853 rtol 1e-13, direct coefficients, "
        f"restarted at every switching instant, steps <= T_n/32 (own error {ref_own:.1e}). "
        f"Target: max error <= {TARGET:g} of the static deflection.", "",
        "| path | rtol | max error | time (s) |", "|---|---|---|---|",
        f"| hand-written: solve_ivp RK45 once, kinematics + contact lines per call | "
        f"{hand_rtol:.0e} | {hand_err:.1e} | {spread(times['hand'])} |",
        f"| **method auto** (`simulate`, picks {res.stats.method}, incl. outputs and the stated "
        f"error {stated:.1e}) | {settings.rtol:.0e} | {ours_err:.1e} | "
        f"{spread(times['ours'])} |",
        f"| integration alone (`integrate`, auto = {res.stats.method}) | {settings.rtol:.0e} | "
        f"{ours_err:.1e} | {spread(times['solve'])} |",
        f"| `--method DOP853` (`simulate`, DOP853 + table, stated error {dop_stated:.1e}) | "
        f"{settings.rtol:.0e} | {dop_err:.1e} | {spread(times['dop'])} |", "",
        f"- hand-written RK45 / method auto: **{spread(ratio['ours'])}x**",
        f"- hand-written RK45 / integration alone (auto): {spread(ratio['solve'])}x",
        f"- hand-written RK45 / --method DOP853: {spread(ratio['dop'])}x",
        f"- interpolation error of the table (relative to x_s, x_s omega_n, k_m, r_b1, r_b2): "
        f"{', '.join(f'{v:.1e}' for v in tab.max_error)}", "",
        "## Error against rtol (DOP853 with the table, one run each)", "",
        "| rtol | max error | nfev | time (s) |", "|---|---|---|---|",
        *[f"| {r:.0e} | {e:.2e} | {n} | {dt:.3g} |" for r, e, n, dt in conv], "",
    ]
    out_dir = ROOT / "benchmarks" / "results" if args.record else args.out
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "torsional.md").write_text("\n".join(lines), encoding="utf-8")
    print(f"wrote {out_dir / 'torsional.md'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
