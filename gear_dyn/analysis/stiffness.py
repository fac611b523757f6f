"""Mesh stiffness of one pair by several methods, side by side, with ISO 6336 and the
potential-energy compliance components at the pitch point (the API behind ``gear-dyn stiffness``).
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from gear_dyn.errors import InputError
from gear_dyn.geometry import GearPair
from gear_dyn.stiffness.iso6336 import iso6336_stiffness
from gear_dyn.stiffness.potential_energy import potential_energy_compliances
from gear_dyn.stiffness.select import (
    METHOD_OPTIONS,
    build_stiffness,
    method_scope,
    tooth_options,
)
from gear_dyn.stiffness.summary import operating_summary, stiffness_summary


def pitch_point_components(pair: GearPair, options: dict[str, Any] | None = None
                           ) -> tuple[Any, dict[str, Any]]:
    """Potential-energy compliances at the pitch point: the raw object and a JSON-ready dict.

    ``options``: the stiffness options of the case (fillet radius, bore radii, plane strain,
    grid points apply), so that the split adds up to the potential-energy curve drawn beside
    it.
    """
    comp = potential_energy_compliances(pair, np.array([pair.pitch_point]),
                                        tooth_options(options or {}))
    components: dict[str, Any] = {
        "position": "pitch point",
        "s_m": pair.pitch_point,
        "hertz_m_per_n": float(comp.hertz[0]),
        "pair_stiffness_n_per_m": float(comp.stiffness[0]),
    }
    for term, arr in (("bending", comp.bending), ("shear", comp.shear), ("axial", comp.axial),
                      ("fillet", comp.fillet)):
        components[f"{term}_pinion_m_per_n"] = float(arr[0, 0])
        components[f"{term}_gear_m_per_n"] = float(arr[1, 0])
    return comp, components


def compare_methods(pair: GearPair, methods: list[str], scene_method: str,
                    scene_opts: dict[str, Any], fourier: int | None = None
                    ) -> tuple[dict[str, Any], dict[str, Any]]:
    """``(curves, report)``: each method's stiffness and the JSON-ready comparison.

    Per method: mean, min, max and zone values
    (:func:`~gear_dyn.stiffness.summary.stiffness_summary`), the ratio of the
    mean to ISO 6336-1 c_gamma b (``ratio_to_iso``) and what the method includes and leaves out
    (``includes``, ``leaves_out``: :func:`gear_dyn.stiffness.select.method_scope`).

    Parameters
    ----------
    pair : GearPair
    methods : list of str
        Method names of :data:`gear_dyn.stiffness.select.METHODS`.
    scene_method : str
        The method the case itself uses (its Fourier truncation is added when ``fourier``).
    scene_opts : dict
        Method options; each method gets the ones it accepts.
    fourier : int or None
        Fourier terms of the case's stiffness.

    Raises
    ------
    InputError
        A method's options out of range (the message names the method).
    """
    curves: dict[str, Any] = {}
    per_method: dict[str, Any] = {}
    iso = iso6336_stiffness(pair)
    for m in methods:  # each method with the scene's options that apply to it
        opts = {k: v for k, v in scene_opts.items() if k in METHOD_OPTIONS[m]}
        t0 = time.perf_counter()
        try:
            k = build_stiffness(pair, m, **opts)
        except InputError as exc:
            raise InputError(f"method {m}: {exc}") from None
        summ = stiffness_summary(pair, k)
        summ["build_time_s"] = time.perf_counter() - t0
        summ["options"] = opts
        summ["ratio_to_iso"] = k.mean / iso.k_mesh
        summ["includes"], summ["leaves_out"] = method_scope(pair, m, opts)
        curves[m] = k
        if fourier is not None and m == scene_method:
            kf = k.truncated(fourier)
            curves[f"{m} (Fourier {fourier})"] = kf
            summ["fourier"] = stiffness_summary(pair, kf)
        per_method[m] = summ
    comp, components = pitch_point_components(pair, scene_opts)
    report: dict[str, Any] = {
        "scene_method": scene_method,
        "fourier_terms": fourier,
        "pair": {"z1": pair.z1, "z2": pair.z2, "module_m": pair.module,
                 "pressure_angle_deg": float(np.degrees(pair.pressure_angle)),
                 "helix_angle_deg": float(np.degrees(pair.helix_angle)), "hand": pair.hand,
                 "face_width_m": pair.face_width},
        "operating": operating_summary(pair),
        "iso6336": {"c_single_n_per_m2": iso.c_single, "c_gamma_n_per_m2": iso.c_mesh,
                    "c_gamma_beta_n_per_m2": iso.c_mesh_beta, "k_single_n_per_m": iso.k_single,
                    "k_mesh_n_per_m": iso.k_mesh},
        "methods": per_method,
        "components_at_pitch_point": components,
        "_components": comp,
    }
    return curves, report
