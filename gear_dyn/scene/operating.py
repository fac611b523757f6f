"""The API's operating-point arguments, read as the scene file reads them.

``run_scene(scene, speed="6000 rpm", torque="200 Nm")`` and ``sweep_scene(scene, ["4000 rpm",
"6275 rpm"])`` take their speeds and torques with units, through the same fields
(``gear_dyn.scene.core.OPERATING``) and messages as a scene's ``[operating]`` table: a plain
number is refused with a hint (1500 rad/s is not what anyone meant by ``speed=1500``), unless
the caller says ``si=True`` (values already in rad/s and N m). Unknown keywords are refused
with a did-you-mean (:func:`check_keywords`), as the scene's unknown keys are.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError, check_range
from gear_dyn.scene.validated import Scene

FloatArray = NDArray[np.float64]


def check_keywords(function: str, given: Iterable[str], valid: Sequence[str]) -> None:
    """Refuse keywords of ``function`` not in ``valid``, with the closest valid one.

    Raises
    ------
    InputError
        ``run_scene: unknown keyword 'sped'; did you mean 'speed'? (valid: ...)``.
    """
    for key in sorted(set(given) - set(valid)):
        hint = difflib.get_close_matches(key, list(valid), n=1)
        mean = f"; did you mean {hint[0]!r}?" if hint else ""
        raise InputError(f"{function}: unknown keyword {key!r}{mean} (valid: "
                         f"{', '.join(valid)})")


def _refuse_hz(text: str, where: str) -> None:
    if "hz" in text.lower():
        # pint reads 1 Hz as 1 rad/s (radians are dimensionless): 2 pi off for a shaft speed
        raise InputError(f"{where} = {text!r}: Hz is ambiguous for a shaft speed (it would be "
                         "read as rad/s); write e.g. '600 rpm' or '10 turn/s'")


def parse_operating(name: str, value: Any, where: str, si: bool = False) -> float:
    """``speed`` (rad/s) or ``torque`` (N m) from text with a unit, as the scene reads it.

    Parameters
    ----------
    name : {"speed", "torque"}
        The ``[operating]`` field.
    value : str or float
        ``"6000 rpm"``, ``"200 Nm"``; a plain number only with ``si``.
    where : str
        What the message names, e.g. ``run_scene speed``.
    si : bool
        Plain numbers are SI values (rad/s, N m).

    Raises
    ------
    InputError
        A plain number without ``si`` (with the readings it might mean), a bad unit, Hz for a
        speed, or a value out of the field's range.
    """
    from gear_dyn.scene.core import OPERATING

    field = {f.name: f for f in OPERATING.fields}[name]
    if name == "speed" and isinstance(value, str):
        _refuse_hz(value, where)
    if isinstance(value, np.generic):
        value = value.item()
    try:
        return float(field.parse(value, where, si=si))
    except InputError as exc:
        if not si and isinstance(value, int | float) and "give a unit" in str(exc):
            raise InputError(f"{exc}; or pass si=True for a value in {field.unit}") from None
        raise


def with_operating(scene: Scene, speed: Any = None, torque: Any = None, *, si: bool = False,
                   function: str = "run_scene") -> Scene:
    """``scene`` with its ``[operating]`` speed and/or torque replaced (None keeps the scene's).

    Raises
    ------
    InputError
        As :func:`parse_operating`, naming ``function``.
    """
    if speed is None and torque is None:
        return scene
    op = dict(scene.tables["operating"])
    if speed is not None:
        op["speed"] = parse_operating("speed", speed, f"{function} speed", si)
    if torque is not None:
        op["torque"] = parse_operating("torque", torque, f"{function} torque", si)
    return Scene(source=scene.source, tables={**scene.tables, "operating": op}, raw=scene.raw)


def parse_speeds(speeds: Any, si: bool = False, function: str = "sweep_scene") -> FloatArray:
    """Sweep speeds in rad/s from what a caller gives.

    Accepted: a range string ``"600 rpm:1200 rpm:31"`` (START:STOP:N, as ``--speeds``), a
    sequence of strings with units (``["4000 rpm", "6275 rpm"]``), or, with ``si=True``, numbers
    in rad/s (a list or a numpy array).

    Raises
    ------
    InputError
        Plain numbers without ``si`` (with a hint), an empty sequence, a bad unit or range.
    """
    if isinstance(speeds, str):
        if speeds.count(":") == 2:
            return parse_speed_range(speeds)
        speeds = [speeds]
    values = list(np.ravel(np.asarray(speeds, dtype=object)))
    if not values:
        raise InputError(f"{function} speeds: empty; give at least one speed, e.g. "
                         "['4000 rpm', '6275 rpm']")
    plain = [v for v in values if not isinstance(v, str)]
    if plain and not si:
        first = plain[0].item() if isinstance(plain[0], np.generic) else plain[0]
        raise InputError(
            f"{function} speeds: plain numbers ({first!r}, ...) have no unit; give strings "
            f"with units, e.g. ['{first:g} rpm', ...] or '1000 rpm:6000 rpm:51', or speeds "
            "in rad/s with si=True" if isinstance(first, int | float) else
            f"{function} speeds: {first!r} is not a speed; give strings with units, e.g. "
            "['4000 rpm', '6275 rpm'], or numbers in rad/s with si=True")
    return np.array([parse_operating("speed", v, f"{function} speeds[{i}]", si)
                     for i, v in enumerate(values)], dtype=float)


def parse_speed_range(text: str) -> FloatArray:
    """Speeds from ``START:STOP:N``, in rad/s; START and STOP carry their unit.

    >>> parse_speed_range("600 rpm:1200 rpm:3") * 60 / (2 * math.pi)
    array([ 600.,  900., 1200.])

    Raises
    ------
    InputError
        Not three parts, a plain number (``1500``: give a unit, e.g. ``1500 rpm``), a bad
        number or unit (Hz is refused: pint would read it as rad/s), N < 2, or speeds out of
        range.
    """
    parts = text.split(":")
    if len(parts) != 3:
        raise InputError(f"--speeds {text!r}: expected START:STOP:N, e.g. '500 rpm:6000 rpm:200'")
    ends = [parse_operating("speed", part.strip(), f"--speeds {label}")
            for label, part in zip(("START", "STOP"), parts[:2], strict=True)]
    try:
        n = int(parts[2])
    except ValueError:
        raise InputError(f"--speeds N = {parts[2]!r}: expected a whole number >= 2") from None
    check_range("--speeds N", n, "", low=2, high=1_000_000)
    return np.linspace(ends[0], ends[1], n)
