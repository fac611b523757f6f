"""``gear-dyn contact SCENE --out DIR``: loaded contact with tip relief, per relief rule.

Writes ``face_load.png`` (the slice loaded contact over the face and the path of contact),
``stiffness.png``, ``ltca.csv`` and ``contact.json`` into DIR (whole or not at all); a spur pair
without lead modifications or misalignment also ``load_sharing.png`` and ``path.csv`` of the
spur loaded contact, whose rows ``contact.json`` then reports; with ``--dynamics`` also
``dynamics.png`` and ``dynamics.json``: the unmodified pair, the scene's ``[tip_relief]`` if
any, and every relief rule, each with the scene's lead modifications and misalignment
(docs/modification.md).
"""

from __future__ import annotations

import argparse
from typing import Any

from gear_dyn.choices import PAIR_STIFFNESS_METHODS, RELIEF_CURVES
from gear_dyn.cli.progress import Stages, add_quiet_flag
from gear_dyn.cli.run import add_budget_flag, add_scene_and_out
from gear_dyn.errors import InputError


def register(sub: Any) -> None:
    p = sub.add_parser(
        "contact", help="loaded contact with tip relief: load sharing, contact stress, K_TPM",
        description="Loaded-contact analysis of SCENE's pair (spur or helical) at its torque: "
        "the unmodified pair, the scene's [tip_relief] (if any) and the published relief "
        "rules, each with the scene's [lead_modification] and [misalignment]. Writes "
        "face_load.png, stiffness.png, ltca.csv and contact.json into DIR (spur pairs without "
        "lead modification or misalignment also load_sharing.png and path.csv).",
    )
    add_scene_and_out(p)
    p.add_argument("--curve", choices=RELIEF_CURVES, default=None,
                   help="relief curve for the rules (default: the scene's tip_relief.curve, "
                   "else linear)")
    p.add_argument("--pair-stiffness", choices=PAIR_STIFFNESS_METHODS, default=None,
                   help="unmodified single-pair stiffness (default: the scene's "
                   "tip_relief.pair_stiffness, else potential_energy)")
    p.add_argument("--dynamics", action="store_true",
                   help="also run the single-DOF model of every case (slower)")
    add_budget_flag(p)
    add_quiet_flag(p)
    p.set_defaults(func=run)


def compute(scene: Any, curve: str | None = None, pair_method: str | None = None) -> dict[
        str, Any]:
    """The relief cases of a scene (unmodified, scene relief, rules) without writing files:
    the slice loaded contact of every case (``ltca``) and, for a spur pair without lead
    modifications or misalignment, the spur loaded contact (``cases``, else empty)."""
    from gear_dyn.modification.analysis import relief_case, rule_modifications, slice_cases
    from gear_dyn.scene import build_pair
    from gear_dyn.scene.lead import SLICE_TABLES, flank_from_scene, slice_options_from_scene
    from gear_dyn.scene.modification import relief_from_scene, rule_options, scene_pair_function

    pair = build_pair(scene)
    torque = scene.get("operating")["torque"]
    if not torque > 0:
        raise InputError(f"{scene.source}: operating.torque = 0: the loaded contact needs a load")
    opts: dict[str, float] = {}
    extra = {}
    t = scene.tables.get("tip_relief")
    if t is not None:
        opts = rule_options(t)
        extra["scene relief"] = relief_from_scene(scene, pair)
    curve = curve or (t["curve"] if t is not None else "linear")
    method = pair_method or (t["pair_stiffness"] if t is not None else "potential_energy")
    fn = scene_pair_function(scene, pair, method)  # its errors name the scene already
    slice_mode = pair.helix_angle != 0.0 or any(scene.has(n) for n in SLICE_TABLES)
    flank = flank_from_scene(scene, pair)
    try:
        designs = rule_modifications(pair, torque, curve, extra, opts)
        ltca = slice_cases(pair, torque, designs, flank, fn, slice_options_from_scene(scene))
        cases = {} if slice_mode else {name: relief_case(name, pair, fn, torque, mod)
                                       for name, mod in designs.items()}
    except InputError as exc:
        raise InputError(f"{scene.source}: {exc}") from None
    return {"pair": pair, "cases": cases, "ltca": ltca, "slice_mode": slice_mode,
            "curve": curve, "pair_stiffness": method, "fn": fn, "torque": torque,
            "flank": flank}


