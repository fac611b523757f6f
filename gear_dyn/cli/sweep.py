"""``gear-dyn sweep SCENE --speeds START:STOP:N --out DIR``: a speed sweep with plots, CSV, JSON."""

from __future__ import annotations

import argparse
import contextlib
from collections.abc import Iterator
from pathlib import Path
from typing import Any, cast

from gear_dyn.cli.progress import add_quiet_flag, counter
from gear_dyn.cli.run import add_scene_and_out, add_solver_flags, overrides
from gear_dyn.errors import InputError


def register(sub: Any) -> None:
    p = sub.add_parser(
        "sweep", help="sweep a scene over pinion speeds: dynamic factor, DTE, jumps, stability",
        description="Evaluate SCENE at N pinion speeds from START to STOP and write into DIR: "
        "response.png (dynamic factor K_dyn beside ISO 6336-1 K_v, peak force / W on its right "
        "axis, RMS and peak-to-peak DTE against speed and f_m/f_n; up "
        "and down sweeps for scenes with backlash; separation, back-side contact and "
        "instability marked), waterfall.png (DTE spectra over speed), with --chart stability.png "
        "(Floquet stability chart over f_m/f_n and stiffness variation or damping), "
        "sweep.csv, spectra.csv and sweep.json. K_dyn = peak dynamic mesh force / peak "
        "quasi-static mesh force, as gear-dyn run states it (one quasi-static run per sweep); "
        "the stiffness-jump factor (peak force / W = K_dyn x that factor) is printed beside it. "
        "DIR is replaced as a whole only on success.",
        epilog="examples: gear-dyn sweep scene.toml --speeds '500 rpm:12000 rpm:300' --out out; "
        "on a Dask cluster: --dask tcp://scheduler:8786",
    )
    add_scene_and_out(p)
    p.add_argument("--speeds", required=True, metavar="START:STOP:N",
                   help="pinion speeds: START and STOP with their units ('500 rpm', '50 rad/s', "
                   "'10 turn/s'; a plain number is refused); N points, linearly spaced")
    p.add_argument("--sweep-method", choices=("steady", "transient"), default="steady",
                   help="steady: periodic steady state from the monodromy matrix / shooting "
                   "(default); transient: integrate [solver] periods at every speed")
    p.add_argument("--direction", choices=("auto", "up", "down", "both"), default="auto",
                   help="auto (default): up and down with backlash, up otherwise")
    add_parallel_flags(p)
    p.add_argument("--block", type=int, default=None,
                   help="speeds per block (default: 8 with backlash; linear scenes about 20 "
                   "blocks of at least 32 speeds)")
    p.add_argument("--harmonics", type=int, default=5, help="mesh harmonics in the spectra")
    p.add_argument("--chart", choices=("stiffness", "damping", "both", "none"), default="none",
                   help="stability.png: Floquet stability charts over f_m/f_n and the stiffness "
                   "variation, the damping or both (default none: the response plot marks the "
                   "unstable speeds of the sweep itself)")
    add_quiet_flag(p, "--no-progress")
    add_solver_flags(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from gear_dyn.analysis.sweep import SweepOptions
    from gear_dyn.scene import load_scene
    from gear_dyn.scene.operating import parse_speed_range
    from gear_dyn.scene.sweep import sweep_scene

    scene = load_scene(args.scene)
    speeds = parse_speed_range(args.speeds)
    if args.workers is not None and not 1 <= args.workers <= 4096:
        raise InputError(f"--workers = {args.workers}: valid range 1..4096 processes")
    opts = SweepOptions(method=args.sweep_method, harmonics=args.harmonics)
    show = counter("speed", args.quiet)
    # one BLAS thread per process (and pool worker): gear_dyn.cli.app.limit_blas_threads
    with dask_executor(args.dask) as executor:
        result = sweep_scene(scene, speeds, si=True, options=opts, direction=args.direction,
                             workers=args.workers, executor=executor, block=args.block,
                             progress=show, **overrides(args))
    summary = write_sweep_outputs(result, scene, args.out, args.chart)
    _print_summary(result, scene, summary, args.chart)
    print(f"wrote {args.out}/")
    return 0


def add_parallel_flags(p: Any, what: str = "blocks of speeds", note: str = "") -> None:
    """``--workers N`` or ``--dask ADDRESS`` (one of them): where ``what`` runs."""
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, default=None, metavar="N",
                       help=f"run {what} on a pool of N local processes{note} (default: "
                       "serial, in this process); the results are the same")
    where.add_argument("--dask", metavar="ADDRESS", default=None,
                       help=f"run {what} on the Dask scheduler at ADDRESS (e.g. "
                       "tcp://host:8786; needs pip install \"gear_dyn[dask]\")")


