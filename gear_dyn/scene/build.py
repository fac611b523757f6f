"""Scene -> objects: gear pair, stiffness, model, solver settings. Builds only what is enabled.

:func:`gear_dyn.scene.run.run_scene` runs what :func:`build_plan` builds.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from gear_dyn.errors import InputError, SceneError
from gear_dyn.excitation import HarmonicSignal, SumSignal
from gear_dyn.geometry import GearPair
from gear_dyn.models.base import Model
from gear_dyn.models.sdof import sdof_from_pair
from gear_dyn.scene.deviations import scene_deviations
from gear_dyn.scene.registry import MODEL_BUILDERS
from gear_dyn.scene.validated import Scene, scene_error
from gear_dyn.solvers import SolverSettings
from gear_dyn.stiffness.periodic import PeriodicStiffness
from gear_dyn.stiffness.select import (  # ISO_DOUBLE_FACTOR re-exported: its earlier home
    ISO_DOUBLE_FACTOR as ISO_DOUBLE_FACTOR,
)
from gear_dyn.stiffness.select import (
    StiffnessChoice,
    build_stiffness,
    choose_stiffness,
    stiffness_options_from_table,
)


def build_pair(scene: Scene) -> GearPair:
    """The :class:`.GearPair` of the scene's ``[gear]`` table."""
    g = scene.get("gear")
    kw: dict[str, Any] = dict(
        z1=g["teeth_pinion"], z2=g["teeth_gear"], module=g["module"],
        pressure_angle=g["pressure_angle"], face_width=g["face_width"],
        helix_angle=g["helix_angle"], addendum_coef=g["addendum_coef"],
        clearance_coef=g["clearance_coef"], x1=g["profile_shift_pinion"],
        x2=g["profile_shift_gear"], youngs_modulus1=g["youngs_modulus"],
        youngs_modulus2=g["youngs_modulus"], poisson1=g["poisson"], poisson2=g["poisson"],
        density1=g["density"], density2=g["density"], tip_diameter1=g["tip_diameter_pinion"],
        tip_diameter2=g["tip_diameter_gear"], tip_shortening=g["tip_shortening"],
    )
    try:
        if g["center_distance"] is None and g["center_distance_offset"] == 0.0:
            return GearPair(**kw)
        base = g["center_distance"]
        if base is None:
            base = GearPair(**kw).a_w
        return GearPair(**kw, center_distance=base + g["center_distance_offset"])
    except InputError as exc:
        raise scene_error(scene.source, exc) from None


def scene_inertias(scene: Scene) -> tuple[float, float] | None:
    """(pinion, gear) polar inertias in kg m^2 of the ``[inertia]`` table; None without it."""
    t = scene.tables.get("inertia")
    return None if t is None else (t["pinion"], t["gear"])


def scene_facts(scene: Scene, pair: GearPair | None = None) -> dict[str, Any]:
    """What the scene says about the case, for run summaries: speeds (rpm), contact and overlap
    ratios, centre distance and geometric backlash (m), stiffness method and why it was chosen
    (``stiffness_choice``, :func:`stiffness_choice_text`). ``pair``: the scene's
    :func:`build_pair`, where the caller has it already (None: built here)."""
    pair = build_pair(scene) if pair is None else pair
    op = scene.get("operating")
    rpm = op["speed"] * 60 / (2 * math.pi)
    return {
        "scene": scene.name,
        "model": scene.get("scene")["model"],
        "input_speed_rpm": rpm,
        "output_speed_rpm": rpm * pair.z1 / pair.z2,
        "contact_ratio": pair.contact_ratio,
        "overlap_ratio": pair.overlap_ratio,
        "helix_hand": pair.hand,
        "center_distance_m": pair.a_w,
        "geometric_backlash_m": pair.backlash,
        "stiffness_method": scene_stiffness_choice(scene, pair).method,
        "stiffness_choice": stiffness_choice_text(scene, pair),
        "fourier_terms": scene.get("stiffness")["fourier_terms"],
    }


def scene_stiffness_choice(scene: Scene, pair: GearPair) -> StiffnessChoice:
    """The stiffness method of the scene's pair: ``[stiffness] method``, or the default rule
    of :func:`gear_dyn.stiffness.select.choose_stiffness` (contact_line for a helical pair,
    iso6336 for a spur pair)."""
    return choose_stiffness(pair, scene.get("stiffness")["method"])


def stiffness_choice_text(scene: Scene, pair: GearPair) -> str:
    """Which stiffness the scene's model gets and why, in one line for the terminal.

    E.g. ``contact_line (helical pair, eps_beta = 1.27: contact-line length; set [stiffness]
    method to override)``; with ``[tip_relief]`` the loaded contact's stiffness.
    """
    relief = scene.tables.get("tip_relief")
    if relief is not None:
        return (f"loaded contact of [tip_relief] (pair stiffness {relief['pair_stiffness']}, "
                f"linearisation {relief['linearisation']})")
    choice = scene_stiffness_choice(scene, pair)
    if choice.by_default:
        return f"{choice.method} ({choice.reason}; set [stiffness] method to override)"
    return f"{choice.method} ([stiffness] method, {choice.reason})"


