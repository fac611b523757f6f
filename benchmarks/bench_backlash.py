"""Backlash scene in process: ``run_scene`` (auto = exact_contact) against hand-written RK45.

Run:  python benchmarks/bench_backlash.py [--repeats 5] [--out DIR] [--record]

On ``examples/scenes/helicopter_tail_backlash.toml`` (200 mesh periods, 64 samples per period),
measured in one run and interleaved (hand, ours, hand, ours, ...):

1. what a user writes by hand: one ``solve_ivp(RK45)`` call over the whole span, plain Python
   right-hand side with the dead zone, at its loosest rtol (of 1e-6..1e-11) reaching max error
   <= 1e-6 of the static deflection;
2. the default path of ``gear-dyn run``: ``run_scene(scene)`` (auto = ``exact_contact``, incl.
   model build, outputs and the stated error);
3. the toolkit's previous default for backlash: LSODA restarted at switches and contact changes,
   at its loosest rtol reaching the target;

and the ratios hand / ours, LSODA / ours pair by pair, as median (min..max). The reference is
DOP853 restarted at every stiffness switch and contact change at rtol 1e-13
(``gear_dyn.analysis.bench.reference_solution``), whose own error is stated too. The same scene
at the mesh resonance (f_m = f_n, where the teeth separate every period) is measured the same
way. Writes ``backlash.md`` into ``--out`` (default ``benchmarks/out/``, git-ignored);
``--record`` writes into ``benchmarks/results/``.
"""

from __future__ import annotations

import platform
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from _timing import bench_args, output_dir, spread, timed  # noqa: E402  (benchmarks/ is on sys.path)
from scipy.integrate import solve_ivp

from gear_dyn.analysis.accuracy import relative_errors
from gear_dyn.analysis.bench import reference_solution
from gear_dyn.analysis.study import simulate
from gear_dyn.scene import load_scene
from gear_dyn.scene.build import build_plan
from gear_dyn.solvers import SolverSettings, integrate, output_grid

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "examples" / "scenes" / "helicopter_tail_backlash.toml"
TARGET = 1e-6
RTOLS = (1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11)






def hand_solve(model: Any, t: np.ndarray, rtol: float) -> np.ndarray:
    """What a user writes: the dead zone by ``if``, one RK45 call over the span."""
    edges, values = model.stiffness.segments()
    f_switch, k_hi, k_lo = float(edges[1]), float(values[0]), float(values[1])
    m, c, w, fm, b = (model.mass, model.damping, model.static_load, model.mesh_frequency,
                      model.backlash)

    def rhs(tt: float, y: np.ndarray) -> list[float]:
        k = k_hi if (fm * tt) % 1.0 < f_switch else k_lo
        x = y[0]
        fx = x - b if x > b else (x + b if x < -b else 0.0)
        return [y[1], (w - c * y[1] - k * fx) / m]

    sol = solve_ivp(rhs, (0.0, float(t[-1])), model.initial_state(), method="RK45", t_eval=t,
                    rtol=rtol, atol=rtol * np.asarray(model.state_scale))
    return np.asarray(sol.y)


def loosest(run: Callable[[float], np.ndarray], model: Any, t: np.ndarray,
            y_ref: np.ndarray) -> tuple[float, float]:
    for rtol in RTOLS:
        err = relative_errors(model, t, run(rtol), y_ref)[0]
        if err <= TARGET:
            return rtol, err
    raise SystemExit(f"does not reach {TARGET:g} at rtol {RTOLS[-1]:g}")


def bench_case(label: str, model: Any, t_end: float, settings: SolverSettings, repeats: int
               ) -> dict[str, Any]:
    t = output_grid(model, t_end, settings)
    ref = reference_solution(model, t)
    hand_rtol, hand_err = loosest(lambda r: hand_solve(model, t, r), model, t, ref.y)

    def lsoda(r: float) -> np.ndarray:
        return integrate(model, t, SolverSettings(method="LSODA", rtol=r))[0]
    ls_rtol, ls_err = loosest(lsoda, model, t, ref.y)

    def ours() -> Any:
        return simulate(model, t_end, settings)
    res = ours()
    err = relative_errors(model, t, res.y, ref.y)[0]
    times: dict[str, list[float]] = {"hand": [], "ours": [], "lsoda": []}
    for _ in range(repeats):
        times["hand"].append(timed(lambda: hand_solve(model, t, hand_rtol))[0])
        times["ours"].append(timed(ours)[0])
        times["lsoda"].append(timed(lambda: lsoda(ls_rtol))[0])
    return {"label": label, "method": res.stats.method, "err": err,
            "stated": res.extra["estimated_error"]["max_rel"],
            "hand_rtol": hand_rtol, "hand_err": hand_err, "ls_rtol": ls_rtol,
            "ls_err": ls_err, "ref": ref.kind, "ref_own": ref.own_error, "times": times,
            "r_hand": [a / b for a, b in zip(times["hand"], times["ours"], strict=True)],
            "r_lsoda": [a / b for a, b in zip(times["lsoda"], times["ours"], strict=True)]}


def report(rows: list[dict[str, Any]], repeats: int) -> str:
    out = ["# Backlash: closed form between located contact changes vs hand-written RK45", "",
           f"Produced by `python benchmarks/bench_backlash.py --repeats {repeats}` on "
           f"{platform.machine()} (Python {platform.python_version()}); {repeats} interleaved "
           "runs, times as median (min..max); the ratios, pair by pair, are the figures to "
           "quote (shared 2-core machine).", ""]
    for r in rows:
        tm = r["times"]
        out += [f"## {r['label']}", "",
                f"Reference: {r['ref']} (own error {r['ref_own']:.1e}). Target: max error <= "
                f"{TARGET:g} of the static deflection.", "",
                "| path | rtol | max error | time (s) |", "|---|---|---|---|",
                f"| hand-written: solve_ivp RK45 once, plain Python rhs | {r['hand_rtol']:.0e} | "
                f"{r['hand_err']:.1e} | {spread(tm['hand'])} |",
                f"| **default path** (`run_scene`/`simulate`, auto = {r['method']}, stated error "
                f"{r['stated']:.1e}) | - | {r['err']:.1e} | {spread(tm['ours'])} |",
                f"| LSODA restarted at switches and contact changes | {r['ls_rtol']:.0e} | "
                f"{r['ls_err']:.1e} | {spread(tm['lsoda'])} |", "",
                f"- hand-written RK45 / default path: **{spread(r['r_hand'])}x**",
                f"- LSODA restarted / default path: {spread(r['r_lsoda'])}x", ""]
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    args = bench_args(__doc__.splitlines()[0], argv, repeats=5)
    plan = build_plan(load_scene(SCENE))
    model = plan.model
    resonant = model.at_mesh_frequency(model.natural_frequency)
    rows = [bench_case("helicopter_tail_backlash scene (200 mesh periods)", model, plan.t_end,
                       plan.settings, args.repeats),
            bench_case("same pair at the mesh resonance f_m = f_n (200 mesh periods)", resonant,
                       200 / resonant.mesh_frequency, plan.settings, args.repeats)]
    for r in rows:
        print(f"{r['label']}: hand RK45 / ours = {spread(r['r_hand'])}x, LSODA / ours = "
              f"{spread(r['r_lsoda'])}x (errors {r['hand_err']:.1e} / {r['err']:.1e})")
    out_dir = output_dir(args)
    (out_dir / "backlash.md").write_text(report(rows, args.repeats))
    print(f"wrote {out_dir / 'backlash.md'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
