"""``gear-dyn compare A.toml B.toml ... --speeds START:STOP:N --out DIR``: the designs swept over
the same speeds, ranked by peak force against the first (:func:`gear_dyn.compare_scenes`)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from gear_dyn.cli.run import add_budget_flag


def register(sub: Any) -> None:
    p = sub.add_parser(
        "compare", help="sweep several designs over the same speeds, rank them by peak force",
        description="Sweep every SCENE over the same pinion speeds (as gear-dyn sweep; each "
        "scene's operating speed added) and rank the designs by their peak dynamic mesh force "
        "over the static load, F_max / W; the first SCENE is the baseline. Writes into DIR: "
        "compare.json (per design the values at its operating speed and the peaks over the "
        "range with their speeds, for F_max / W, K_dyn, RMS DTE and the peak contact stress "
        "where known; the differences from the baseline, absolute and in per cent; the ranks; "
        "flags: a peak at an end of the range, a linear model's mesh force negative at its "
        "peak), compare.csv (the same, one row per design in rank order) and compare.png. "
        "K_dyn = peak dynamic / peak quasi-static force of the same design, kept as a column: "
        "it does not rank designs. DIR is replaced as a whole only on success.",
        epilog="example: gear-dyn compare plain.toml relief.toml --speeds "
        "'1000 rpm:10000 rpm:181' --out cmp",
    )
    p.add_argument("scenes", type=Path, nargs="+", metavar="SCENE",
                   help="scene files (TOML) or packaged scene names; the first is the baseline")
    p.add_argument("--speeds", required=True, metavar="START:STOP:N",
                   help="pinion speeds, as for gear-dyn sweep ('500 rpm:6000 rpm:200')")
    p.add_argument("--out", type=Path, required=True, help="output folder")
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="each sweep on a pool of N local processes (default: serial)")
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    add_budget_flag(p)
    p.set_defaults(func=run)


def table_lines(comparison: Any) -> list[str]:
    """The ranked table for the terminal, its legend and the warnings."""
    import math

    rows = comparison.rows()
    width = max(len(r["scene"]) for r in rows)

    def num(v: float, fmt: str, scale: float = 1.0) -> str:
        return format(v * scale, fmt) if math.isfinite(v) else "-"
    heads = ("F/W peak", "at rpm", "vs base", "F/W oper.", "vs base", "RMS DTE um", "vs base",
             "sigma_H MPa", "K_dyn", "flags")
    lines = [f"{'#':>2} {'design':<{width}}  " + "  ".join(heads)]
    for r in rows:
        cells = (num(r["peak_peak_force_ratio"], ".4f"),
                 num(r["peak_peak_force_ratio_speed_rpm"], ".0f"),
                 num(r["peak_peak_force_ratio_delta_pct"], "+.1f") + " %",
                 num(r["operating_peak_force_ratio"], ".4f"),
                 num(r["operating_peak_force_ratio_delta_pct"], "+.1f") + " %",
                 num(r["peak_rms_dte_m"], ".4g", 1e6),
                 num(r["peak_rms_dte_m_delta_pct"], "+.1f") + " %",
                 num(r["peak_contact_stress_pa"], ".0f", 1e-6),
                 num(r["peak_dynamic_factor"], ".4f"), r["flags"] or "-")
        text = "  ".join(f"{c:>{len(h)}}" for c, h in zip(cells, heads, strict=True))
        lines.append(f"{r['rank'] or '-':>2} {r['scene']:<{width}}  {text}")
    lines.append(f"ranked by the peak mesh force over the static load, F/W (lower first); "
                 f"'vs base': change from the baseline {comparison.baseline!r}; 'oper.': at the "
                 "design's operating speed; sigma_H: peak Hertz contact stress (quasi-static "
                 "x sqrt(K_dyn), '-' where not known); K_dyn = peak dynamic / peak "
                 "quasi-static force of the same design (does not rank designs)")
    lines += [f"warning: {w}" for w in comparison.warnings]
    return lines


def run(args: argparse.Namespace) -> int:
    from gear_dyn.cli.progress import counter
    from gear_dyn.io import save_figure, staged_output, write_json
    from gear_dyn.scene import load_scene
    from gear_dyn.scene.compare import compare_scenes

    scenes = [load_scene(p) for p in args.scenes]  # every file checked before any sweep
    names = [s.name for s in scenes]
    if len(set(names)) != len(names):
        names = [f"{s.name} ({p.name})" for s, p in zip(scenes, args.scenes, strict=True)]
    budget = {} if args.max_nfev is None else {"max_nfev": args.max_nfev}
    comparison = compare_scenes(scenes, args.speeds, names=names, workers=args.workers,
                                progress=lambda name: counter(f"{name} speed", args.quiet),
                                **budget)
    with staged_output(args.out) as tmp:
        write_json(tmp / "compare.json", {**comparison.to_dict(),
                                          "files": [str(p) for p in args.scenes]})
        comparison.to_csv(tmp / "compare.csv")
        save_figure(comparison.plot(), tmp / "compare.png", dpi=110)
    print("\n".join(table_lines(comparison)))
    from gear_dyn.scene.build import build_pair, stiffness_choice_text

    for name, scene in zip(names, scenes, strict=True):
        print(f"{name} stiffness: {stiffness_choice_text(scene, build_pair(scene))}")
    print(f"wrote {args.out}/ (compare.png, compare.csv, compare.json)")
    return 0


__all__ = ["register", "run", "table_lines"]
