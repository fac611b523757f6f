"""Summaries of results as plain dicts (for summary.json and the terminal)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from gear_dyn.analysis.spectrum import amplitude_spectrum, find_peaks
from gear_dyn.solvers import Result

#: the keys of :func:`gear_dyn.scene.build.scene_facts`, listed first in summaries
SCENE_FACTS = ("scene", "model", "input_speed_rpm", "output_speed_rpm", "contact_ratio",
               "overlap_ratio", "center_distance_m", "geometric_backlash_m", "stiffness_method",
               "stiffness_choice", "fourier_terms")


#: what ``dte`` is, per model kind (summary.json ``dte_definition``, CSV header, plots)
DTE_DEFINITION = {
    "sdof": "DTE x: dynamic transmission error on the line of action (base-circle arc of the "
            "pinion minus that of the gear; elastic deflection incl. the static W/k_m)",
    "torsional": "DTE = r_b1 q1 - r_b2 q2 (base-circle arcs of the vibration angles): kinematic "
                 "part -e_ecc (eccentricity, rigid teeth) + elastic part delta (mesh deflection)",
}

#: the figures of the dynamic factor (summary.json, terminal output; defined there)
from gear_dyn.analysis.dynamic_factor import (  # noqa: E402
    DYNAMIC_FACTOR_DEFINITION,
    STIFFNESS_JUMP_DEFINITION,
)

#: what ``peak_force_ratio`` is (summary.json ``peak_force_ratio_definition``)
PEAK_FORCE_DEFINITION = (
    "peak of the dynamic mesh force over the steady window / static load W = T1 / r_b1")


def model_kind(result: Result) -> str:
    """``"torsional"`` or ``"sdof"``: which DTE definition applies to ``result``."""
    return "torsional" if "w1" in result.outputs else "sdof"


def dominant_peak(result: Result, name: str = "dte") -> tuple[float, float]:
    """Largest non-DC spectral peak ``(frequency Hz, amplitude)`` of a series, steady window."""
    mask = result.steady
    f, amp = amplitude_spectrum(result.t[mask], result.series(name)[mask])
    peaks = find_peaks(f, amp, n=1, min_freq=0.5 * (f[1] - f[0]) + f[1])
    return peaks[0] if peaks else (math.nan, math.nan)


def timeseries_comments(result: Result) -> list[str]:
    """The ``#`` lines heading timeseries.csv (:meth:`gear_dyn.solvers.result.Result.to_csv`):
    the scene's name (``run`` without a scene), the units, what ``dte`` is and the dynamic
    factor with its definition, as :func:`summarize` states them."""
    name = getattr(result.scene, "name", None) or "run"
    return [f"# {name}: time series in SI units (t_s in s; dte, delta, e_ecc in m;",
            "# mesh_force in N; stiffness in N/m; angles in rad, rates in rad/s)",
            f"# dte: {DTE_DEFINITION[model_kind(result)]}",
            f"# dynamic factor {result.dynamic_factor:.6g}: {DYNAMIC_FACTOR_DEFINITION}"]


def summarize(result: Result) -> dict[str, Any]:
    """The run summary: kinematics, stiffness, dynamic factor, DTE figures, solver cost.

    Keys (SI units in the names): mesh_frequency_hz, output_speed_rpm, contact_ratio,
    mean_mesh_stiffness_n_per_m, static_transmission_error_m, dynamic_factor, rms_dte_m,
    ptp_dte_m, mean_dte_m, dominant_frequency_hz, solver {...}; plus what the model offers.

    Parameters
    ----------
    result : Result
        A run of :func:`~gear_dyn.analysis.study.simulate` or :func:`~gear_dyn.scene.run_scene`.

    Returns
    -------
    dict
        JSON-ready; what ``gear-dyn run`` writes as ``summary.json``.

    See Also
    --------
    :meth:`~gear_dyn.solvers.result.Result.key_figures` : The few figures a notebook shows.
    :func:`~gear_dyn.analysis.study.simulate` : Makes the result.

    Examples
    --------
    >>> from gear_dyn import SDOFModel, rectangular_stiffness, simulate
    >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
    >>> summary = summarize(simulate(m, 0.2))
    >>> summary["mesh_frequency_hz"], round(summary["natural_frequency_hz"], 1)
    (500.0, 2566.3)
    """
    out: dict[str, Any] = {"mesh_frequency_hz": result.mesh_frequency}
    # what a scene says about the case (run_scene puts it in extra), first as in earlier files
    out.update({k: result.extra[k] for k in SCENE_FACTS if k in result.extra})
    k = result.outputs.get("stiffness")
    if k is not None and "mean_mesh_stiffness_n_per_m" not in result.extra:
        out["mean_mesh_stiffness_n_per_m"] = float(np.mean(k[result.steady]))
        out["static_transmission_error_m"] = result.static_load / out[
            "mean_mesh_stiffness_n_per_m"]
    out["static_load_n"] = result.static_load
    out["dynamic_factor"] = result.dynamic_factor
    out["dynamic_factor_definition"] = DYNAMIC_FACTOR_DEFINITION
    out["peak_force_ratio"] = result.peak_force_ratio
    out["peak_force_ratio_definition"] = PEAK_FORCE_DEFINITION
    if "stiffness_jump_factor" in result.extra:
        out["stiffness_jump_definition"] = STIFFNESS_JUMP_DEFINITION
    out["dte_definition"] = DTE_DEFINITION[model_kind(result)]
    out["mean_dte_m"] = result.mean_dte
    out["rms_dte_m"] = result.rms_dte
    out["ptp_dte_m"] = result.ptp_dte
    out["dominant_frequency_hz"] = dominant_peak(result)[0]
    out["steady_window_s"] = [result.steady_start, float(result.t[-1])]
    out["transient_window_s"] = [0.0, result.steady_start]
    out["solver"] = result.stats.as_dict()
    out.update(result.extra)
    return out
