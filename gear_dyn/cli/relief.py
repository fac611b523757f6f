"""``gear-dyn relief SCENE``: recommended tip relief of a scene's pair by every rule, side by side.

Rules (docs/modification.md): gear handbook, Dudley and Niemann (as collected by Han, n.d.) and
Wang et al. (2024), eq. 1, at the scene's torque. The scene's ``[tip_relief]`` table, if present,
supplies the handbook constants and Dudley's C_m. ``--json PATH`` also writes the table as JSON.
For a helical pair the rules (all written for spur gears) are applied in the transverse section,
and the output states what they assume there (:func:`helical_caveat`), with the amounts normal to
the flank beside the transverse ones.
"""

from __future__ import annotations

import argparse
import math
from dataclasses import asdict
from pathlib import Path
from typing import Any

from gear_dyn.cli.progress import Stages, add_quiet_flag


def register(sub: Any) -> None:
    p = sub.add_parser(
        "relief", help="recommended tip relief by the handbook, Dudley, Niemann and Wang et al. "
        "(2024) rules",
        description="Print the tip relief (amount, radial height, length along the line of "
        "action, for pinion and gear) that each published rule recommends for SCENE's pair at "
        "its torque.",
    )
    p.add_argument("scene", type=Path, help="scene file (TOML)")
    p.add_argument("--json", type=Path, default=None, help="also write the table to this file")
    add_quiet_flag(p)
    p.set_defaults(func=run)


def table(scene: Any) -> dict[str, Any]:
    """The rules' recommendations for the scene as a JSON-ready dict (SI units in key names)."""
    from gear_dyn.modification.relief import recommended_reliefs, tangential_load_per_width
    from gear_dyn.scene import build_pair
    from gear_dyn.scene.modification import rule_options

    pair = build_pair(scene)
    torque = scene.get("operating")["torque"]
    opts = rule_options(scene.tables["tip_relief"]) if scene.has("tip_relief") else {}
    # the recommendation's fields, those in m named with _m
    rows = [{k if k in ("rule", "source") else f"{k}_m": v for k, v in asdict(rec).items()}
            for rec in recommended_reliefs(pair, torque, **opts)]
    if pair.helix_angle != 0.0:  # the amounts normal to the flank: transverse x cos(beta_b)
        cos_bb = math.cos(pair.beta_b)
        for row in rows:
            row["amount_normal_pinion_m"] = row["amount_pinion_m"] * cos_bb
            row["amount_normal_gear_m"] = row["amount_gear_m"] * cos_bb
    return {
        "scene": scene.name,
        "torque_n_m": torque,
        "tangential_force_n": torque / pair.r1,
        "load_per_width_n_per_mm": tangential_load_per_width(pair, torque),
        "contact_ratio": pair.contact_ratio,
        "overlap_ratio": pair.overlap_ratio,
        "base_pitch_m": pair.base_pitch,
        "rules": rows,
        "helical_caveat": helical_caveat(pair),
    }


def helical_caveat(pair: Any) -> list[str]:
    """What the spur rules assume, said for a helical pair (empty for a spur pair).

    The rules size a relief for the sudden entry of a contact line as wide as the face at the
    gear tip: a spur pair's total contact-line length L(t) jumps between B and 2 B (for
    1 < eps_a < 2). A helical pair's lines enter the field of contact gradually; its L(t)
    (:func:`gear_dyn.stiffness.contact_line.contact_line_length`, Liu et al. 2017) varies by
    far less. The rules' inputs are transverse: ``w_t = F_t / B`` with the transverse F_t at the
    reference circle, the long relief ``(eps_a - 1) p_bt`` from the transverse contact ratio and
    base pitch, heights and lengths in the transverse section. A relief amount along the
    transverse line of action is ``cos(beta_b)`` times that amount normal to the flank.
    """
    if pair.helix_angle == 0.0:
        return []
    from gear_dyn.stiffness.contact_line import (
        contact_line_breakpoints,
        contact_line_length,
        mean_contact_line_length,
    )

    # L(t) of a helical pair is continuous and linear between its breakpoints: its extremes
    length = contact_line_length(pair, contact_line_breakpoints(pair))
    mean = mean_contact_line_length(pair)
    swing = (float(length.max()) - float(length.min())) / mean
    beta = math.degrees(pair.beta)
    return [
        f"helical pair (beta = {beta:.4g} deg, eps_beta = {pair.overlap_ratio:.4g}): these are "
        "spur rules, applied in the transverse section. They assume:",
        "  - a contact line as wide as the face entering at once at the tip (the impact a "
        "relief softens): a spur pair's contact-line length jumps between B and 2 B; here the "
        f"lines enter gradually and L(t) swings by {swing:.1%} of its mean "
        f"{mean * 1e3:.4g} mm over a mesh cycle (spur pair of this eps_a: "
        f"{1 / pair.contact_ratio:.1%})",
        "  - the transverse load w_t = F_t/B (F_t at the reference circle), the long relief "
        "(eps_a - 1) p_bt from the transverse eps_a and p_bt; h and L in the transverse section",
        f"  - amounts C_a along the transverse line of action; normal to the flank they are "
        f"C_a cos(beta_b) = {math.cos(pair.beta_b):.4f} C_a (columns Cn)",
        "  check a relief for this pair by its loaded contact (transmission error and load "
        "over the face), not by these rules alone",
    ]


def run(args: argparse.Namespace) -> int:
    from gear_dyn.io import write_json
    from gear_dyn.scene import load_scene

    with Stages(["load scene", "relief rules"], args.quiet) as st:
        scene = load_scene(args.scene)
        st.next()
        tab = table(scene)
    helical = bool(tab["helical_caveat"])
    eps_b = f", eps_b = {tab['overlap_ratio']:.4f}" if helical else ""
    print(f"{tab['scene']}: T1 = {tab['torque_n_m']:.6g} N m, F_t = {tab['tangential_force_n']:.6g}"
          f" N, w_t = F_t/B = {tab['load_per_width_n_per_mm']:.6g} N/mm, eps_a = "
          f"{tab['contact_ratio']:.4f}{eps_b}")
    head = (f"{'rule':<10} {'C_a1 um':>8} {'C_a2 um':>8} {'h1 mm':>7} {'h2 mm':>7} "
            f"{'L1 mm':>7} {'L2 mm':>7}")
    if helical:
        head += f" {'Cn1 um':>7} {'Cn2 um':>7}"
    print(head)
    print("-" * len(head))
    for r in tab["rules"]:
        row = (f"{r['rule']:<10} {r['amount_pinion_m'] * 1e6:8.2f} "
               f"{r['amount_gear_m'] * 1e6:8.2f} {r['height_pinion_m'] * 1e3:7.3f} "
               f"{r['height_gear_m'] * 1e3:7.3f} {r['length_pinion_m'] * 1e3:7.3f} "
               f"{r['length_gear_m'] * 1e3:7.3f}")
        if helical:
            row += (f" {r['amount_normal_pinion_m'] * 1e6:7.2f} "
                    f"{r['amount_normal_gear_m'] * 1e6:7.2f}")
        print(row)
    print("h: radial height from the tip; L: length along the line of action"
          + (" (transverse); Cn: amount normal to the flank" if helical else ""))
    for r in tab["rules"]:
        print(f"  {r['rule']}: {r['source']}")
    for line in tab["helical_caveat"]:
        print(line)
    if args.json is not None:
        write_json(args.json, tab)
        print(f"wrote {args.json}")
    return 0
