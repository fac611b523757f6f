"""The validated scene (:class:`~gear_dyn.scene.validated.Scene`: its tables in SI values) and
:func:`~gear_dyn.scene.validated.scene_error`, which
words an error of the API in the scene's key paths.

Every scene module uses these; the reading of files (:mod:`.loader`) and the building of objects
(:mod:`gear_dyn.scene.build`) sit above.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from gear_dyn.errors import SceneError
from gear_dyn.scene.fields import REQUIRED
from gear_dyn.scene.registry import SECTIONS


@dataclass(frozen=True)
class Scene:
    """A validated scene.

    Attributes
    ----------
    source : str
        File name (or ``<dict>``) used in messages.
    tables : dict
        Section name -> dict of SI values, only for the tables present in the file (plus the
        required ones). An absent optional table means that part is disabled.
    raw : dict
        The TOML content as read.
    """

    source: str
    tables: dict[str, dict[str, Any]]
    raw: dict[str, Any] = field(repr=False, default_factory=dict)

    def has(self, name: str) -> bool:
        """Whether the optional table ``name`` is present (the part is enabled)."""
        return name in self.tables

    def get(self, name: str) -> dict[str, Any]:
        """The table ``name`` with defaults (an absent optional table gives its defaults)."""
        if name in self.tables:
            return self.tables[name]
        return SECTIONS[name].parse({}, self.source) if _all_defaults(name) else {}

    @property
    def name(self) -> str:
        """Case name (file stem if not given)."""
        n = self.tables.get("scene", {}).get("name", "")
        return n or Path(self.source).stem


#: Python parameter names (GearPair, sdof_from_pair, SDOFModel) -> scene key paths, so that an
#: error raised by the API while building a scene names the key the user wrote
SCENE_KEY_PATHS: dict[str, str] = {
    "z1": "gear.teeth_pinion", "z2": "gear.teeth_gear", "module": "gear.module",
    "pressure_angle": "gear.pressure_angle", "face_width": "gear.face_width",
    "helix_angle": "gear.helix_angle", "addendum_coef": "gear.addendum_coef",
    "clearance_coef": "gear.clearance_coef", "x1": "gear.profile_shift_pinion",
    "x2": "gear.profile_shift_gear", "center_distance": "gear.center_distance",
    "youngs_modulus1": "gear.youngs_modulus", "youngs_modulus2": "gear.youngs_modulus",
    "poisson1": "gear.poisson", "poisson2": "gear.poisson", "density1": "gear.density",
    "density2": "gear.density", "speed": "operating.speed", "torque": "operating.torque",
    "inertia_pinion": "inertia.pinion", "inertia_gear": "inertia.gear",
    "damping_ratio": "damping.ratio", "backlash": "backlash.half_gap",
    "tip_diameter1": "gear.tip_diameter_pinion", "tip_diameter2": "gear.tip_diameter_gear",
    "tip_shortening": "gear.tip_shortening",
}
_NAMES = "|".join(sorted(SCENE_KEY_PATHS, key=len, reverse=True))
_NAME_RE = re.compile(rf"(?<![\w.])({_NAMES})(?=\s*(?:=|<|>))")
#: names in advice ("check center_distance and addendum_coef", "reduce x1 or addendum_coef")
_ADVICE_RE = re.compile(
    rf"\b(check|reduce|increase) ({_NAMES})(?: (and|or) ({_NAMES}))?(?![\w.])"
)


def _advice(m: re.Match[str]) -> str:
    text = f"{m.group(1)} {SCENE_KEY_PATHS[m.group(2)]}"
    if m.group(3):
        text += f" {m.group(3)} {SCENE_KEY_PATHS[m.group(4)]}"
    return text


def scene_error(source: str, exc: Exception) -> SceneError:
    """A :class:`.SceneError` for an error raised by the API while building a scene.

    The message gets the file name in front, and Python parameter names used as variables
    (``z1 = 9``, ``x1 >= 0.3``) become the scene key paths (``gear.teeth_pinion = 9``).
    A :class:`.SceneError` is returned unchanged.
    """
    if isinstance(exc, SceneError):
        return exc
    text = _NAME_RE.sub(lambda m: SCENE_KEY_PATHS[m.group(1)], str(exc))
    text = _ADVICE_RE.sub(_advice, text)
    return SceneError(f"{source}: {text}")


def _all_defaults(name: str) -> bool:
    return all(f.default is not REQUIRED for f in SECTIONS[name].fields)
