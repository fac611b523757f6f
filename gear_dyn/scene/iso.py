"""The ``[iso]`` scene table and the ISO 6336-1 method B K_v of a scene, beside the simulation.

Every run of a loaded scene states K_v for the same pair and speed
(:func:`gear_dyn.stiffness.iso_kv.iso_dynamic_factor`). The deviations come from the optional
``[iso]`` table (keys in docs/scenes.md), else from stated defaults the summary names. C_a is the
larger ``[tip_relief]`` amount, else the running-in C_ay when credited, else 0; the mass is the
model's.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from gear_dyn.errors import InputError, SceneError
from gear_dyn.geometry import GearPair
from gear_dyn.scene.build import build_pair, scene_inertias
from gear_dyn.scene.deviations import scene_tolerances
from gear_dyn.scene.fields import Field, Section
from gear_dyn.scene.modification import relief_from_scene
from gear_dyn.scene.registry import register_section
from gear_dyn.scene.validated import Scene
from gear_dyn.stiffness.iso_kv import (
    FORMULAS,
    RUNNING_IN,
    IsoKv,
    iso1328_deviations,
    iso_dynamic_factor,
    reduced_mass_solid_wheels,
    resonance_speed,
    running_in_tip_relief,
)

DEFAULT_GRADE = 5

ISO = register_section(Section("iso", (
    Field("accuracy_grade", kind="int", default=None, low=0, high=12,
          doc="ISO 1328-1 accuracy grade: f_pb = f_pt cos a_t and f_falpha unless given "
              "(default 5, stated as assumed)"),
    Field("f_pb", "m", default=None, low=0.0, high=1e-3,
          doc="base pitch deviation f_pb (e.g. \"6 um\"; default from the grade)"),
    Field("f_falpha", "m", default=None, low=0.0, high=1e-3,
          doc="profile form deviation f_falpha (e.g. \"5 um\"; default from the grade)"),
    Field("application_factor", default=1.0, low=1.0, high=10.0,
          doc="application factor K_A (line load K_A F_t / b)"),
    Field("running_in", kind="str", default="none", choices=RUNNING_IN,
          doc="running-in allowances y_p, y_f (none: no credit)"),
    Field("sigma_hlim", "Pa", default=None, low=200e6, high=2500e6,
          doc="sigma_Hlim (e.g. \"1500 MPa\"): through_hardened running-in, and C_ay when "
              "there is no tip relief"),
), doc="ISO 6336-1 method B dynamic factor K_v printed beside the simulated one; absent: "
       "grade 5, K_A = 1, no running-in, C_a from [tip_relief] or 0"))


def _tip_relief(scene: Scene, t: dict[str, Any]) -> tuple[float, str]:
    if scene.has("tip_relief"):
        mod = relief_from_scene(scene)
        amounts = [r.amount for r in (mod.pinion, mod.gear) if r is not None]
        return max(amounts), "larger amount of [tip_relief]"
    if t["running_in"] != "none" and t["sigma_hlim"] is not None:
        return running_in_tip_relief(t["sigma_hlim"]), "running-in C_ay from sigma_hlim"
    return 0.0, "no tip relief (C_a = 0)"


def scene_iso_kv(scene: Scene, speeds: ArrayLike | None = None,
                 pair: GearPair | None = None) -> tuple[IsoKv, dict[str, str]]:
    """K_v of the scene's pair at ``speeds`` (rad/s; default the scene's speed), and where each
    input came from (``{"deviations": ..., "tip_relief": ..., "mass": ...}``). ``pair``: the
    scene's :func:`~gear_dyn.scene.build.build_pair`, where the caller has it (None: built).

    Raises
    ------
    InputError
        Zero torque (K_v needs a load), or values the formulas cannot take.
    """
    pair = build_pair(scene) if pair is None else pair
    op = scene.get("operating")
    t = scene.get("iso")
    if speeds is None:
        speeds = [op["speed"]]
    grade = t["accuracy_grade"] if t["accuracy_grade"] is not None else DEFAULT_GRADE
    f_pt, f_fa = (max(v) for v in zip(*(iso1328_deviations(grade, pair.module, 2 * r)
                                          for r in (pair.r1, pair.r2)), strict=True))
    src = f"ISO 1328-1 grade {grade}" + ("" if t["accuracy_grade"] is not None
                                          else " (assumed: set [iso] accuracy_grade)")
    if scene.has("deviations") and scene.tables["deviations"]["pattern"] != "none":
        # like for like: the deviations that excite the run, at their tolerance values
        tol, dev_src = scene_tolerances(scene, pair)
        f_pt, f_fa = max(x.f_pt for x in tol), max(x.f_falpha for x in tol)
        src = f"[deviations] ({dev_src}; the same deviations excite the run)"
    f_pb = t["f_pb"] if t["f_pb"] is not None else f_pt * math.cos(pair.alpha_t)
    f_falpha = t["f_falpha"] if t["f_falpha"] is not None else f_fa
    if t["f_pb"] is not None and t["f_falpha"] is not None:
        src = "[iso] f_pb, f_falpha"
    elif t["f_pb"] is not None or t["f_falpha"] is not None:
        src = f"[iso] {'f_pb' if t['f_pb'] is not None else 'f_falpha'}, the other from {src}"
    c_a, relief_src = _tip_relief(scene, t)
    inertias = scene_inertias(scene) or pair.blank_inertias()
    mass_src = ("[inertia]" if scene.has("inertia") else "solid blanks at the pitch radii"
                ) + " (as the model)"
    try:
        kv = iso_dynamic_factor(pair, speeds, op["torque"], inertias, f_pb=f_pb,
                                f_falpha=f_falpha, tip_relief=c_a,
                                application_factor=t["application_factor"],
                                running_in=t["running_in"], sigma_hlim=t["sigma_hlim"])
    except InputError as exc:
        raise SceneError(f"{scene.source}: ISO 6336 K_v: {exc}") from None
    return kv, {"deviations": src, "tip_relief": relief_src, "mass": mass_src}


def iso_kv_summary(scene: Scene, pair: GearPair | None = None) -> dict[str, Any]:
    """The ``iso_6336_kv`` entry of a run summary: K_v at the scene's speed, N, n_E1, the speed
    range and its formula, the B factors and the inputs with their sources (SI units in names).
    ``pair``: the scene's :func:`~gear_dyn.scene.build.build_pair`, where the caller has it."""
    if not scene.get("operating")["torque"] > 0:
        return {"k_v": None, "note": "not defined at zero load (operating.torque = 0)"}
    t = scene.get("iso")
    if t["running_in"] == "through_hardened" and t["sigma_hlim"] is None:
        raise SceneError(f"{scene.source}: iso.sigma_hlim: missing (running_in = "
                         "'through_hardened' needs sigma_Hlim, e.g. \"900 MPa\")")
    try:
        pair = build_pair(scene) if pair is None else pair
        kv, src = scene_iso_kv(scene, pair=pair)
    except InputError as exc:  # the standard's figure is beside the run, never in its way
        return {"k_v": None, "note": f"not computed: {exc}"}
    rng = str(kv.speed_range[0])
    cv = kv.cv
    return {
        "k_v": float(kv.k_v[0]),
        "resonance_ratio_n": float(kv.ratio[0]),
        "resonance_speed_rpm": kv.resonance_speed_rpm,
        "speed_range": rng,
        "range_limits": f"N_S = {kv.lower_limit:.3g}: subcritical N <= N_S, main resonance "
                        "N_S < N <= 1.15, intermediate 1.15 < N < 1.5, supercritical N >= 1.5",
        "formula": FORMULAS[rng],
        "lower_limit_n_s": kv.lower_limit,
        "b_p": float(kv.b_p[0]), "b_f": float(kv.b_f[0]), "b_k": kv.b_k,
        "c_v": [cv.cv1, cv.cv2, cv.cv3, cv.cv4, cv.cv5, cv.cv6, cv.cv7],
        "eps_gamma": kv.eps_gamma,
        "c_single_n_per_m2": kv.c_single,
        "c_gamma_alpha_n_per_m2": kv.c_gamma_alpha,
        "m_red_kg_per_m": kv.m_red,
        "m_red_iso_solid_wheels_kg_per_m": (m_iso := reduced_mass_solid_wheels(pair)),
        "resonance_speed_iso_solid_wheels_rpm": resonance_speed(pair.z1, kv.c_gamma_alpha,
                                                                m_iso),
        "line_load_n_per_m": kv.line_load,
        "f_pb_eff_m": float(kv.f_pb_eff[0]), "f_f_eff_m": float(kv.f_f_eff[0]),
        "tip_relief_c_a_m": kv.tip_relief,
        "sources": src,
        "standard": "ISO 6336-1 method B (clause 6.5; eq. numbers of the 2006 edition)",
        "like_for_like": like_for_like_note(scene),
    }


