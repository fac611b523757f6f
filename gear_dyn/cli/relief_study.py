"""``gear-dyn relief-study SCENE --out DIR [--torques START:STOP:N]``: relief designs ranked over
a torque range by the slice loaded contact.

The designs are the unmodified pair, the scene's ``[tip_relief]`` (if any) and every published
rule (at the scene's torque, with the scene's curve), each with the scene's lead modifications
and misalignment. Writes ``study.png`` (PPTE and peak contact pressure against torque; with
``--speeds`` also peak mesh force and p-p DTE against speed), ``study.csv``, ``study.json``
(and ``dynamics.csv`` with ``--speeds``) into DIR (whole or not at all) and prints the ranking
(docs/modification.md, "Relief design study").
"""

from __future__ import annotations

import argparse
from typing import Any

from gear_dyn.choices import RELIEF_CURVES
from gear_dyn.cli.run import add_scene_and_out
from gear_dyn.errors import InputError


def register(sub: Any) -> None:
    p = sub.add_parser(
        "relief-study", help="tip-relief designs ranked by PPTE and contact pressure over a "
        "torque range (slice loaded contact)",
        description="Slice loaded contact of SCENE's pair (spur or helical) for the unmodified "
        "pair, the scene's [tip_relief] and the published rules over a torque range: "
        "peak-to-peak static TE and peak Hertz pressure against torque, and the design with "
        "the lowest PPTE over the range. Writes study.png, study.csv and study.json into DIR.",
        epilog="example: gear-dyn relief-study rail.toml --torques '200 N*m:2000 N*m:10' "
        "--out out",
    )
    add_scene_and_out(p)
    p.add_argument("--torques", default=None, metavar="START:STOP:N",
                   help="pinion torques with their units, N linearly spaced (default: 10 %% .. "
                   "100 %% of the scene's torque, 10 points)")
    p.add_argument("--speeds", default=None, metavar="START:STOP:N",
                   help="pinion speeds with their units, e.g. '1000 rpm:6000 rpm:40': each "
                   "design's peak mesh force F_max / W and p-p DTE over the range at the "
                   "scene's torque (single-DOF periodic steady state; default: off)")
    p.add_argument("--curve", choices=RELIEF_CURVES, default=None,
                   help="relief curve for the rules (default: the scene's tip_relief.curve, "
                   "else linear)")
    p.set_defaults(func=run)


def parse_torques(text: str | None, scene_torque: float) -> Any:
    """Torques in N m from ``START:STOP:N`` (each end with its unit), or the default ladder
    (an ndarray)."""
    import numpy as np

    from gear_dyn.scene.operating import parse_operating

    if text is None:
        if not scene_torque > 0:
            raise InputError("operating.torque = 0: give --torques START:STOP:N")
        return np.linspace(0.1 * scene_torque, scene_torque, 10)
    parts = text.split(":")
    if len(parts) != 3:
        raise InputError(f"--torques {text!r}: expected START:STOP:N, e.g. "
                         "'200 N*m:2000 N*m:10'")
    ends = [parse_operating("torque", part.strip(), f"--torques {label}")
            for label, part in zip(("START", "STOP"), parts[:2], strict=True)]
    try:
        n = int(parts[2])
    except ValueError:
        raise InputError(f"--torques N = {parts[2]!r}: expected a whole number >= 1") from None
    if not 1 <= n <= 1000:
        raise InputError(f"--torques N = {n}: valid range 1 .. 1000")
    t = np.linspace(ends[0], ends[1], n)
    if np.any(t <= 0):
        raise InputError(f"--torques {text!r}: every torque must be > 0 N*m")
    return t