def _dynamics(scene: Any, res: dict[str, Any], stage: Any = None,
              max_nfev: int | None = None) -> tuple[dict[str, Any], dict[str, Any]]:
    """Single-DOF run of every case with the scene's damping, inertias and [solver] settings."""
    from gear_dyn.analysis.study import simulate
    from gear_dyn.models.relief import relief_sdof, slice_sdof
    from gear_dyn.scene.build import scene_inertias
    from gear_dyn.solvers import MAX_NFEV, SolverSettings

    pair = res["pair"]
    op = scene.get("operating")
    sv = scene.get("solver")
    method = sv["method"] if sv["method"] not in ("auto", "exact") else "DOP853"
    try:
        settings = SolverSettings(method=method, rtol=sv["rtol"], atol=sv["atol"],
                                  samples_per_period=sv["samples_per_period"],
                                  max_nfev=MAX_NFEV if max_nfev is None else max_nfev)
    except InputError as exc:
        raise InputError(f"{scene.source}: {exc}") from None
    periods = sv["periods"]
    steady = sv["steady_periods"] or periods // 2
    dyn: dict[str, Any] = {}
    results: dict[str, Any] = {}
    for i, (name, case) in enumerate((res["cases"] or res["ltca"]).items()):
        if stage is not None and i > 0:
            stage.next()  # one stage per case (the first started on entering)
        if res["slice_mode"]:
            model, _ = slice_sdof(pair, op["speed"], op["torque"], case.modification, res["fn"],
                                  scene.get("damping")["ratio"], scene_inertias(scene),
                                  case.contact.options)
        else:
            model, _ = relief_sdof(pair, op["speed"], op["torque"], case.modification,
                                   res["fn"], scene.get("damping")["ratio"],
                                   scene_inertias(scene))
        fm = model.mesh_frequency
        r = simulate(model, periods / fm, settings, (periods - steady) / fm)
        results[name] = r
        # designs of one pair compare by their peak force: relief lowers the jump overshoot
        dyn[name] = {"peak_force_ratio": r.peak_force_ratio, "dynamic_factor": r.dynamic_factor,
                     "stiffness_jump_factor": r.extra.get("stiffness_jump_factor"),
                     "rms_dte_m": r.rms_dte,
                     "ptp_dte_m": r.ptp_dte, "mean_dte_m": r.mean_dte,
                     "solver": r.stats.as_dict()}
    return dyn, results


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from gear_dyn.io import save_figure, staged_output, write_csv, write_json
    from gear_dyn.plots.contact import (
        plot_load_sharing,
        plot_loaded_stiffness,
        plot_slice_stiffness,
    )
    from gear_dyn.scene import load_scene

    names = ["load scene", "loaded contact"]
    with Stages(names, args.quiet) as st:  # the dynamics get their own stages below
        scene = load_scene(args.scene)
        st.next()
        res = compute(scene, args.curve, args.pair_stiffness)
    cases, ltca = res["cases"], res["ltca"]
    pair = res["pair"]
    rows = [c.row() for c in (cases or ltca).values()]
    report: dict[str, Any] = {
        "scene": scene.name, "torque_n_m": res["torque"], "normal_load_n": res["torque"] / pair.rb1,
        "normal_load_along_flank_n": res["torque"] / (pair.rb1 * np.cos(pair.beta_b)),
        "curve_for_rules": res["curve"], "pair_stiffness": res["pair_stiffness"],
        "method": "slice LTCA" if res["slice_mode"] else "spur loaded contact",
        "start_of_contact_m": pair.start_of_contact, "end_of_contact_m": pair.end_of_contact,
        "base_pitch_m": pair.base_pitch, "contact_ratio": pair.contact_ratio,
        "overlap_ratio": pair.overlap_ratio,
        "positions": "m from T1 along the line of action (*_from_a_m: from the start of contact)",
        "cases": rows,
        "ltca": {name: c.contact.to_dict() for name, c in ltca.items()},
    }
    dyn: dict[str, Any] = {}
    results: dict[str, Any] = {}
    if args.dynamics:
        with Stages([f"dynamics: {name}" for name in (cases or ltca)], args.quiet) as st:
            dyn, results = _dynamics(scene, res, st, args.max_nfev)
    first = next(iter(ltca.values())).contact
    table: dict[str, Any] = {"phase": first.phase}
    for name, c in ltca.items():
        key = name.replace(" ", "_")
        for col, values in c.contact.position_table().items():
            if col not in ("torque_n_m", "phase"):
                table[f"{key}_{col}"] = values
    featured = ltca.get("scene relief") or next(iter(ltca.values()))
    with staged_output(args.out) as tmp:
        save_figure(featured.contact.plot(title=featured.name), tmp / "face_load.png",
                    dpi=120)
        write_csv(tmp / "ltca.csv", table)
        if cases:
            cols: dict[str, Any] = {}
            for name, c in cases.items():
                key = name.replace(" ", "_")
                cols |= {f"{key}_{col}": v for col, v in c.path_columns().items()}
            n = max(len(v) for v in cols.values())
            cols = {k: np.concatenate([v, np.full(n - len(v), np.nan)]) for k, v in cols.items()}
            save_figure(plot_load_sharing(cases), tmp / "load_sharing.png", dpi=120)
            save_figure(plot_loaded_stiffness(cases), tmp / "stiffness.png", dpi=120)
            write_csv(tmp / "path.csv", cols)
        else:
            save_figure(plot_slice_stiffness(ltca), tmp / "stiffness.png", dpi=120)
        write_json(tmp / "contact.json", report)
        if results:
            from gear_dyn.plots.contact import plot_dynamic_comparison

            save_figure(plot_dynamic_comparison(results), tmp / "dynamics.png", dpi=120)
            write_json(tmp / "dynamics.json", dyn)
    how = (f"slice LTCA, {first.options.slices} slices x {first.phase.size} positions"
           if res["slice_mode"] else "spur loaded contact")
    print(f"{scene.name}: loaded contact at T1 = {res['torque']:.6g} N m ({how}; "
          f"{res['pair_stiffness']} pair stiffness, rules with {res['curve']} relief)")
    if res["slice_mode"]:
        print(f"  eps_alpha = {pair.contact_ratio:.4f}, eps_beta = {pair.overlap_ratio:.4f}")
    zone_head = "max share" if res["slice_mode"] else "single zone from A (mm)"
    head = (f"{'case':<14} {'C_a1 um':>8} {'C_a2 um':>8} {'peak MPa':>9} {'ptp TE um':>10} "
            f"{zone_head:>24}" + (f" {'F_max/W':>8}" if dyn else ""))
    print(head)
    for row in report["cases"]:
        z0, z1 = row["single_contact_start_from_a_m"], row["single_contact_end_from_a_m"]
        if res["slice_mode"]:
            zone = f"{row['max_sharing']:.3f}"
        else:
            zone = "none" if z0 is None else f"{z0 * 1e3:.3f} .. {z1 * 1e3:.3f}"
        line = (f"{row['case']:<14} {row['amount_pinion_m'] * 1e6:8.2f} "
                f"{row['amount_gear_m'] * 1e6:8.2f} {row['peak_stress_pa'] / 1e6:9.1f} "
                f"{row['peak_to_peak_static_te_m'] * 1e6:10.3f} {zone:>24}")
        if dyn:
            line += f" {dyn[row['case']]['peak_force_ratio']:8.3f}"
        print(line)
    print(f"wrote {args.out}/")
    return 0
