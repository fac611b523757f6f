"""The ``[tip_relief]`` scene table and the single-DOF model with tip relief.

A scene with a ``[tip_relief]`` table runs the single-DOF model on the loaded contact of the
relieved pair (:func:`~gear_dyn.models.relief.relief_sdof` for spur pairs; the slice loaded
contact, :func:`~gear_dyn.models.relief.slice_sdof`, for helical pairs or with the tables of
:mod:`gear_dyn.scene.lead`); without these tables nothing of this module runs. The keys
(a rule or custom amounts, the curve, lengths or heights, the
linearisation) are listed in docs/scenes.md and explained in docs/modification.md.
"""

from __future__ import annotations

from typing import Any

from gear_dyn.choices import PAIR_STIFFNESS_METHODS
from gear_dyn.errors import InputError, SceneError
from gear_dyn.geometry import GearPair
from gear_dyn.models.base import Model
from gear_dyn.models.relief import (
    ContactSDOFModel,
    pair_stiffness_function,
    relief_sdof,
    slice_sdof,
)
from gear_dyn.modification.relief import (
    CURVES,
    RULES,
    ProfileModification,
    TipRelief,
    current_rule,
    length_from_height,
    recommended_relief,
)
from gear_dyn.scene.build import build_pair, build_sdof, scene_inertias
from gear_dyn.scene.fields import Field, Section
from gear_dyn.scene.lead import (
    SLICE_TABLES,
    flank_from_scene,
    slice_options_from_scene,
    uses_slice_contact,
)
from gear_dyn.scene.registry import register_model, register_section
from gear_dyn.scene.validated import Scene, scene_error
from gear_dyn.stiffness.select import stiffness_options_from_table

TIP_RELIEF = register_section(Section("tip_relief", (
    Field("rule", kind="str", default="custom", choices=("custom", *RULES),
          doc="custom amounts and lengths, or a recommended rule at the scene's torque "
              "(wang2024: Wang et al. 2024; its old name seed001 still works, with a warning)",
          renamed=current_rule),
    Field("curve", kind="str", default="linear", choices=CURVES, doc="relief curve"),
    Field("amount_pinion", "m", default=None, low=0.0, high=1e-3,
          doc="pinion relief amount C_a1 (custom)"),
    Field("amount_gear", "m", default=None, low=0.0, high=1e-3,
          doc="gear relief amount C_a2 (custom)"),
    Field("length_pinion", "m", default=None, low=0.0, high=1.0, low_open=True,
          doc="pinion relief length along the line of action (custom)"),
    Field("length_gear", "m", default=None, low=0.0, high=1.0, low_open=True,
          doc="gear relief length along the line of action (custom)"),
    Field("height_pinion", "m", default=None, low=0.0, high=1.0, low_open=True,
          doc="pinion relief height, radial from the tip (custom)"),
    Field("height_gear", "m", default=None, low=0.0, high=1.0, low_open=True,
          doc="gear relief height, radial from the tip (custom)"),
    Field("handbook_a", "m", default=9e-6, low=5e-6, high=13e-6,
          doc="handbook rule constant a (pinion amount at zero load, e.g. \"9 um\")"),
    Field("handbook_b", "m", default=4e-6, low=0.0, high=8e-6,
          doc="handbook rule constant b (gear amount at zero load, e.g. \"4 um\")"),
    Field("face_load_factor", default=1.0, low=1.0, high=3.0, doc="Dudley's C_m"),
    Field("pair_stiffness", kind="str", default="potential_energy", choices=PAIR_STIFFNESS_METHODS,
          doc="unmodified single-pair stiffness method for the loaded contact"),
    Field("linearisation", kind="str", default="tangent",
          choices=("tangent", "secant", "contact"),
          doc="tangent stiffness + relief TE, secant K_TPM, or the nonlinear contact force"),
    Field("samples_per_segment", kind="int", default=48, low=2, high=10000,
          doc="loaded-contact samples between switching phases"),
), doc="tip relief on pinion and/or gear; the single-DOF model runs on the loaded contact",
   models=("sdof",)))


def rule_options(table: dict[str, Any]) -> dict[str, float]:
    """The rule constants of a parsed ``[tip_relief]`` table as
    :func:`~gear_dyn.modification.relief.recommended_relief` takes them (a, b in micrometres)."""
    return {"handbook_a": table["handbook_a"] * 1e6, "handbook_b": table["handbook_b"] * 1e6,
            "face_load_factor": table["face_load_factor"]}


_CUSTOM_KEYS = ("amount_pinion", "amount_gear", "length_pinion", "length_gear",
                "height_pinion", "height_gear")


def _custom_relief(pair: GearPair, t: dict[str, Any], gear: int, where: str) -> TipRelief | None:
    name = "pinion" if gear == 1 else "gear"
    amount, length, height = t[f"amount_{name}"], t[f"length_{name}"], t[f"height_{name}"]
    if amount is None:
        if length is not None or height is not None:
            raise SceneError(f"{where}.amount_{name}: missing (a length or height is given "
                             f"for the {name} but no amount)")
        return None
    if (length is None) == (height is None):
        raise SceneError(f"{where}: give exactly one of length_{name} (along the line of "
                         f"action) or height_{name} (radial from the tip)")
    if height is not None:
        length = length_from_height(pair, gear, height)
    return TipRelief(amount, length, t["curve"])


