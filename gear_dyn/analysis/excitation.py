"""The excitations of an eccentric pair (Liu et al. 2017) and their labelled spectra (the API behind
``gear-dyn excitation``): driven speed w2(t), contact-line length L(t) and, with friction, the
friction force and torques, at constant input speed and normal load ``W = T1 / r_b1``."""

from __future__ import annotations

from typing import Any

import numpy as np

from gear_dyn.analysis.spectrum import amplitude_spectrum
from gear_dyn.analysis.spectrum_labels import Basis, labelled_peaks
from gear_dyn.eccentricity.kinematics import Eccentricity, EccentricMesh
from gear_dyn.eccentricity.signals import excitation_signals
from gear_dyn.errors import InputError
from gear_dyn.geometry import GearPair


def analyse_excitation(pair: GearPair, speed: float, torque: float, ecc: Eccentricity,
                       mu: float | None, periods: int = 1, samples_per_mesh: int = 64,
                       n_peaks: int = 30) -> dict[str, Any]:
    """Signals, spectra and labelled peaks of an eccentric pair.

    Parameters
    ----------
    pair : GearPair
    speed : float
        Pinion speed in rad/s.
    torque : float
        Pinion torque in N m.
    ecc : Eccentricity
    mu : float or None
        Friction coefficient, or None for no friction signals.
    periods, samples_per_mesh : int
        Hunting periods and samples per mesh period.
    n_peaks : int
        Labelled peaks per signal (>= 1).

    Returns
    -------
    dict
        ``t``, ``series`` (name -> array), ``spectra`` (name -> (f, amp)), ``peaks``
        (name -> list of dicts), ``basis`` and ``report`` (the JSON-ready summary).
    """
    if n_peaks < 1:
        raise InputError(f"--peaks = {n_peaks}: valid range >= 1")
    mesh = EccentricMesh(pair, ecc, speed)
    load = torque / pair.rb1
    sig = excitation_signals(mesh, load, mu, periods=periods, samples_per_mesh=samples_per_mesh)
    series: dict[str, np.ndarray] = {"w2": sig.w2, "contact_length": sig.contact_length}
    for name in ("friction_force", "friction_torque_pinion", "friction_torque_gear"):
        if getattr(sig, name) is not None:  # with friction
            series[name] = getattr(sig, name)
    basis = Basis.of_pair(pair.z1, pair.z2, speed)
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
