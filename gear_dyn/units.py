"""Units: the one unit registry of the process and text -> SI conversion (pint).

One rule everywhere (scene files, CLI options, strings given to the API): a dimensional quantity
carries its unit (``"1500 rpm"``, ``"20 deg"``, ``"200 N*m"``, ``"6 mm"``); a plain number there
is refused with a message proposing readings. Dimensionless quantities stay plain numbers.
``Nm`` (and ``kNm``, ``N.m``, ``N·m``) means newton-metre in torque fields (pint alone reads
``Nm`` as nanometre). In rotational-speed fields ``RPM`` (any case), ``r/min`` and ``rev``
(``rev/min``, ``rev/s``) are read as rpm and turns (pint knows only ``rpm`` and ``turn``).

pint is imported when the first text with a unit other than the plainest ones (``_PLAIN``: a
number and ``mm``, ``deg``, ``rpm``, ``N*m``, ...) is read, and the registry is built once per
process. The spelling rules of our own are the torque and speed ones above. A value out of
range is reported with the range in the unit the user wrote (:func:`range_in_user_unit`).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from functools import lru_cache
from typing import Any

from gear_dyn.errors import InputError, range_text


@lru_cache(maxsize=1)
def registry() -> Any:
    """The process's pint ``UnitRegistry`` (built on first use).

    Built with pint's ``cache_folder=":auto:"`` (parsed definitions cached in the user's cache
    folder): 1.29 s instead of 1.77 s per new process (benchmarks/results/units.md), same
    definitions. Without a usable cache folder (``OSError``) it is built without the cache.
    """
    import pint

    try:
        return pint.UnitRegistry(cache_folder=":auto:")
    except OSError:  # no usable cache folder (e.g. a read-only home): parse the files
        return pint.UnitRegistry()


#: (example unit, words) for each dimension; an exact unit match is tried first
_DIM_NAMES: tuple[tuple[str, str], ...] = (
    ("rad", "an angle (e.g. '20 deg')"),
    ("m", "a length (e.g. '6 mm')"),
    ("kg", "a mass (e.g. '2 kg')"),
    ("s", "a time (e.g. '0.1 s')"),
    ("rad/s", "a rotational speed (e.g. '3319 rpm', '50 rad/s')"),
    ("N*m", "a torque (e.g. '1474.4 N*m' or '1474.4 Nm')"),
    ("N/m**2", "a stiffness per contact-line length (e.g. '14 N/(mm*um)')"),
    ("Pa", "a pressure or modulus (e.g. '207 GPa')"),
    ("kg/m**3", "a density (e.g. '7850 kg/m^3')"),
    ("kg*m**2", "an inertia (e.g. '0.05 kg*m^2')"),
    ("N/m", "a stiffness (e.g. '8e8 N/m')"),
    ("N", "a force (e.g. '1 kN')"),
    ("W", "a power (e.g. '10 kW')"),
)

#: units proposed for a plain number, per SI unit of the field (first = the usual reading)
SUGGESTED_UNITS: dict[str, tuple[str, ...]] = {
    "rad/s": ("rpm", "rad/s"),
    "rad": ("deg", "rad"),
    "m": ("mm", "um", "m"),
    "N*m": ("N*m", "kN*m"),
    "Pa": ("GPa", "MPa", "Pa"),
    "kg/m**3": ("kg/m^3",),
    "kg*m**2": ("kg*m^2",),
    "N/m": ("N/um", "N/m"),
    "N/m**2": ("N/(mm*um)", "N/m^2"),
    "N": ("N", "kN"),
    "s": ("s", "ms"),
    "W": ("kW", "W"),
    "kg": ("kg",),
}

#: torque spellings pint does not read as newton-metre: Nm (nanometre!), kNm, N.m, N·m
_NM_RE = re.compile(r"(?<![A-Za-z_])(k|M)?N\s*(?:m|\.m|·m|⋅m)(?![A-Za-z_])")
#: speed spellings pint does not read: RPM in any case and r/min (rpm); rev (turn)
_RPM_RE = re.compile(r"(?<![A-Za-z_])(?:rpm|r\s*/\s*min)(?![A-Za-z_])", re.IGNORECASE)
_REV_RE = re.compile(r"(?<![A-Za-z_])rev(?![A-Za-z_])", re.IGNORECASE)
#: the number in front of a quantity's unit ("4000", "-1.5e3 ")
_NUMBER_RE = re.compile(r"^\s*[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?\s*")


def dimension_text(unit: str) -> str:
    """What a quantity in the SI ``unit`` is, in words with an example (``"a length ..."``)."""
    if not is_dimensional(unit):
        return "a dimensionless number"
    for example, words in _DIM_NAMES:
        if example == unit:
            return words
    for example, words in _DIM_NAMES[1:]:
        if _dimension(example) == _dimension(unit):
            return words
    return f"a quantity in {unit}"


def _dimension(unit: str) -> str:
    ureg = registry()
    dim = str(ureg.Quantity(1, unit).dimensionality) if unit else ""
    return "" if dim == "dimensionless" else dim


def is_dimensional(unit: str) -> bool:
    """Whether a field in the SI ``unit`` needs a unit when given (angles included)."""
    return bool(unit) and unit not in ("", "dimensionless", "1")


def needs_unit_message(where: str, raw: Any, unit: str,
                       valid: Callable[[float], bool] | None = None) -> str:
    """``speed = 1500: give a unit, e.g. "1500 rpm" (or "1500 rad/s")``.

    ``valid``: the field's range check on an SI value; readings inside the range are proposed
    first (``handbook_a = 9`` -> ``"9 um"`` before ``"9 mm"``).
    """
    number = raw if isinstance(raw, str) else f"{raw:g}" if isinstance(raw, float) else raw
    number = str(number).strip()
    units = _suggested(unit, number)
    if valid is not None:
        units = tuple(sorted(units, key=lambda u: not _reading_valid(number, u, unit, valid)))
    first = f'"{number} {units[0]}"'
    others = " or ".join(f'"{number} {u}"' for u in units[1:])
    alt = f" (or {others})" if others else ""
    return (f"{where} = {number}: give a unit, e.g. {first}{alt}; a plain number is refused "
            f"for {dimension_text(unit).split(' (e.g.')[0]}")


def _reading_valid(number: str, reading: str, unit: str,
                   valid: Callable[[float], bool]) -> bool:
    """Whether ``number`` read in the unit ``reading`` lies in the field's range (SI ``unit``)."""
    try:
        return valid(float(registry().Quantity(float(number), reading).to(unit).magnitude))
    except Exception:  # not a number, or a unit pint cannot convert: no preference
        return False