def scene_stiffness(scene: Scene, pair: GearPair) -> PeriodicStiffness:
    """The mesh stiffness of ``pair`` that the scene's ``[stiffness]`` table asks for.

    Reads the table's method and options and calls :func:`gear_dyn.stiffness.build_stiffness`
    (the one selector for every method, which takes them as arguments).

    Raises
    ------
    SceneError
        Unknown method or options, or values the method cannot take (named by key path).
    """
    s = scene.get("stiffness")
    try:
        method, options = stiffness_options_from_table(s, pair)
        return build_stiffness(pair, method, fourier_terms=s["fourier_terms"], **options)
    except InputError as exc:
        raise scene_error(scene.source, exc) from None


def scene_transmission_error(scene: Scene) -> HarmonicSignal | SumSignal | None:
    """The scene's static transmission error: the ``[transmission_error]`` harmonics, plus the
    ``[deviations]`` (shaft orders over the hunting period, :mod:`gear_dyn.scene.deviations`);
    None without either.

    Raises
    ------
    SceneError
        ``sin`` and ``cos`` of different lengths.
    """
    dev = scene_deviations(scene, build_pair(scene)) if scene.has("deviations") else None
    harmonics = _harmonics(scene)
    if dev is None:
        return harmonics
    parts = dev.signals()
    return SumSignal(parts if harmonics is None else (*parts, harmonics))


def _harmonics(scene: Scene) -> HarmonicSignal | None:
    if not scene.has("transmission_error"):
        return None
    t = scene.tables["transmission_error"]
    sin = t["sin"] if t["sin"] is not None else [0.0] * len(t["cos"])
    if len(sin) != len(t["cos"]):
        raise SceneError(f"{scene.source}: transmission_error.sin has {len(sin)} entries, cos "
                         f"has {len(t['cos'])}: they must match")
    return HarmonicSignal(0.0, np.asarray(t["cos"], dtype=float), np.asarray(sin, dtype=float))


def build_sdof(scene: Scene) -> Model:
    """Single-DOF model of the scene (backlash and transmission error only when present),
    without tip relief: the ``sdof`` kind's builder
    (:func:`gear_dyn.scene.modification.build_relief_sdof`) calls it for a scene without
    ``[tip_relief]``."""
    pair = build_pair(scene)
    op = scene.get("operating")
    k = scene_stiffness(scene, pair)
    backlash = scene.tables["backlash"]["half_gap"] if scene.has("backlash") else None
    te = scene_transmission_error(scene)
    try:
        return sdof_from_pair(
            pair, op["speed"], op["torque"], k, damping_ratio=scene.get("damping")["ratio"],
            inertias=scene_inertias(scene), backlash=backlash, transmission_error=te,
        )
    except InputError as exc:
        raise scene_error(scene.source, exc) from None


def build_model(scene: Scene) -> Model:
    """The model named by ``[scene] model``."""
    kind = scene.get("scene")["model"]
    builder = MODEL_BUILDERS.get(kind)
    if builder is None:
        raise SceneError(f"{scene.source}: scene.model = {kind!r} is not available in this build")
    model: Model = builder(scene)
    return model


@dataclasses.dataclass(frozen=True)
class RunPlan:
    """Everything needed to run a scene: model, settings, span and steady window."""

    model: Model
    settings: SolverSettings
    t_end: float
    steady_start: float


def build_plan(scene: Scene, **overrides: Any) -> RunPlan:
    """Model and solver settings; ``overrides`` replace ``[solver]`` values (e.g. from the CLI)."""
    model = build_model(scene)
    sv = dict(scene.get("solver"))
    for key, val in overrides.items():
        if val is not None:
            sv[key] = val
    if overrides.get("periods") is not None and overrides.get("steady_periods") is None:
        sv["steady_periods"] = None  # a new span takes its own second half as steady window
    try:
        settings = SolverSettings(
            method=sv["method"], rtol=sv["rtol"], atol=sv["atol"],
            samples_per_period=sv["samples_per_period"],
            **({"max_nfev": sv["max_nfev"]} if sv.get("max_nfev") is not None else {}),
        )
    except InputError as exc:
        raise scene_error(scene.source, exc) from None
    periods = sv["periods"]
    steady = sv["steady_periods"] if sv["steady_periods"] is not None else periods // 2
    if steady > periods:
        raise SceneError(
            f"{scene.source}: solver.steady_periods = {steady}: valid range <= solver.periods "
            f"= {periods}"
        )
    t_end = periods / model.mesh_frequency
    return RunPlan(model, settings, t_end, (periods - steady) / model.mesh_frequency)
