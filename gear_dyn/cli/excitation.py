"""``gear-dyn excitation SCENE --out DIR``: the excitations of Liu et al. (2017) (eccentricity,
friction, contact lines) and their labelled spectra.

At constant input speed and normal load ``W = T1 / r_b1``, over whole hunting periods: w2(t),
L(t) and (with ``[friction]``) the friction force and torques; writes ``excitation_time.png``,
``excitation_spectrum.png``, ``excitation.csv`` and ``peaks.json`` (docs/eccentricity.md).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from gear_dyn.cli.progress import Stages, add_quiet_flag
from gear_dyn.cli.run import add_scene_and_out


def register(sub: Any) -> None:
    p = sub.add_parser(
        "excitation", help="eccentricity and friction excitations with labelled spectra",
        description="Excitations of SCENE after Liu et al. (2017) (tables [eccentricity], "
        "[friction]): driven speed, contact-line length, friction force and torque over whole "
        "hunting periods; writes excitation_time.png, excitation_spectrum.png, excitation.csv "
        "and peaks.json into DIR (replaced as a whole only when everything succeeded).",
    )
    add_scene_and_out(p)
    p.add_argument("--periods", type=int, default=1,
                   help="hunting periods analysed (default 1; both gears return to the start)")
    p.add_argument("--samples-per-mesh", type=int, default=64,
                   help="samples per mesh period (default 64)")
    p.add_argument("--peaks", type=int, default=30, help="peaks listed per signal (default 30)")
    add_quiet_flag(p)
    p.set_defaults(func=run)


def analyse(scene: Any, periods: int = 1, samples_per_mesh: int = 64,
            n_peaks: int = 30) -> dict[str, Any]:
    """Signals, spectra and labelled peaks of a scene: the scene's parts handed to
    :func:`gear_dyn.analysis.excitation.analyse_excitation`."""
    from gear_dyn.analysis.excitation import analyse_excitation
    from gear_dyn.eccentricity.kinematics import Eccentricity
    from gear_dyn.scene import build_pair
    from gear_dyn.scene.eccentricity import scene_eccentricity, scene_friction

    op = scene.get("operating")
    res = analyse_excitation(build_pair(scene), op["speed"], op["torque"],
                             scene_eccentricity(scene) or Eccentricity(), scene_friction(scene),
                             periods=periods, samples_per_mesh=samples_per_mesh,
                             n_peaks=n_peaks)
    res["report"] = {"scene": scene.name, **res["report"]}
    return res


def run(args: argparse.Namespace) -> int:
    from gear_dyn.scene import load_scene

    with Stages(["load scene", "excitation and spectra", "write"], args.quiet) as st:
        scene = load_scene(args.scene)
        st.next()
        res = analyse(scene, args.periods, args.samples_per_mesh, args.peaks)
        st.next()
        _write(args.out, res)
    for name, pk in res["peaks"].items():
        top = ", ".join(f"{p['label'] or '?'} {p['frequency_hz']:.2f} Hz" for p in pk[:6])
        print(f"{name}: {top or 'constant (no peaks)'}")
    print(f"wrote {args.out}")
    return 0


def _write(out: Path, res: dict[str, Any]) -> None:
    from gear_dyn.io import save_figure, staged_output, write_csv, write_json
    from gear_dyn.plots.excitation import plot_excitation_spectra, plot_excitation_time

    with staged_output(out) as tmp:
        write_csv(tmp / "excitation.csv", {"t_s": res["t"], **res["series"]})
        fig = plot_excitation_time(res["t"], res["series"], res["basis"])
        save_figure(fig, tmp / "excitation_time.png", dpi=110)
        fig = plot_excitation_spectra(res["spectra"], res["peaks"], res["basis"])
        save_figure(fig, tmp / "excitation_spectrum.png", dpi=110)
        write_json(tmp / "peaks.json", res["report"])