@contextlib.contextmanager
def dask_executor(address: str | None) -> Iterator[Any]:
    """For the block, the executor of the Dask scheduler at ``address`` (None without one);
    a user mistake is an InputError."""
    if not address:
        yield None
        return
    try:
        from distributed import Client
    except ImportError:
        raise InputError('--dask needs the optional dask extra: pip install "gear_dyn[dask]"'
                         ) from None
    try:
        client = Client(address, timeout="20s")
    except (OSError, TimeoutError, ValueError) as exc:  # ValueError: a malformed address
        raise InputError(f"--dask {address}: cannot reach the scheduler ({exc})") from None
    with client:
        yield client.get_executor()


def _ranges(ranges: list[tuple[float, float]]) -> str:
    """Speed ranges in rpm, ``a-b`` (one speed alone as ``a``)."""
    return ", ".join(f"{a:.0f}" if round(a) == round(b) else f"{a:.0f}-{b:.0f}"
                     for a, b in ranges)


def _jump_text(j: dict[str, Any]) -> str:
    """One jump as ``6100 -> 6200 rpm (fold at 6111.8 rpm)``."""
    what = {"fold": f"fold at {j['fold_rpm']:.1f} rpm" if j["fold_rpm"] is not None else "fold",
            "contact_pattern": "onto an orbit with another contact pattern",
            "branch": "onto another branch", "unresolved": "continuation did not resolve it",
            "rms_fallback": "no orbit: RMS DTE changes > 30 %"}.get(j["kind"], j["kind"])
    return f"{j['from_rpm']:.0f} -> {j['to_rpm']:.0f} rpm ({what})"


def _print_summary(result: Any, scene: Any, summary: dict[str, Any], chart: str) -> None:
    """The sweep's terminal report: range, resonance, maximum dynamic factor, K_v, warnings."""
    print(f"{scene.name}: {summary['n_speeds']} speeds {summary['speed_range_rpm'][0]:.0f}-"
          f"{summary['speed_range_rpm'][1]:.0f} rpm in {result.run_time_s:.3g} s "
          f"({result.options.method}, {result.executor}); f_n = "
          f"{summary['natural_frequency_hz']:.0f} Hz, f_m = f_n at "
          f"{summary['resonance_speed_rpm']:.0f} rpm")
    from gear_dyn.scene.build import build_pair, stiffness_choice_text

    print(f"  stiffness: {stiffness_choice_text(scene, build_pair(scene))}")
    for note in summary.get("resonances_outside_range", []):
        print(f"  {note}")
    peaks = {d: info["max_dynamic_factor"] for d, info in summary["curves"].items()
             if "max_dynamic_factor" in info}
    for d in peaks:
        info = summary["curves"][d]
        share = info.get("max_dynamic_factor_separation_share", 0.0)
        if share > 0:
            what = "teeth separate" if result.nonlinear else "F < 0, linear model invalid"
            lost = f" - {what} over {share:.0%} of the mesh period there"
        else:
            lost = " (teeth in contact)"
        others = [v for k, v in peaks.items() if k != d]
        # the larger of the directions' peaks (none where they are equal)
        mark = " <- the larger" if others and peaks[d] > max(others) else ""
        kv = info.get("iso_6336_kv_at_max")
        beside = f", ISO K_v there {kv:.4f}" if kv is not None else ""
        print(f"  max dynamic factor K_dyn, sweep {d}: {info['max_dynamic_factor']:.4f} at "
              f"{info['max_dynamic_factor_speed_rpm']:.0f} rpm{beside}; peak force "
              f"{info['max_peak_force_ratio']:.4f} W{lost}{mark}")
    if peaks:
        for line in dynamic_factor_lines(summary):
            print(f"  {line}")
    if "iso_6336_kv_max" in summary:
        print(f"  ISO 6336-1 method B K_v: max {summary['iso_6336_kv_max']:.4f} over the range "
              "(column iso_6336_kv in sweep.csv, dash-dot line in response.png)")
    for d, info in summary["curves"].items():
        if info["separation_ranges_rpm"]:
            rng = _ranges(info["separation_ranges_rpm"])
            if result.nonlinear:
                print(f"  contact loss, teeth separate ({d}): {rng} rpm (column "
                      "separation_share in sweep.csv)")
            else:
                print(f"  negative mesh force ({d}): {rng} rpm - the linear model is invalid "
                      "there (the teeth would separate): add [backlash]")
        if info["unstable_ranges_rpm"]:
            rng = _ranges(info["unstable_ranges_rpm"])
            print(f"  parametric instability ({d}): {rng} rpm")
        if info["jumps"]:
            print(f"  jumps ({d}): " + "; ".join(_jump_text(j) for j in info["jumps"]))
        if info["aperiodic_ranges_rpm"]:
            rng = _ranges(info["aperiodic_ranges_rpm"])
            print(f"  no period-1 or period-2 orbit ({d}): {rng} rpm (aperiodic: not "
                  "periodic, so up and down are not compared there)")
    if summary["hysteresis_ranges_rpm"]:
        rng = _ranges(summary["hysteresis_ranges_rpm"])
        print(f"  hysteresis, up and down sweeps on different periodic orbits: {rng} rpm")
    for warning in result.warnings:
        print(f"  warning: {warning}")
    if chart == "none" and "stability_chart" not in summary:
        print("  Floquet stability charts around the scene: --chart both (stability.png)")


