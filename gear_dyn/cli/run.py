"""``gear-dyn run SCENE --out DIR``: simulate a scene, write plots, CSV and summary.json."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from gear_dyn.errors import InputError


def add_solver_flags(p: argparse.ArgumentParser) -> None:
    """The solver override flags shared by commands that integrate."""
    p.add_argument("--method", help="override [solver] method (auto, exact, exact_contact, "
                   "periodic, RK45, DOP853, Radau, BDF, LSODA)")
    p.add_argument("--rtol", type=float, help="override [solver] rtol")
    p.add_argument("--atol", type=float, help="override [solver] atol")
    p.add_argument("--periods", type=int, help="override [solver] periods (mesh periods)")
    add_budget_flag(p)


def add_budget_flag(p: argparse.ArgumentParser) -> None:
    """``--max-nfev N``: the work budget of a solve_ivp run (SolverSettings.max_nfev)."""
    p.add_argument("--max-nfev", type=int, default=None, metavar="N",
                   help="work budget of a solve_ivp run: right-hand-side evaluations "
                   "(default 5000000); a run that needs more stops with an error naming it")


def add_scene_and_out(p: argparse.ArgumentParser) -> None:
    """The SCENE argument and the required ``--out DIR`` of the commands that write a folder."""
    p.add_argument("scene", type=Path, help="scene file (TOML) or packaged scene name")
    p.add_argument("--out", type=Path, required=True, help="output folder")


def register(sub: Any) -> None:
    p = sub.add_parser(
        "run", help="simulate a scene and write plots, CSV and summary.json",
        description="Simulate SCENE and write into DIR: time_history.png (DTE and mesh force, "
        "steady window shaded; eccentric models: kinematic and elastic parts), spectrum.png "
        "(f_n, mesh harmonics, shaft frequencies and sidebands marked in Hz, the run's stated "
        "error as noise floor), timeseries.csv and summary.json. SCENE is a file or a packaged "
        "scene name (gear-dyn scenes). DIR is replaced as a whole only when everything succeeded.",
    )
    add_scene_and_out(p)
    p.add_argument("--speed", metavar="SPEED",
                   help='override [operating] speed, with its unit (e.g. "6000 rpm")')
    p.add_argument("--torque", metavar="TORQUE",
                   help='override [operating] torque, with its unit (e.g. "200 Nm")')
    p.add_argument("--spectrum-scale", choices=("log", "linear"), default="log",
                   help="amplitude axis of spectrum.png (default log)")
    add_solver_flags(p)
    p.set_defaults(func=run)


def overrides(args: argparse.Namespace) -> dict[str, Any]:
    """Solver overrides from the flags a command has, validated."""
    if args.periods is not None and args.periods < 2:
        raise InputError(f"--periods = {args.periods}: valid range >= 2 mesh periods")
    return {k: v for k in ("method", "rtol", "atol", "periods", "max_nfev")
            if (v := getattr(args, k, None)) is not None}


def run(args: argparse.Namespace) -> int:
    from gear_dyn.cli.output import write_run_outputs
    from gear_dyn.scene import load_scene, run_scene
    from gear_dyn.scene.operating import parse_operating

    scene = load_scene(args.scene)
    # read as the scene reads them: "--speed 6000" is refused with the readings it might mean
    speed = None if args.speed is None else parse_operating("speed", args.speed, "--speed")
    torque = None if args.torque is None else parse_operating("torque", args.torque, "--torque")
    result = run_scene(scene, speed=speed, torque=torque, si=True, **overrides(args))
    summary = write_run_outputs(result, args.out, spectrum_scale=args.spectrum_scale)
    print(f"{scene.name}: f_m = {summary['mesh_frequency_hz']:.1f} Hz{_fn(summary)}, dynamic "
          f"factor {summary['dynamic_factor']:.4f}, RMS DTE {summary['rms_dte_m'] * 1e6:.4g} "
          f"um ({summary['solver']['method']}, {summary['solver']['run_time_s']:.3g} s)")
    if summary.get("stiffness_choice"):
        print(f"  stiffness: {summary['stiffness_choice']}")
    print(f"  dynamic factor: {summary['dynamic_factor_definition']}")
    for line in jump_lines(summary):
        print(f"  {line}")
    if summary.get("iso_6336_kv"):
        from gear_dyn.scene.iso import iso_kv_lines

        for line in iso_kv_lines(summary["iso_6336_kv"]):
            print(f"  {line}")
    print(f"  {summary['dte_definition']}")
    for line in self_assessment_lines(summary):
        print(line)
    print(f"wrote {args.out}/")
    return 0


def jump_lines(summary: dict[str, Any]) -> list[str]:
    """The peak force over W and the stiffness-jump overshoot, beside the dynamic factor."""
    qs = summary.get("quasi_static")
    if not qs:
        return []
    jump = summary["stiffness_jump_factor"]
    name = ("stiffness-jump overshoot" if jump > 1 + qs["estimated_error"]
            else "no stiffness-jump overshoot")
    return [f"peak mesh force {summary['peak_force_ratio']:.4f} W = dynamic factor x "
            f"quasi-static peak {jump:.4f} W ({name}: the force overshoot at the jumps of "
            f"k(t), at any speed; quasi-static run at f_m = f_n x {qs['speed_ratio']:.3g}, "
            f"error {qs['estimated_error']:.1g})"]


def _fn(summary: dict[str, Any]) -> str:
    """``, f_n = 2913 Hz (f_m / f_n = 0.44)`` where the model has a natural frequency."""
    fn = summary.get("natural_frequency_hz")
    if not fn:
        return ""
    return f", f_n = {fn:.0f} Hz (f_m / f_n = {summary['mesh_frequency_hz'] / fn:.3g})"


def self_assessment_lines(summary: dict[str, Any]) -> list[str]:
    """What the run states about itself: its error (pointwise, or of its figures where the
    trajectory is not reproducible), contact loss, the orbit's stability, and its warnings."""
    lines = []
    est = summary.get("estimated_error")
    if isinstance(est, dict) and est.get("max_rel") is not None:
        if est.get("reproducible", True):
            lines.append(f"estimated error: {est['max_rel']:.2g} of the static deflection "
                         f"({est['basis']})")
        else:
            figs = ", ".join(f"{name.replace('_', ' ')} {err:.2g}"
                             for name, err in est.get("figures", {}).items())
            lines.append(f"estimated error of the figures (relative): {figs}")
    contact = summary.get("contact") or {}
    if "separation_share" in contact:
        sep, back = contact["separation_share"], contact["backside_share"]
        events = contact.get("n_contact_events")
        n = f", {events} contact changes in the run" if events is not None else ""
        lines.append("contact: " + (f"teeth apart {100 * sep:.3g} % and on the back flank "
                                    f"{100 * back:.3g} % of the steady window{n}"
                                    if sep > 0 or back > 0 else
                                    f"no contact loss in the steady window{n}"))
    orbit = summary.get("orbit")
    if orbit:
        lines.append(f"stability: {orbit['statement']}")
    for warning in summary.get("warnings") or []:
        lines.append(f"warning: {warning}")
    return lines