def relief_from_scene(scene: Scene, pair: GearPair | None = None) -> ProfileModification:
    """The :class:`~gear_dyn.modification.relief.ProfileModification` of the scene's
    ``[tip_relief]`` table.

    Raises
    ------
    SceneError
        No table, missing or conflicting keys, values the pair cannot take.
    """
    if not scene.has("tip_relief"):
        raise SceneError(f"{scene.source}: [tip_relief]: missing table (this command needs it)")
    pair = pair or build_pair(scene)
    t = scene.tables["tip_relief"]
    where = f"{scene.source}: tip_relief"
    try:
        if t["rule"] == "custom":
            mod = ProfileModification(_custom_relief(pair, t, 1, where),
                                      _custom_relief(pair, t, 2, where))
            if mod.pinion is None and mod.gear is None:
                raise SceneError(f"{where}: rule 'custom' needs amount_pinion and/or amount_gear")
        else:
            given = [k for k in _CUSTOM_KEYS if t[k] is not None]
            if given:
                raise SceneError(f"{where}.{given[0]}: only for rule = 'custom' (rule "
                                 f"{t['rule']!r} sets amounts and lengths itself)")
            rec = recommended_relief(pair, scene.get("operating")["torque"], t["rule"],
                                     **rule_options(t))
            mod = rec.modification(t["curve"])
        mod.check(pair)
    except SceneError:
        raise
    except InputError as exc:
        raise SceneError(f"{where}: {exc}") from None
    return mod


def _check_combination(scene: Scene) -> None:
    part = next(t for t in ("tip_relief", *SLICE_TABLES) if scene.has(t))
    for table, why in (("transmission_error", "the loaded contact sets the transmission error"),
                       ("backlash", "backlash with the loaded contact is not implemented"),
                       ("deviations", "deviations with the loaded contact are not implemented")):
        if scene.has(table):
            raise SceneError(f"{scene.source}: [{table}] cannot be combined with [{part}] "
                             f"({why}); remove one of them")
    t = scene.tables.get("tip_relief")
    method = t["pair_stiffness"] if t is not None else "potential_energy"
    key = "tip_relief.pair_stiffness" if t is not None else "the pair stiffness"
    if scene.has("stiffness"):
        s = scene.tables["stiffness"]
        if s["method"] != method or s["fourier_terms"] is not None:
            raise SceneError(
                f"{scene.source}: [stiffness] with [{part}]: the mesh stiffness comes from "
                f"the loaded contact with {key} = {method!r}; "
                f"remove [stiffness] or set stiffness.method = {method!r} without "
                "fourier_terms"
            )


def scene_pair_function(scene: Scene, pair: GearPair, method: str | None = None) -> Any:
    """The unmodified single-pair stiffness ``K(s)`` for a scene: ``method`` (default
    ``tip_relief.pair_stiffness``, else potential energy) with the tooth options of the scene's
    ``[stiffness]`` table when that table names the same method.

    Raises
    ------
    SceneError
        Unknown method or options.
    """
    t = scene.tables.get("tip_relief")
    method = method or (t["pair_stiffness"] if t is not None else "potential_energy")
    options: dict[str, Any] = {}
    try:
        if scene.has("stiffness"):
            s_method, s_opts = stiffness_options_from_table(scene.tables["stiffness"], pair)
            if s_method == method:
                options = s_opts
        return pair_stiffness_function(pair, method, options)
    except InputError as exc:
        raise SceneError(f"{scene.source}: {exc}") from None


def build_relief_sdof(scene: Scene) -> Model:
    """Single-DOF model of a scene with ``[tip_relief]`` (spur: the spur loaded contact) or
    with the slice loaded contact (a helical pair with ``[tip_relief]``, or any of
    ``[lead_modification]``, ``[misalignment]``, ``[slice_contact]``); plain single-DOF
    otherwise."""
    if not scene.has("tip_relief") and not any(scene.has(t) for t in SLICE_TABLES):
        return build_sdof(scene)
    _check_combination(scene)
    pair = build_pair(scene)
    if uses_slice_contact(scene, pair):
        return _build_slice_sdof(scene, pair)
    mod = relief_from_scene(scene, pair)
    t = scene.tables["tip_relief"]
    op = scene.get("operating")
    inertias = scene_inertias(scene)
    try:
        fn = scene_pair_function(scene, pair)
        xi = scene.get("damping")["ratio"]
        if t["linearisation"] == "contact":
            return ContactSDOFModel(pair, op["speed"], op["torque"], mod, fn, xi, inertias)
        model, _ = relief_sdof(pair, op["speed"], op["torque"], mod, fn, xi, inertias,
                               t["linearisation"], t["samples_per_segment"])
    except InputError as exc:
        raise scene_error(scene.source, exc) from None  # Python names -> scene key paths
    return model


def _build_slice_sdof(scene: Scene, pair: GearPair) -> Model:
    """Single-DOF model on the slice loaded contact at the scene's torque."""
    t = scene.tables.get("tip_relief")
    if t is not None and t["linearisation"] != "tangent":
        raise SceneError(f"{scene.source}: tip_relief.linearisation = {t['linearisation']!r}: "
                         "the slice loaded contact (helical pair, lead modification or "
                         "misalignment) gives the tangent form only; set it to 'tangent'")
    profile = relief_from_scene(scene, pair) if t is not None else None
    flank = flank_from_scene(scene, pair, profile)
    op = scene.get("operating")
    if not op["torque"] > 0:
        raise SceneError(f"{scene.source}: operating.torque = 0: the loaded contact needs a "
                         "load (valid range > 0 N*m)")
    try:
        fn = scene_pair_function(scene, pair)
        model, _ = slice_sdof(pair, op["speed"], op["torque"], flank, fn,
                              scene.get("damping")["ratio"], scene_inertias(scene),
                              slice_options_from_scene(scene))
    except InputError as exc:
        raise scene_error(scene.source, exc) from None
    return model


# the one builder of the sdof kind (with or without [tip_relief]); other model kinds refuse
# [tip_relief] at load time (the table declares models=("sdof",))
register_model("sdof", build_relief_sdof)