def dynamic_factor_lines(summary: dict[str, Any]) -> list[str]:
    """What the dynamic factor is, and the stiffness-jump factor beside it (not inside it)."""
    lines = [f"dynamic factor: {summary['dynamic_factor_definition']}"]
    qs = summary.get("quasi_static")
    jump = summary.get("stiffness_jump_factor")
    if qs and jump is not None:
        name = ("stiffness-jump overshoot" if jump > 1 + qs["estimated_error"]
                else "no stiffness-jump overshoot")
        lines.append(f"stiffness-jump factor {jump:.4f} = quasi-static peak force / W ({name}: "
                     "the force overshoot at the jumps of k(t), at any speed; one quasi-static "
                     f"run at f_m = f_n x {qs['speed_ratio']:.3g}, error "
                     f"{qs['estimated_error']:.1g}); peak force / W = K_dyn x {jump:.4f}")
    return lines


def write_sweep_outputs(result: Any, scene: Any, out: Path, chart: str = "both"
                        ) -> dict[str, Any]:
    """Write plots, CSV and sweep.json of a sweep into ``out`` (whole or not at all)."""
    import numpy as np

    from gear_dyn.analysis.chart import chart_summary, sweep_charts
    from gear_dyn.analysis.sweep import RPM
    from gear_dyn.analysis.sweep.types import spectra_columns
    from gear_dyn.io import save_figure, staged_output, write_csv, write_json
    from gear_dyn.models.base import MeshModel
    from gear_dyn.plots.sweep import plot_stability_charts, plot_sweep_response, plot_waterfall
    from gear_dyn.scene import build_model
    from gear_dyn.scene.iso import iso_kv_at

    summary = result.to_dict()
    speed = np.concatenate([c.speed for c in result.curves])  # rad/s, the order of the rows
    extra: dict[str, Any] = {}
    iso_curve = None
    if (kv := iso_kv_at(scene, speed)) is not None:  # the standard per speed
        extra["iso_6336_kv"] = kv
        rpm = np.linspace(float(np.min(speed / RPM)), float(np.max(speed / RPM)), 600)
        dense = np.asarray(iso_kv_at(scene, rpm * RPM))
        iso_curve = (rpm, dense)
        summary["iso_6336_kv_max"] = float(np.max(dense))
        for info in summary["curves"].values():  # K_v beside each peak K_dyn, at its speed
            if "max_dynamic_factor_speed_rpm" in info:
                at = iso_kv_at(scene, np.array([info["max_dynamic_factor_speed_rpm"] * RPM]))
                info["iso_6336_kv_at_max"] = float(np.asarray(at)[0])
    stability = None
    model = build_model(scene) if chart != "none" else None
    if model is not None and model.mesh_periodic:
        ratio = result.curves[0].mesh_frequency / result.natural_frequency
        lo, hi = float(np.min(ratio)), float(np.max(ratio))
        if found := sweep_charts(cast(MeshModel, model), lo, hi, chart):
            note = " (backlash ignored: full contact)" if model.backlash is not None else ""
            title = f"{result.scene_name}: Floquet stability{note}; black line |mu| = 1"
            stability = plot_stability_charts(found, sweep_range=(lo, hi), title=title)
            summary["stability_chart"] = chart_summary(found)
    with staged_output(out) as tmp:
        result.to_csv(tmp / "sweep.csv", extra)
        write_csv(tmp / "spectra.csv", spectra_columns(result))
        write_json(tmp / "sweep.json", summary)
        save_figure(plot_sweep_response(result, iso_kv=iso_curve), tmp / "response.png", dpi=110)
        for c in result.curves:
            name = "waterfall.png" if c is result.curves[0] else f"waterfall_{c.direction}.png"
            save_figure(plot_waterfall(result, c.direction), tmp / name, dpi=110)
        if stability is not None:
            save_figure(stability, tmp / "stability.png", dpi=110)
    return summary


__all__ = ["register", "run", "write_sweep_outputs"]
