"""Read a TOML scene file into a validated :class:`Scene` (SI values, defaults filled)."""

from __future__ import annotations

import difflib
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from gear_dyn.errors import SceneError
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
}
_NAME_RE = re.compile(
    r"(?<![\w.])(" + "|".join(sorted(SCENE_KEY_PATHS, key=len, reverse=True))
    + r")(?=\s*(?:=|<|>))"
)
#: names in advice ("check center_distance and addendum_coef", "reduce x1 or addendum_coef")
_NAMES = "|".join(sorted(SCENE_KEY_PATHS, key=len, reverse=True))
_ADVICE_RE = re.compile(
    rf"\b(check|reduce|increase) ({_NAMES})(?: (and|or) ({_NAMES}))?(?![\w.])"
)


def _advice(m: re.Match[str]) -> str:
    text = f"{m.group(1)} {SCENE_KEY_PATHS[m.group(2)]}"
    if m.group(3):
        text += f" {m.group(3)} {SCENE_KEY_PATHS[m.group(4)]}"
    return text


def scene_error(source: str, exc: Exception) -> SceneError:
    """A :class:`SceneError` for an error raised by the API while building a scene.

    The message gets the file name in front, and Python parameter names used as variables
    (``z1 = 9``, ``x1 >= 0.3``) become the scene key paths (``gear.teeth_pinion = 9``).
    A :class:`SceneError` is returned unchanged.
    """
    if isinstance(exc, SceneError):
        return exc
    text = _NAME_RE.sub(lambda m: SCENE_KEY_PATHS[m.group(1)], str(exc))
    text = _ADVICE_RE.sub(_advice, text)
    return SceneError(f"{source}: {text}")


def _all_defaults(name: str) -> bool:
    from gear_dyn.scene.fields import REQUIRED

    return all(f.default is not REQUIRED for f in SECTIONS[name].fields)


def parse_scene(data: dict[str, Any], source: str = "<dict>", si: bool = False) -> Scene:
    """Validate a scene given as a dict (the parsed TOML).

    Dimensional keys need text with a unit (``"1500 rpm"``); a plain number there is refused,
    unless ``si`` (the values are already SI floats, e.g. a scene's own ``tables``).

    Raises
    ------
    SceneError
        Unknown tables or keys (with a did-you-mean), missing required keys, wrong types or
        units, non-finite numbers or out-of-range values; the message names file and key path.
    """
    from gear_dyn.scene import load_feature_sections

    load_feature_sections()
    if not isinstance(data, dict):
        raise SceneError(f"{source}: a scene must be a TOML table")
    tables: dict[str, dict[str, Any]] = {}
    for key, value in data.items():
        if key not in SECTIONS:
            hint = difflib.get_close_matches(str(key), list(SECTIONS), n=1)
            mean = f"; did you mean [{hint[0]}]?" if hint else ""
            raise SceneError(
                f"{source}: [{key}]: unknown table{mean} (valid tables: {', '.join(SECTIONS)})"
            )
        tables[key] = SECTIONS[key].parse(value, source, si)
    model = tables.get("scene", {}).get("model", "sdof")
    for name in tables:
        kinds = SECTIONS[name].models
        if kinds is not None and model not in kinds:
            raise SceneError(
                f"{source}: [{name}] applies to scene.model = {' or '.join(map(repr, kinds))} "
                f"only; this scene runs {model!r} (remove the table or change scene.model)"
            )
    for name, sec in SECTIONS.items():
        if not sec.optional and name not in tables:
            raise SceneError(f"{source}: [{name}]: missing required table ({sec.doc})")
    return Scene(source=source, tables=tables, raw=data)


def load_scene(path: str | Path) -> Scene:
    """Read and validate a scene file, or a packaged scene by name (``"helicopter_tail"``).

    A ``path`` that is no existing file is looked up among the packaged scenes
    (:func:`gear_dyn.scene.packaged.resolve_scene`), so names work from any folder.

    Raises
    ------
    SceneError
        Missing or unreadable file, invalid TOML, or any invalid value (see :func:`parse_scene`).
    """
    from gear_dyn.scene.packaged import resolve_scene

    p = resolve_scene(path)
    try:
        text = p.read_bytes().decode("utf-8")
    except FileNotFoundError:
        raise SceneError(f"{p}: scene file not found") from None
    except IsADirectoryError:
        raise SceneError(f"{p}: is a directory, expected a scene file (.toml)") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(f"{p}: cannot read scene file ({exc.__class__.__name__})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"{p}: invalid TOML: {exc}") from None
    return parse_scene(data, source=p.name)