def _suggested(unit: str, number: str) -> tuple[str, ...]:
    """The proposed units, the likelier reading of this magnitude first (0.006 -> m, 6 -> mm)."""
    units = SUGGESTED_UNITS.get(unit, (unit,))
    try:
        size = abs(float(number))
    except ValueError:
        return units
    si_first = {"m": size < 0.5, "Pa": size >= 1e5, "N/m": size >= 1e5, "N/m**2": size >= 1e5}
    if si_first.get(unit, False):
        units = (unit, *[u for u in units if u != unit])
    return units


def normalise_torque_text(raw: str) -> str:
    """``"200 Nm"`` -> ``"200 N*m"`` (also kNm, N.m, N·m): newton-metre, never nanometre."""
    return _NM_RE.sub(lambda m: f"{m.group(1) or ''}N*m", raw)


def normalise_speed_text(raw: str) -> str:
    """``"4000 RPM"``, ``"4000 r/min"`` -> ``"4000 rpm"``; ``"4000 rev/min"`` ->
    ``"4000 turn/min"``: the usual shaft-speed spellings pint does not read."""
    return _REV_RE.sub("turn", _RPM_RE.sub("rpm", raw))


def _normalised(raw: str, unit: str) -> str:
    """``raw`` with the torque (Nm) or speed (RPM, rev) spellings of a field in ``unit``."""
    if unit and _dimension(unit) == _dimension("N*m"):
        return normalise_torque_text(raw)
    if unit == "rad/s":
        return normalise_speed_text(raw)
    return raw


def range_in_user_unit(raw: Any, unit: str, low: float | None, high: float | None,
                       low_open: bool = False, high_open: bool = False) -> str:
    """The valid range (SI bounds ``low``, ``high`` of a field in ``unit``) as text, in the unit
    the user wrote in ``raw`` (``"50 deg"`` -> ``0 <= x <= 45 deg``); in ``unit`` when ``raw``
    is no text with a unit of that dimension.

    Examples
    --------
    >>> import math
    >>> range_in_user_unit("50 deg", "rad", 0.0, math.radians(45))
    '0 <= x <= 45 deg'
    >>> range_in_user_unit(0.9, "rad", 0.0, math.radians(45))
    '0 <= x <= 0.785398 rad'
    """
    text = _user_unit(raw, unit)
    if text is None:
        return range_text(low, high, low_open, high_open, unit)
    factor = _factor(text, unit)
    lo = None if low is None else float(f"{low / factor:.9g}")
    hi = None if high is None else float(f"{high / factor:.9g}")
    return range_text(lo, hi, low_open, high_open, text)


def _user_unit(raw: Any, unit: str) -> str | None:
    """The unit text after the number in ``raw`` if it converts to ``unit``, else None."""
    if not isinstance(raw, str) or not is_dimensional(unit):
        return None
    m = _NUMBER_RE.match(raw)
    text = raw[m.end():].strip() if m else ""
    if not text:
        return None
    try:
        factor = _factor(text, unit)
    except Exception:  # not a unit, or another dimension: keep the SI unit
        return None
    return text if factor > 0 else None


def _factor(text: str, unit: str) -> float:
    """1 ``text`` (a unit) in the SI ``unit``: from :data:`_PLAIN` or pint."""
    plain = _PLAIN.get(unit, {}).get(text)
    if plain is not None:
        return plain
    return float(registry().Quantity(1.0, _normalised(text, unit)).to(unit).magnitude)


