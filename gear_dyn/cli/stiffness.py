"""``gear-dyn stiffness SCENE --out DIR``: mesh stiffness of a scene's pair by several methods.

Writes ``stiffness.png``, ``components.png``, ``stiffness.csv`` and ``stiffness.json`` into DIR
(whole or not at all; contents in docs/stiffness.md, "Command").
"""

from __future__ import annotations

import argparse
from typing import Any

from gear_dyn.choices import STIFFNESS_METHODS as METHODS
from gear_dyn.cli.progress import Stages, add_quiet_flag
from gear_dyn.cli.run import add_scene_and_out
from gear_dyn.errors import InputError


def register(sub: Any) -> None:
    p = sub.add_parser(
        "stiffness", help="mesh stiffness of a scene's gear pair by several methods",
        description="Compute the mesh stiffness of SCENE's pair by the chosen methods and write "
        "stiffness.png, components.png, stiffness.csv and stiffness.json into DIR. The scene's "
        "[stiffness] options apply to every method that takes them. The terminal gives eps_alpha "
        "and eps_beta, each method's mean and its ratio to ISO 6336-1 c_gamma b, and what each "
        "method includes and leaves out (the spread between methods).",
    )
    add_scene_and_out(p)
    p.add_argument("--methods", default="scene,iso6336,potential_energy,weber,contact_line",
                   help="comma-separated methods among " + ", ".join(METHODS) + " and 'scene' "
                   "(the scene's own method); default: %(default)s")
    p.add_argument("--cycles", type=float, default=2.0, help="mesh cycles plotted (default 2)")
    p.add_argument("--samples", type=int, default=400,
                   help="phase samples per cycle in stiffness.csv (default 400)")
    add_quiet_flag(p)
    p.set_defaults(func=run)


def _methods(text: str, scene_method: str) -> list[str]:
    names = [scene_method if n == "scene" else n for n in (r.strip() for r in text.split(","))
             if n]
    for name in names:
        if name not in METHODS:
            raise InputError(f"--methods: {name!r} is not a stiffness method; valid: "
                             f"{', '.join(METHODS)}, scene")
    if not names:
        raise InputError("--methods: give at least one method")
    return list(dict.fromkeys(names))  # each once, in the order given


def compute(scene: Any, methods: list[str]) -> tuple[Any, dict[str, Any], dict[str, Any]]:
    """``(pair, curves, report)`` for ``methods`` on the scene's pair (no files written)."""
    from gear_dyn.analysis.stiffness import compare_methods
    from gear_dyn.scene import build_pair
    from gear_dyn.scene.build import stiffness_choice_text
    from gear_dyn.stiffness.select import stiffness_options_from_table

    pair = build_pair(scene)
    table = dict(scene.get("stiffness"))
    try:
        scene_method, scene_opts = stiffness_options_from_table(table, pair)
        curves, report = compare_methods(pair, methods, scene_method, scene_opts,
                                         table.get("fourier_terms"))
    except InputError as exc:
        raise InputError(f"{scene.source}: {exc}") from None
    return pair, curves, {"scene": scene.name, "scene_stiffness": stiffness_choice_text(
        scene, pair), **report}


def run(args: argparse.Namespace) -> int:
    from gear_dyn.scene import build_pair, load_scene
    from gear_dyn.scene.build import scene_stiffness_choice

    if not (args.cycles > 0 and args.cycles <= 1000):
        raise InputError(f"--cycles = {args.cycles}: valid range 0 < cycles <= 1000")
    if args.samples < 4:
        raise InputError(f"--samples = {args.samples}: valid range >= 4")
    with Stages(["load scene", "stiffness curves", "write"], args.quiet) as st:
        scene = load_scene(args.scene)
        methods = _methods(args.methods, scene_stiffness_choice(scene, build_pair(scene)).method)
        st.next()
        pair, curves, report = compute(scene, methods)
        st.next()
        _write(args, pair, curves, report)
    for line in report_lines(report):
        print(line)
    print(f"wrote {args.out}/")
    return 0


def report_lines(report: dict[str, Any]) -> list[str]:
    """The terminal report: eps_alpha and eps_beta, the scene's stiffness and why, then per
    method its mean, min and max, the ratio of its mean to ISO 6336-1 c_gamma b, and what it
    includes and leaves out."""
    op = report["operating"]
    iso = report["iso6336"]["k_mesh_n_per_m"]
    lines = [f"{report['scene']}: eps_alpha = {op['contact_ratio']:.4f}, eps_beta = "
             f"{op['overlap_ratio']:.4f}, single-contact share {op['single_contact_share']:.3f}"
             f", backlash {_um(op['backlash_m'])} um",
             f"  scene stiffness: {report['scene_stiffness']}",
             f"  mean mesh stiffness by method (ratio to ISO 6336-1 c_gamma b = {iso:.4g} N/m):"]
    for name, s in report["methods"].items():
        lines.append(f"  {name:17s} mean {s['mean_n_per_m']:.4g} N/m = {s['ratio_to_iso']:.3f} "
                     f"x ISO  (min {s['min_n_per_m']:.4g}, max {s['max_n_per_m']:.4g} N/m, "
                     f"{s['build_time_s'] * 1e3:.3g} ms)")
        lines.append(f"    includes: {s['includes']}")
        lines.append(f"    leaves out: {s['leaves_out']}")
    return lines


def _write(args: argparse.Namespace, pair: Any, curves: dict[str, Any],
           report: dict[str, Any]) -> None:
    import numpy as np

    from gear_dyn.io import save_figure, staged_output, write_csv, write_json
    from gear_dyn.plots.stiffness import plot_components, plot_stiffness_curves

    comp = report.pop("_components")
    with staged_output(args.out) as tmp:
        fig = plot_stiffness_curves(curves, pair.contact_ratio, cycles=args.cycles,
                                    transverse_note=pair.helix_angle != 0.0)
        save_figure(fig, tmp / "stiffness.png", dpi=110)
        fig = plot_components(comp, title="potential-energy compliance split at the pitch point "
                              f"(K = {1 / float(comp.total[0]):.4g} N/m)")
        save_figure(fig, tmp / "components.png", dpi=110)
        p = np.arange(args.samples) / args.samples
        cols: dict[str, Any] = {"phase_cycles": p}
        for name, k in curves.items():
            cols[f"k_{name.replace(' ', '_')}_n_per_m"] = k(p)
        write_csv(tmp / "stiffness.csv", cols)
        write_json(tmp / "stiffness.json", report)


def _um(x: float) -> str:
    """Micrometres with 3 decimals, without a sign on a rounded zero ("-0.000")."""
    v = round(x * 1e6, 3)
    return f"{v + 0.0:.3f}"  # -0.0 + 0.0 is 0.0
