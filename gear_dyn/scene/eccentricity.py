"""Scene tables of the eccentric pair and the torsional model, and its model builder.

Tables ``[eccentricity]`` (Liu et al. 2017, eq. 1), ``[friction]`` and ``[torsional]``, each
optional (a table left out builds none of its machinery; keys in docs/scenes.md).
``[scene] model = "torsional"`` selects :func:`build_torsional`.
"""

from __future__ import annotations

from typing import Any

from gear_dyn.eccentricity.kinematics import Eccentricity
from gear_dyn.errors import InputError
from gear_dyn.models.base import Model
from gear_dyn.models.torsional import ContactLineStiffness, TorsionalModel
from gear_dyn.scene.build import (
    build_pair,
    scene_inertias,
    scene_stiffness,
    scene_stiffness_choice,
    scene_transmission_error,
)
from gear_dyn.scene.fields import REQUIRED, Field, Section
from gear_dyn.scene.registry import register_model, register_section
from gear_dyn.scene.validated import Scene, scene_error
from gear_dyn.stiffness.contact_line import mean_contact_line_length
from gear_dyn.stiffness.periodic import PeriodicStiffness

ECCENTRICITY = register_section(Section("eccentricity", (
    Field("pinion", "m", default=0.0, low=0.0, high=0.01, doc="pinion eccentricity e1"),
    Field("gear", "m", default=0.0, low=0.0, high=0.01, doc="gear eccentricity e2"),
    Field("phase_pinion", "rad", default=0.0, low=-1e3, high=1e3,
          doc="initial angle of the pinion's geometric centre"),
    Field("phase_gear", "rad", default=0.0, low=-1e3, high=1e3,
          doc="initial angle of the gear's geometric centre"),
), doc="geometric eccentricity of pinion and gear (Liu et al. 2017; present = enabled)",
   models=("torsional",)))

FRICTION = register_section(Section("friction", (
    Field("coefficient", default=REQUIRED, low=0.0, high=1.0,
          doc="mean tooth friction coefficient mu"),
), doc="sliding friction on the contact lines (Liu et al. 2017; present = enabled)",
   models=("torsional",)))

TORSIONAL = register_section(Section("torsional", (
    Field("load_torque", "N*m", default=None, low=0.0, high=1e9,
          doc="gear load torque T2 (default: balances T1 with the mean friction loss)"),
    Field("stiffness_per_length", "N/m**2", default=None, low=0.0, high=1e16, low_open=True,
          doc="k_l for stiffness method contact_line (default from that method's mean)"),
), doc="options of the two-DOF torsional model", models=("torsional",)))


def scene_eccentricity(scene: Scene) -> Eccentricity | None:
    """The scene's eccentricity, or None without an ``[eccentricity]`` table."""
    if not scene.has("eccentricity"):
        return None
    e = scene.tables["eccentricity"]
    try:
        return Eccentricity(e["pinion"], e["gear"], e["phase_pinion"], e["phase_gear"])
    except InputError as exc:
        raise scene_error(scene.source, exc) from None


def scene_friction(scene: Scene) -> float | None:
    """The friction coefficient, or None without a ``[friction]`` table."""
    return scene.tables["friction"]["coefficient"] if scene.has("friction") else None


def build_torsional(scene: Scene) -> Model:
    """Two-DOF torsional model of the scene (only the parts whose tables are present)."""
    pair = build_pair(scene)
    op = scene.get("operating")
    tors = scene.get("torsional")
    stiff: PeriodicStiffness | ContactLineStiffness
    if scene_stiffness_choice(scene, pair).method == "contact_line":
        k_l = tors["stiffness_per_length"]
        if k_l is None:
            k_l = scene_stiffness(scene, pair).mean / mean_contact_line_length(pair)
        stiff = ContactLineStiffness(k_l)
    else:
        stiff = scene_stiffness(scene, pair)
    inertias = scene_inertias(scene) or pair.blank_inertias()
    kw: dict[str, Any] = dict(
        eccentricity=scene_eccentricity(scene), friction=scene_friction(scene),
        backlash=scene.tables["backlash"]["half_gap"] if scene.has("backlash") else None,
        transmission_error=scene_transmission_error(scene), load_torque=tors.get("load_torque"),
    )
    try:
        return TorsionalModel(pair=pair, speed=op["speed"], torque=op["torque"], stiffness=stiff,
                              inertias=inertias, damping_ratio=scene.get("damping")["ratio"], **kw)
    except InputError as exc:
        raise scene_error(scene.source, exc) from None


register_model("torsional", build_torsional)