#: SI factors of the plainest spellings, per SI unit of a field: ``"<number> <unit>"`` with one
#: of these is read without pint (importing it and building its registry costs more than the
#: rest of a small command). Each factor is pint's own for that unit, and pint's value is the
#: number times it, so the reading is pint's to the bit (tests/ground/test_units.py compares).
_PLAIN: dict[str, dict[str, float]] = {
    "m": {"m": 1.0, "mm": 1e-3, "um": 1e-6, "cm": 1e-2},
    "rad": {"rad": 1.0, "deg": 0.017453292519943295},
    "Pa": {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "GPa": 1e9},
    "kg/m**3": {"kg/m^3": 1.0, "kg/m**3": 1.0},
    "rad/s": {"rpm": 0.10471975511965977, "rad/s": 1.0},
    "N*m": {"N*m": 1.0, "kN*m": 1e3, "Nm": 1.0},
    "N/m": {"N/m": 1.0, "N/um": 1e6, "N/mm": 1e3},
    "N": {"N": 1.0, "kN": 1e3},
    "kg*m**2": {"kg*m^2": 1.0, "kg*m**2": 1.0},
    "kg": {"kg": 1.0, "g": 1e-3},
    "s": {"s": 1.0, "ms": 1e-3},
    "W": {"W": 1.0, "kW": 1e3},
}


def _plain_reading(raw: str, unit: str) -> float | None:
    """``raw`` in the SI ``unit`` when it is a number and a unit of :data:`_PLAIN` for it,
    else None (pint reads it)."""
    units = _PLAIN.get(unit)
    number = _NUMBER_RE.match(raw) if units else None
    if number is None:
        return None
    factor = units.get(raw[number.end():].strip())  # type: ignore[union-attr]
    return None if factor is None else float(number.group()) * factor


def parse_quantity(raw: str, unit: str, where: str, rng: str,
                   error: type[InputError] = InputError,
                   valid: Callable[[float], bool] | None = None) -> float:
    """``raw`` (text with a unit, e.g. ``"6 mm"``) in the SI ``unit`` (``""``: dimensionless).

    ``where`` names the field and ``rng`` its valid range in messages; ``error`` is the
    exception class raised (an :class:`~gear_dyn.errors.InputError` subclass); ``valid`` (the
    field's range check) orders the readings proposed for a missing unit. In a torque
    field ``Nm`` is newton-metre (in a speed field ``RPM`` and ``r/min`` are rpm, ``rev``
    a turn). A text without a unit (``"1500"``) in a dimensional field is
    refused like a plain number (exact zero excepted: it is zero in every unit).

    Raises
    ------
    InputError
        Unparsable text, an unknown unit (named), a missing unit, a wrong dimension, or Hz for
        a rotational speed (pint would read 1 Hz as 1 rad/s).
    """
    plain = _plain_reading(raw, unit)
    if plain is not None:
        return plain
    import pint

    ureg = registry()
    text = _normalised(raw.strip(), unit)  # torque: Nm is newton-metre; speed: RPM, rev
    try:
        q = ureg.Quantity(text)
    except pint.UndefinedUnitError as exc:
        if not _NUMBER_RE.match(text):  # "six mm": no number in front
            raise error(f"{where} = {raw!r}: not a number with a unit; expected "
                        f"{dimension_text(unit)}") from None
        names = ", ".join(repr(n) for n in exc.unit_names)
        raise error(
            f"{where} = {raw!r}: unknown unit {names}; expected {dimension_text(unit)}"
        ) from None
    except Exception:  # pint raises many types for unparsable text
        raise error(
            f"{where} = {raw!r}: not a number with a unit; expected {dimension_text(unit)}"
        ) from None
    if not isinstance(q, ureg.Quantity):
        q = ureg.Quantity(float(q))
    if is_dimensional(unit) and q.unitless:
        if float(q.magnitude) == 0.0:
            return 0.0  # zero is zero in every unit, written "0" too
        raise error(needs_unit_message(where, raw, unit, valid))
    if (unit == "rad/s" and q.check("1/[time]")
            and "radian" not in str(q.to_root_units().units)):
        # pint takes 1 Hz = 1 1/s = 1 rad/s: 2 pi off for a shaft speed, so refuse it
        raise error(
            f"{where} = {raw!r}: ambiguous unit for a rotational speed (pint reads 1 Hz as "
            "1 rad/s); write it in rpm, rad/s or turn/s"
        )
    try:
        value = float(q.to(unit or "dimensionless").magnitude)
    except pint.DimensionalityError:
        hint = ""
        if _NM_RE.search(raw):  # pint reads Nm as nanometre (or number * metre)
            hint = " (Nm is newton-metre only in torque fields)"
        raise error(
            f"{where} = {raw!r}: wrong unit; expected {dimension_text(unit)}, "
            f"valid range {rng}{hint}"
        ) from None
    except Exception:
        raise error(f"{where} = {raw!r}: not a number with a unit") from None
    return value