def like_for_like_note(scene: Scene) -> str:
    """Whether K_dyn and K_v see the same deviations (ISO 6336-1 B_p, B_f; Tamminana,
    Kahraman & Vijayakar 2007 compare the force-based dynamic factor with K_v)."""
    if scene.has("deviations") and scene.tables["deviations"]["pattern"] != "none":
        return ("like for like: K_v takes f_pb and f_falpha (B_p, B_f) of the [deviations] that "
                "excite this run, so K_dyn includes the same deviations")
    return ("not like for like: K_v assumes the pitch and profile deviations of its grade "
            "(B_p, B_f); this simulation has none (add a [deviations] table to include them)")


def iso_kv_lines(s: dict[str, Any]) -> list[str]:
    """Terminal lines from :func:`iso_kv_summary` (``s``): K_v, N, range, formula, inputs."""
    if s.get("k_v") is None:
        return [f"ISO 6336-1 K_v: {s.get('note', 'not available')}"]
    lim = "N <= N_S" if s["speed_range"] == "subcritical" else \
        "N_S < N <= 1.15" if s["speed_range"] == "main resonance" else \
        "1.15 < N < 1.5" if s["speed_range"] == "intermediate" else "N >= 1.5"
    src = s["sources"]
    return [
        f"ISO 6336-1 method B: K_v = {s['k_v']:.4f} at N = n1/n_E1 = "
        f"{s['resonance_ratio_n']:.3f} (n_E1 = {s['resonance_speed_rpm']:.0f} rpm), "
        f"{s['speed_range']} range {lim} (N_S = {s['lower_limit_n_s']:.3g})",
        f"  {s['formula']}; B_p {s['b_p']:.3g}, B_f {s['b_f']:.3g}, B_k {s['b_k']:.3g}",
        f"  inputs: deviations {src['deviations']}; {src['tip_relief']}; m_red "
        f"{s['m_red_kg_per_m']:.4g} kg/m from {src['mass']}; c_gamma_alpha "
        f"{s['c_gamma_alpha_n_per_m2'] / 1e9:.4g} N/(mm um)",
        f"  {s['like_for_like']}",
    ]


def iso_kv_at(scene: Scene, speeds: ArrayLike) -> np.ndarray | None:
    """K_v at pinion speeds (rad/s), or None at zero load (for sweep tables and plots)."""
    if not scene.get("operating")["torque"] > 0:
        return None
    return scene_iso_kv(scene, speeds)[0].k_v
