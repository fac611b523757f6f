"""``gear-dyn compare A.toml B.toml ... --speeds START:STOP:N --out DIR``: one sweep per scene,
one response plot with all of them, a table of peak factors (terminal, compare.csv, compare.json).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from gear_dyn.errors import InputError


def register(sub: Any) -> None:
    p = sub.add_parser(
        "compare", help="sweep several scenes over the same speeds and compare their peaks",
        description="Sweep every SCENE over the same pinion speeds (as gear-dyn sweep) and "
        "write into DIR: compare.png (dynamic factor K_dyn of all scenes against speed beside "
        "their ISO 6336-1 K_v, and RMS DTE; each peak starred), compare.csv and compare.json "
        "(per scene and direction: peak K_dyn and its speed, ISO K_v there, the peak force / W "
        "and the stiffness-jump factor beside it, peak RMS DTE, f_n, the speed where "
        "f_m = f_n). K_dyn = peak dynamic force / peak quasi-static force, as gear-dyn run "
        "states it. DIR is replaced as a whole only on success.",
        epilog="example: gear-dyn compare plain.toml relief.toml --speeds "
        "'1000 rpm:10000 rpm:181' --out cmp",
    )
    p.add_argument("scenes", type=Path, nargs="+", metavar="SCENE", help="scene files (TOML)")
    p.add_argument("--speeds", required=True, metavar="START:STOP:N",
                   help="pinion speeds, as for gear-dyn sweep ('500 rpm:6000 rpm:200')")
    p.add_argument("--out", type=Path, required=True, help="output folder")
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="each sweep on a pool of N local processes (default: serial)")
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    p.set_defaults(func=run)


def compare_rows(name: str, result: Any, scene: Any = None) -> list[dict[str, Any]]:
    """One row per sweep direction: peak dynamic factor K_dyn with its speed, ISO 6336-1 K_v
    there (with ``scene``; NaN without it or at zero load), the peak force / W and the
    stiffness-jump factor beside it, and the peak RMS DTE with its speed."""
    import numpy as np

    from gear_dyn.analysis.sweep import RPM, summarize_sweep

    summary = summarize_sweep(result)
    jump = summary["stiffness_jump_factor"]
    rows = []
    for d, info in summary["curves"].items():
        at = info.get("max_dynamic_factor_speed_rpm", float("nan"))
        kv = float("nan")
        if scene is not None and np.isfinite(at):
            from gear_dyn.scene.iso import iso_kv_at

            k = iso_kv_at(scene, np.array([at * RPM]))
            kv = float("nan") if k is None else float(np.asarray(k)[0])
        rows.append({
            "scene": name, "direction": d,
            "max_dynamic_factor": info.get("max_dynamic_factor", float("nan")),
            "max_dynamic_factor_speed_rpm": at,
            "iso_6336_kv_at_max": kv,
            "max_peak_force_ratio": info.get("max_peak_force_ratio", float("nan")),
            "stiffness_jump_factor": float("nan") if jump is None else jump,
            "max_rms_dte_m": info.get("max_rms_dte_m", float("nan")),
            "max_rms_dte_speed_rpm": info.get("max_rms_dte_speed_rpm", float("nan")),
            "natural_frequency_hz": summary["natural_frequency_hz"],
            "resonance_speed_rpm": summary["resonance_speed_rpm"],
            "unstable_speeds": int(np.sum([s == "unstable"
                                           for s in result.curve(d).status])),
            "speeds": int(result.curve(d).speed.size),
        })
    return rows


def run(args: argparse.Namespace) -> int:
    from gear_dyn.analysis.sweep import RPM
    from gear_dyn.cli.progress import counter
    from gear_dyn.io import save_figure, staged_output, write_csv, write_json
    from gear_dyn.plots.sweep import plot_compare
    from gear_dyn.scene import load_scene
    from gear_dyn.scene.sweep import parse_speed_range, sweep_scene

    scenes = [load_scene(p) for p in args.scenes]  # every file checked before any sweep
    speeds = parse_speed_range(args.speeds)
    names = [s.name for s in scenes]
    if len(set(names)) != len(names):
        names = [f"{s.name} ({p.name})" for s, p in zip(scenes, args.scenes, strict=True)]
        if len(set(names)) != len(names):
            raise InputError("compare: the same scene file given twice")
    results = []
    for name, scene in zip(names, scenes, strict=True):
        show = counter(f"{name} speed", args.quiet)
        results.append(sweep_scene(scene, speeds, si=True, workers=args.workers,
                                   progress=show))
    rows = [r for name, res, scene in zip(names, results, scenes, strict=True)
            for r in compare_rows(name, res, scene)]
    cols = {"scene_index": [float(names.index(r["scene"])) for r in rows],
            "direction_down": [float(r["direction"] == "down") for r in rows]}
    cols |= {k: [float(r[k]) for r in rows] for k in rows[0] if k not in ("scene", "direction")}
    legend = [f"# scene_index {i}: {n}" for i, n in enumerate(names)]
    with staged_output(args.out) as tmp:
        write_csv(tmp / "compare.csv", cols, comments=legend)
        write_json(tmp / "compare.json", {
            "scenes": names, "files": [str(p) for p in args.scenes],
            "speed_range_rpm": [float(speeds[0] / RPM), float(speeds[-1] / RPM)],
            "n_speeds": int(speeds.size), "peaks": rows})
        save_figure(plot_compare(results, names, iso_kv=[_kv_curve(s, speeds) for s in scenes]),
                    tmp / "compare.png", dpi=110)
    width = max(len(n) for n in names)
    heads = ("max K_dyn", "at rpm", "ISO K_v there", "F_max/W", "stiffness jump",
             "max RMS DTE (µm)", "at rpm")
    print(f"{'scene':<{width}}  dir  " + "  ".join(heads) + "  f_m = f_n at")
    for r in rows:
        values = (f"{r['max_dynamic_factor']:.4f}", f"{r['max_dynamic_factor_speed_rpm']:.0f}",
                  f"{r['iso_6336_kv_at_max']:.4f}", f"{r['max_peak_force_ratio']:.4f}",
                  f"{r['stiffness_jump_factor']:.4f}", f"{r['max_rms_dte_m'] * 1e6:.4g}",
                  f"{r['max_rms_dte_speed_rpm']:.0f}")
        cells = "  ".join(f"{v:>{len(h)}}" for v, h in zip(values, heads, strict=True))
        print(f"{r['scene']:<{width}}  {r['direction']:<4} {cells}  "
              f"{r['resonance_speed_rpm']:.0f} rpm")
    from gear_dyn.scene.build import build_pair, stiffness_choice_text

    for name, scene in zip(names, scenes, strict=True):
        print(f"{name} stiffness: {stiffness_choice_text(scene, build_pair(scene))}")
    print("K_dyn = peak dynamic mesh force / peak quasi-static mesh force of the same scene "
          "(tends to 1 at low speed, like ISO K_v); F_max/W = K_dyn x the stiffness-jump factor "
          "(the quasi-static force overshoot at the jumps of k(t))")
    print(f"wrote {args.out}/ (compare.png, compare.csv, compare.json)")
    return 0


def _kv_curve(scene: Any, speeds: Any) -> tuple[Any, Any] | None:
    """(rpm, ISO 6336-1 K_v) on a dense grid over the swept range, or None at zero load."""
    import numpy as np

    from gear_dyn.analysis.sweep import RPM
    from gear_dyn.scene.iso import iso_kv_at

    rpm = np.linspace(float(speeds[0] / RPM), float(speeds[-1] / RPM), 400)
    kv = iso_kv_at(scene, rpm * RPM)
    return None if kv is None else (rpm, np.asarray(kv))


__all__ = ["compare_rows", "register", "run"]