def compute(scene: Any, torques: str | None = None, curve: str | None = None,
            speeds: str | None = None) -> Any:
    """The :class:`~gear_dyn.modification.analysis.ReliefStudy` of a scene."""
    from gear_dyn.analysis.relief_study import relief_study
    from gear_dyn.modification.analysis import rule_modifications
    from gear_dyn.scene import build_pair
    from gear_dyn.scene.build import scene_inertias
    from gear_dyn.scene.lead import flank_from_scene, slice_options_from_scene
    from gear_dyn.scene.modification import relief_from_scene, rule_options, scene_pair_function
    from gear_dyn.scene.operating import parse_speed_range

    pair = build_pair(scene)
    torque = scene.get("operating")["torque"]
    try:
        ladder = parse_torques(torques, torque)
        sp = None if speeds is None else parse_speed_range(speeds)
    except InputError as exc:
        raise InputError(f"{scene.source}: {exc}") from None
    t = scene.tables.get("tip_relief")
    extra = {"scene relief": relief_from_scene(scene, pair)} if t is not None else {}
    curve = curve or (t["curve"] if t is not None else "linear")
    fn = scene_pair_function(scene, pair)
    rule_torque = torque if torque > 0 else float(ladder[-1])
    try:
        designs = rule_modifications(pair, rule_torque, curve, extra,
                                     rule_options(t) if t is not None else None)
        return relief_study(pair, ladder, designs, flank_from_scene(scene, pair), fn,
                            slice_options_from_scene(scene), speeds=sp, torque=rule_torque,
                            damping_ratio=scene.get("damping")["ratio"],
                            inertias=scene_inertias(scene))
    except InputError as exc:
        raise InputError(f"{scene.source}: {exc}") from None


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from gear_dyn.io import save_figure, staged_output, write_json
    from gear_dyn.scene import load_scene

    scene = load_scene(args.scene)
    study = compute(scene, args.torques, args.curve, args.speeds)
    pair = next(iter(study.cases.values())).contact.pair
    report = {"scene": scene.name, "contact_ratio": pair.contact_ratio,
              "overlap_ratio": pair.overlap_ratio, **study.to_dict()}
    with staged_output(args.out) as tmp:
        save_figure(study.plot(), tmp / "study.png", dpi=120)
        study.to_csv(tmp / "study.csv")
        write_json(tmp / "study.json", report)
        if study.dynamics is not None:
            study.dynamics.to_csv(tmp / "dynamics.csv")
    t = study.torque
    print(f"{scene.name}: relief designs over T1 = {t[0]:.6g} .. {t[-1]:.6g} N m "
          f"({t.size} torques; eps_alpha = {pair.contact_ratio:.4f}, "
          f"eps_beta = {pair.overlap_ratio:.4f})")
    print(f"{'design':<14} {'mean PPTE um':>12} {'max PPTE um':>12} {'PPTE at max T':>14} "
          f"{'peak MPa at max T':>18}")
    order = np.argsort(study.ppte.mean(axis=1))
    for i in order:
        name = study.names[i]
        print(f"{name:<14} {study.ppte[i].mean() * 1e6:12.3f} {study.ppte[i].max() * 1e6:12.3f} "
              f"{study.ppte[i, -1] * 1e6:14.3f} {study.peak_pressure[i, -1] / 1e6:18.1f}")
    print(f"best (lowest PPTE over the range): {study.best}")
    d = study.dynamics
    if d is not None:
        rpm = d.speed * 30 / np.pi
        print(f"dynamics at T1 = {d.torque:.6g} N m over {rpm[0]:.6g} .. {rpm[-1]:.6g} rpm "
              f"({d.speed.size} speeds; single-DOF periodic steady state)")
        print(f"{'design':<14} {'max F/W':>12} {'max p-p DTE um':>15}")
        for i in np.argsort(d.peak_over_range):
            print(f"{d.names[i]:<14} {d.peak_over_range[i]:12.4f} "
                  f"{d.ptp_dte[i].max() * 1e6:15.3f}")
        print(f"lowest peak mesh force over the speed range: {d.best}")
    print(f"wrote {args.out}/")
    return 0
