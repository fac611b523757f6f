"""The ``[lead_modification]``, ``[misalignment]`` and ``[slice_contact]`` scene tables.

They feed the slice-method loaded contact (:mod:`gear_dyn.modification.slice_contact`): a scene
with any of them (or a helical pair with ``[tip_relief]``) runs the single-DOF model on that
analysis, and ``gear-dyn contact`` applies them to every design it compares. Keys and
conventions: docs/modification.md, "Lead modifications and misalignment".
"""

from __future__ import annotations

from typing import Any

from gear_dyn.errors import InputError, SceneError
from gear_dyn.geometry import GearPair
from gear_dyn.modification.lead import FlankModification, LeadModification, Misalignment
from gear_dyn.modification.relief import ProfileModification
from gear_dyn.modification.slice_contact import SliceOptions
from gear_dyn.scene.fields import Field, Section
from gear_dyn.scene.registry import register_section
from gear_dyn.scene.validated import Scene

_UM = 1e-3  # m: the largest amount a table takes (1 mm)


def _lead_fields(gear: str) -> tuple[Field, ...]:
    return (
        Field(f"crowning_{gear}", "m", default=0.0, low=0.0, high=_UM,
              doc=f"{gear} crowning C_b at each face end (parabolic, e.g. \"10 um\")"),
        Field(f"end_relief_{gear}", "m", default=0.0, low=0.0, high=_UM,
              doc=f"{gear} end relief C_e at each face end (linear)"),
        Field(f"end_relief_length_{gear}", "m", default=0.0, low=0.0, high=1.0,
              doc=f"{gear} end relief length L_e from each face end"),
        Field(f"helix_slope_{gear}", "m", default=0.0, low=-_UM, high=_UM,
              doc=f"{gear} helix slope modification: gap growing by this from front to rear"),
    )


LEAD_MODIFICATION = register_section(Section(
    "lead_modification", (*_lead_fields("pinion"), *_lead_fields("gear")),
    doc="lead modifications (crowning, end relief, helix slope) for the slice loaded contact",
    models=("sdof",)))

MISALIGNMENT = register_section(Section("misalignment", (
    Field("f_ma", "m", default=0.0, low=-_UM, high=_UM,
          doc="mesh misalignment in the plane of action over the face width (ISO 6336-1)"),
    Field("f_sigma_beta", "m", default=0.0, low=-_UM, high=_UM,
          doc="out-of-plane axis deviation over the face width (acts with cos a_wt)"),
    Field("f_sigma_delta", "m", default=0.0, low=-_UM, high=_UM,
          doc="in-plane axis deviation over the face width (acts with sin a_wt)"),
), doc="misalignment as a linear gap across the face, for the slice loaded contact",
   models=("sdof",)))

SLICE_CONTACT = register_section(Section("slice_contact", (
    Field("slices", kind="int", default=30, low=1, high=2000, doc="slices across the face"),
    Field("positions", kind="int", default=32, low=2, high=100000,
          doc="mesh positions over one mesh cycle"),
    Field("coupling_length", "m", default=None, low=0.0, high=1.0,
          doc="decay length of the coupling of neighbouring slices (default: whole depth / "
              "sqrt 2; 0: independent slices)"),
), doc="discretisation of the slice loaded contact", models=("sdof",)))

#: tables that make a scene use the slice loaded contact
SLICE_TABLES = ("lead_modification", "misalignment", "slice_contact")


def uses_slice_contact(scene: Scene, pair: GearPair) -> bool:
    """Whether the scene's loaded contact is the slice method: a lead, misalignment or slice
    table, or a helical pair with ``[tip_relief]``."""
    if any(scene.has(t) for t in SLICE_TABLES):
        return True
    return scene.has("tip_relief") and pair.helix_angle != 0.0


def flank_from_scene(scene: Scene, pair: GearPair,
                     profile: ProfileModification | None = None) -> FlankModification:
    """The lead modifications and misalignment of a scene, with ``profile`` as tip reliefs.

    Raises
    ------
    SceneError
        Values the pair cannot take (an end relief longer than half the face, one without a
        length).
    """
    leads: dict[str, LeadModification | None] = {"pinion": None, "gear": None}
    mis = None
    try:
        if scene.has("lead_modification"):
            t = scene.tables["lead_modification"]
            for gear in leads:
                lead = LeadModification(t[f"crowning_{gear}"], t[f"end_relief_{gear}"],
                                        t[f"end_relief_length_{gear}"], t[f"helix_slope_{gear}"])
                lead.separation(pair.face_width, [0.0])  # end relief against the face width
                leads[gear] = lead
        if scene.has("misalignment"):
            m = scene.tables["misalignment"]
            mis = Misalignment(m["f_ma"], m["f_sigma_beta"], m["f_sigma_delta"])
    except InputError as exc:
        raise SceneError(f"{scene.source}: {exc}") from None
    return FlankModification(profile, leads["pinion"], leads["gear"], mis)


def slice_options_from_scene(scene: Scene) -> SliceOptions:
    """The ``[slice_contact]`` options (defaults without the table)."""
    if not scene.has("slice_contact"):
        return SliceOptions()
    t: dict[str, Any] = scene.tables["slice_contact"]
    return SliceOptions(t["slices"], t["positions"], t["coupling_length"])
