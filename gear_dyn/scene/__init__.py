"""TOML scenes: one table per part; a table left out disables that part at no cost.

The adapters of the optional parts (:mod:`.eccentricity`: eccentricity, friction, torsional
model; :mod:`.modification`: tip relief; :mod:`.iso`: ISO 6336 K_v inputs) register their
tables and model builders when imported; :func:`load_feature_sections` imports them on first
use, so the core loads fast.
"""

from __future__ import annotations

from gear_dyn.scene import core  # noqa: F401  (registers the core tables)
from gear_dyn.scene.build import (
    RunPlan,
    build_model,
    build_pair,
    build_plan,
    build_stiffness,
    run_scene,
)
from gear_dyn.scene.fields import REQUIRED, Field, Section
from gear_dyn.scene.loader import Scene, load_scene, parse_scene
from gear_dyn.scene.registry import MODEL_BUILDERS, SECTIONS, register_model, register_section

#: modules that register extra scene tables or model builders when imported
FEATURE_MODULES: tuple[str, ...] = ("gear_dyn.scene.eccentricity", "gear_dyn.scene.modification",
                                     "gear_dyn.scene.iso")

_loaded = False


def load_feature_sections() -> None:
    """Import the feature modules once so their tables and models are registered."""
    global _loaded
    if _loaded:
        return
    from gear_dyn.scene import eccentricity, iso, modification  # noqa: F401  (they register)

    _loaded = True


__all__ = [
    "FEATURE_MODULES", "MODEL_BUILDERS", "REQUIRED", "SECTIONS", "Field", "RunPlan", "Scene",
    "Section", "build_model", "build_pair", "build_plan", "build_stiffness", "load_scene",
    "parse_scene", "register_model", "register_section", "run_scene",
]
