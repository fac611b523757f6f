"""Read a TOML scene file into a validated :class:`~gear_dyn.scene.validated.Scene` (SI values,
defaults filled).

Importing this module registers every scene table and model builder (the modules that
declare them are imported here), so a scene is checked against all of them.
"""

from __future__ import annotations

import difflib
import tomllib
from pathlib import Path
from typing import Any

from gear_dyn.errors import SceneError

# the tables and model builders register when their modules are imported: the core tables,
# then the optional parts (eccentricity and torsional model, tip relief, ISO 6336 K_v)
from gear_dyn.scene import core, deviations, eccentricity, iso, modification  # noqa: F401
from gear_dyn.scene.registry import SECTIONS
from gear_dyn.scene.validated import Scene


def parse_scene(data: dict[str, Any], source: str = "<dict>", si: bool = False) -> Scene:
    """Validate a scene given as a dict (the parsed TOML).

    Dimensional keys need text with a unit (``"1500 rpm"``); a plain number there is refused,
    unless ``si`` (the values are already SI floats, e.g. a scene's own ``tables``).

    Parameters
    ----------
    data : dict
        Tables (``scene``, ``gear``, ``operating``, ...) of keys and values, as in a scene file
        (``docs/scenes.md`` lists every key with its unit and range).
    source : str
        Name of the source, used in error messages.
    si : bool
        Plain numbers for dimensional keys are SI values (m, rad, rad/s, N m, Pa ...).

    Returns
    -------
    Scene
        The validated scene: ``tables`` in SI units, ``name``, ``source``.

    Raises
    ------
    SceneError
        Unknown tables or keys (with a did-you-mean), missing required keys, wrong types or
        units, non-finite numbers or out-of-range values; the message names file and key path.

    See Also
    --------
    :func:`~gear_dyn.scene.load_scene` : The same from a scene file.
    :func:`~gear_dyn.scene.run_scene` : Simulates a scene.

    Examples
    --------
    >>> scene = parse_scene({
    ...     "scene": {"name": "spur", "model": "sdof"},
    ...     "gear": {"teeth_pinion": 23, "teeth_gear": 64, "module": "6 mm",
    ...              "pressure_angle": "22.5 deg", "face_width": "50 mm"},
    ...     "operating": {"speed": "3319 rpm", "torque": "1474.4 N*m"}})
    >>> scene.tables["gear"]["module"]  # m
    0.006
    >>> parse_scene({"scene": {"name": "spur", "model": "sdof"},
    ...              "gear": {"teeth_pinion": 23, "teeth_gear": 64, "module": 6}})
    Traceback (most recent call last):
    ...
    gear_dyn.errors.SceneError: <dict>: gear.module = 6: give a unit, e.g. "6 mm" ...
    """
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

    Parameters
    ----------
    path : str or Path
        A TOML scene file, or the name of a packaged scene.

    Returns
    -------
    Scene
        The validated scene: ``tables`` in SI units, ``name``, ``source``.

    Raises
    ------
    SceneError
        Missing or unreadable file, invalid TOML, or any invalid value (see :func:`parse_scene`).

    See Also
    --------
    :func:`~gear_dyn.scene.parse_scene` : The same from a dict.
    :func:`~gear_dyn.scene.run_scene` : Simulates a scene.
    :func:`~gear_dyn.scene.sweep.sweep_scene` : Sweeps it over speed.

    Examples
    --------
    >>> scene = load_scene("helicopter_tail")
    >>> scene.name, scene.tables["gear"]["teeth_pinion"]
    ('helicopter_tail', 23)
    >>> load_scene("no_such_scene")
    Traceback (most recent call last):
    ...
    gear_dyn.errors.SceneError: no_such_scene: scene file not found, ...
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
