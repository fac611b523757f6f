"""Read a TOML scene file into a validated :class:`Scene` (SI values, defaults filled)."""

from __future__ import annotations

import difflib
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import SceneError
from .registry import SECTIONS


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


def _all_defaults(name: str) -> bool:
    from .fields import REQUIRED

    return all(f.default is not REQUIRED for f in SECTIONS[name].fields)


def parse_scene(data: dict[str, Any], source: str = "<dict>") -> Scene:
    """Validate a scene given as a dict (the parsed TOML).

    Raises
    ------
    SceneError
        Unknown tables or keys (with a did-you-mean), missing required keys, wrong types or
        units, non-finite numbers or out-of-range values; the message names file and key path.
    """
    from . import load_feature_sections

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
        tables[key] = SECTIONS[key].parse(value, source)
    for name, sec in SECTIONS.items():
        if not sec.optional and name not in tables:
            raise SceneError(f"{source}: [{name}]: missing required table ({sec.doc})")
    return Scene(source=source, tables=tables, raw=data)


def load_scene(path: str | Path) -> Scene:
    """Read and validate a scene file.

    Raises
    ------
    SceneError
        Missing or unreadable file, invalid TOML, or any invalid value (see :func:`parse_scene`).
    """
    p = Path(path)
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
