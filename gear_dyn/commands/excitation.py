"""``gear-dyn excitation SCENE --out DIR``: seed 000's excitations and their labelled spectra.

Computes, for the scene's pair at constant input speed and constant normal load
``W = T1 / r_b1``, the driven speed w2(t), the contact-line length L(t) and (with a
``[friction]`` table) the friction force and friction torques over whole hunting periods; writes
``excitation_time.png``, ``excitation_spectrum.png`` (shaft frequencies, mesh harmonics and
sidebands labelled), ``excitation.csv`` and ``peaks.json`` (the labelled peaks of each signal).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError


def register(sub: Any) -> None:
    p = sub.add_parser(
        "excitation", help="eccentricity and friction excitations with labelled spectra",
        description="Seed 000 excitations of SCENE (tables [eccentricity], [friction]): driven "
        "speed, contact-line length, friction force and torque over whole hunting periods; "
        "writes excitation_time.png, excitation_spectrum.png, excitation.csv and peaks.json "
        "into DIR (replaced as a whole only when everything succeeded).",
    )
    p.add_argument("scene", type=Path, help="scene file (TOML)")
    p.add_argument("--out", type=Path, required=True, help="output folder")
    p.add_argument("--periods", type=int, default=1,
                   help="hunting periods analysed (default 1; both gears return to the start)")
    p.add_argument("--samples-per-mesh", type=int, default=64,
                   help="samples per mesh period (default 64)")
    p.add_argument("--peaks", type=int, default=30, help="peaks listed per signal (default 30)")
    p.set_defaults(func=run)


def analyse(scene: Any, periods: int = 1, samples_per_mesh: int = 64,
            n_peaks: int = 30) -> dict[str, Any]:
    """Signals, spectra and labelled peaks of a scene (the API behind the command).

    Returns
    -------
    dict
        ``t``, ``series`` (name -> array), ``spectra`` (name -> (f, amp)), ``peaks``
        (name -> list of dicts), ``basis`` and ``report`` (the JSON-ready summary).
    """
    from ..eccentricity.kinematics import Eccentricity, EccentricMesh
    from ..eccentricity.scene import scene_eccentricity, scene_friction
    from ..eccentricity.signals import excitation_signals
    from ..scene import build_pair
    from ..spectrum import amplitude_spectrum
    from ..spectrum_labels import Basis, labelled_peaks

    if n_peaks < 1:
        raise InputError(f"--peaks = {n_peaks}: valid range >= 1")
    pair = build_pair(scene)
    op = scene.get("operating")
    ecc = scene_eccentricity(scene) or Eccentricity()
    mu = scene_friction(scene)
    mesh = EccentricMesh(pair, ecc, op["speed"])
    load = op["torque"] / pair.rb1
    sig = excitation_signals(mesh, load, mu, periods=periods, samples_per_mesh=samples_per_mesh)
    series: dict[str, np.ndarray] = {"w2": sig.w2, "contact_length": sig.contact_length}
    if sig.friction_force is not None:
        assert sig.friction_torque_pinion is not None and sig.friction_torque_gear is not None
        series["friction_force"] = sig.friction_force
        series["friction_torque_pinion"] = sig.friction_torque_pinion
        series["friction_torque_gear"] = sig.friction_torque_gear
    basis = Basis.of_pair(pair.z1, pair.z2, op["speed"])
    units = {"w2": "rad/s", "contact_length": "m", "friction_force": "N",
             "friction_torque_pinion": "N*m", "friction_torque_gear": "N*m"}
    spectra: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    peaks: dict[str, list[dict[str, Any]]] = {}
    table: dict[str, Any] = {}
    for name, x in series.items():
        f, a = amplitude_spectrum(sig.t, x)
        spectra[name] = (f, a)
        # a constant signal (w2 without eccentricity) has no peaks: rounding noise is not one
        flat = float(np.ptp(x)) <= 1e-12 * max(float(np.max(np.abs(x))), 1e-300)
        peaks[name] = [] if flat else labelled_peaks(f, a, basis, n=n_peaks)
        table[name] = {"unit": units[name], "mean": float(np.mean(x)),
                       "peak_to_peak": float(np.ptp(x)), "peaks": peaks[name]}
    report = {
        "scene": scene.name,
        "mesh_frequency_hz": basis.mesh,
        "shaft_frequencies_hz": [basis.shaft1, basis.shaft2],
        "eccentricity_m": [ecc.e1, ecc.e2],
        "eccentricity_phase_rad": [ecc.phase1, ecc.phase2],
        "friction_coefficient": mu,
        "normal_load_n": load,
        "duration_s": float(sig.t[-1] + sig.t[1] - sig.t[0]),
        "resolution_hz": float(spectra["w2"][0][1]),
        "window": "hann (amplitude-corrected)",
        "signals": table,
    }
    return {"t": sig.t, "series": series, "spectra": spectra, "peaks": peaks, "basis": basis,
            "report": report}


def run(args: argparse.Namespace) -> int:

    from ..io import save_figure, staged_output, write_csv, write_json
    from ..plots_excitation import plot_excitation_spectra, plot_excitation_time
    from ..scene import load_scene

    scene = load_scene(args.scene)
    res = analyse(scene, args.periods, args.samples_per_mesh, args.peaks)
    with staged_output(args.out) as tmp:
        write_csv(tmp / "excitation.csv", {"t_s": res["t"], **res["series"]})
        fig = plot_excitation_time(res["t"], res["series"], res["basis"])
        save_figure(fig, tmp / "excitation_time.png", dpi=110)
        fig = plot_excitation_spectra(res["spectra"], res["peaks"], res["basis"])
        save_figure(fig, tmp / "excitation_spectrum.png", dpi=110)
        write_json(tmp / "peaks.json", res["report"])
    for name, pk in res["peaks"].items():
        top = ", ".join(f"{p['label'] or '?'} {p['frequency_hz']:.2f} Hz" for p in pk[:6])
        print(f"{name}: {top or 'constant (no peaks)'}")
    print(f"wrote {args.out}")
    return 0
