"""TOML scenes: one table per part; a table left out disables that part at no cost.

Each table is declared where its part is built: the core tables in :mod:`.core` (the single-DOF
model in :mod:`.build`), the optional parts in :mod:`.eccentricity` (eccentricity, friction,
torsional model), :mod:`.modification` (tip relief) and :mod:`.iso` (ISO 6336 K_v inputs).
:mod:`.loader` imports them all, so every table is known before a scene is read.
"""

from __future__ import annotations

from gear_dyn.scene.build import (
    RunPlan,
    build_model,
    build_pair,
    build_plan,
    scene_stiffness,
)
from gear_dyn.scene.fields import REQUIRED, Field, Section
from gear_dyn.scene.loader import load_scene, parse_scene
from gear_dyn.scene.registry import MODEL_BUILDERS, SECTIONS, register_model, register_section
from gear_dyn.scene.run import run_scene
from gear_dyn.scene.validated import Scene

__all__ = [
    "MODEL_BUILDERS", "REQUIRED", "SECTIONS", "Field", "RunPlan", "Scene", "Section",
    "build_model", "build_pair", "build_plan", "load_scene", "parse_scene", "register_model",
    "register_section", "run_scene", "scene_stiffness",
]
