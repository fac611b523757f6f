"""``gear-dyn relief SCENE``: recommended tip relief of a scene's pair by every rule, side by side.

Rules (docs/modification.md): gear handbook, Dudley and Niemann (as collected by Han, n.d.) and
Wang et al. (2024), eq. 1, at the scene's torque. The scene's ``[tip_relief]`` table, if present,
supplies the handbook constants and Dudley's C_m. ``--json PATH`` also writes the table as JSON.
"""

from __future__ import annotations

import argparse
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
    return {
        "scene": scene.name,
        "torque_n_m": torque,
        "tangential_force_n": torque / pair.r1,
        "load_per_width_n_per_mm": tangential_load_per_width(pair, torque),
        "contact_ratio": pair.contact_ratio,
        "base_pitch_m": pair.base_pitch,
        "rules": rows,
    }


def run(args: argparse.Namespace) -> int:
    from gear_dyn.io import write_json
    from gear_dyn.scene import load_scene

    with Stages(["load scene", "relief rules"], args.quiet) as st:
        scene = load_scene(args.scene)
        st.next()
        tab = table(scene)
    print(f"{tab['scene']}: T1 = {tab['torque_n_m']:.6g} N m, F_t = {tab['tangential_force_n']:.6g}"
          f" N, w_t = F_t/B = {tab['load_per_width_n_per_mm']:.6g} N/mm, eps_a = "
          f"{tab['contact_ratio']:.4f}")
    head = (f"{'rule':<10} {'C_a1 um':>8} {'C_a2 um':>8} {'h1 mm':>7} {'h2 mm':>7} "
            f"{'L1 mm':>7} {'L2 mm':>7}")
    print(head)
    print("-" * len(head))
    for r in tab["rules"]:
        print(f"{r['rule']:<10} {r['amount_pinion_m'] * 1e6:8.2f} {r['amount_gear_m'] * 1e6:8.2f} "
              f"{r['height_pinion_m'] * 1e3:7.3f} {r['height_gear_m'] * 1e3:7.3f} "
              f"{r['length_pinion_m'] * 1e3:7.3f} {r['length_gear_m'] * 1e3:7.3f}")
    print("h: radial height from the tip; L: length along the line of action")
    for r in tab["rules"]:
        print(f"  {r['rule']}: {r['source']}")
    if args.json is not None:
        write_json(args.json, tab)
        print(f"wrote {args.json}")
    return 0
