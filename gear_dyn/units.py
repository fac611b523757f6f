"""Units: the one unit registry of the process and text -> SI conversion (pint).

One rule for scene files, CLI options and API strings: a dimensional quantity carries its unit
(``"3319 rpm"``, ``"20 deg"``, ``"6 mm"``, ``"1474.4 N*m"``); a plain number there is refused
with the readings it could have (:func:`plain_number_message`), never read silently in SI
(``speed = 1500`` would be 1500 rad/s = 14 324 rpm). Zero needs no unit. Dimensionless fields
(ratios, coefficients, counts) stay plain. In torque fields ``Nm`` means newton-metre (pint
alone reads it as nanometre): ``"200 Nm"`` and ``"1.5 kNm"`` work.

pint is imported on first use, and the registry is built once per process.
"""

from __future__ import annotations

import re
from functools import lru_cache
from typing import Any

from gear_dyn.errors import InputError


@lru_cache(maxsize=1)
def registry() -> Any:
    """The process's pint ``UnitRegistry`` (built on first use)."""
    import pint

    return pint.UnitRegistry()


#: what a quantity of each dimension is, by an example unit of that dimension (compared as
#: pint dimensionalities, not strings: their text differs between pint versions)
_DIM_NAMES: tuple[tuple[str, str], ...] = (
    ("m", "a length (e.g. '6 mm')"),
    ("kg", "a mass (e.g. '2 kg')"),
    ("s", "a time (e.g. '0.1 s')"),
    ("1/s", "a rotational speed or rate (e.g. '3319 rpm', '50 rad/s')"),
    ("N*m", "a torque (e.g. '1474.4 N*m')"),
    ("Pa", "a pressure or modulus (e.g. '207 GPa')"),
    ("kg/m**3", "a density (e.g. '7850 kg/m^3')"),
    ("kg*m**2", "an inertia (e.g. '0.05 kg*m^2')"),
    ("N/m", "a stiffness (e.g. '8e8 N/m')"),
    ("N/m**2", "a stiffness per length (e.g. '1.5e10 N/m^2')"),
    ("N", "a force (e.g. '1 kN')"),
    ("W", "a power (e.g. '10 kW')"),
)


def dimension_text(unit: str) -> str:
    """What a quantity in ``unit`` is, with an example (for messages)."""
    if unit == "rad":
        return "an angle (e.g. '20 deg')"
    for example, text in _DIM_NAMES:
        if example == unit:
            return text
    ureg = registry()
    dim = ureg.Quantity(1, unit).dimensionality if unit else None
    if dim is None or not dim:
        return "a dimensionless number" if unit in ("", "rad") or dim is None else (
            f"a quantity in {unit}")
    for example, text in _DIM_NAMES:
        if ureg.Quantity(1, example).dimensionality == dim:
            return text
    return f"a quantity in {unit}"


#: suggested units for a plain number, by the SI unit of the field: (first, second reading)
SUGGESTED_UNITS: dict[str, tuple[str, str]] = {
    "rad/s": ("rpm", "rad/s"),
    "rad": ("deg", "rad"),
    "m": ("mm", "m"),
    "N*m": ("N*m", "kN*m"),
    "Pa": ("GPa", "MPa"),
    "N/m": ("N/m", "N/um"),
    "N/m**2": ("N/m^2", "N/(mm*um)"),
    "kg*m**2": ("kg*m^2", "g*mm^2"),
    "kg/m**3": ("kg/m^3", "g/cm^3"),
    "s": ("s", "ms"),
    "N": ("N", "kN"),
}


def plain_number_message(where: str, value: float, unit: str) -> str:
    """The refusal of a plain number in a dimensional field, with the readings it could have:
    ``speed = 1500: give a unit, e.g. "1500 rpm" (or "1500 rad/s")``."""
    first, second = SUGGESTED_UNITS.get(unit, (unit, unit))
    shown = f"{value:.12g}"
    alt = f' (or "{shown} {second}")' if second != first else ""
    return (f'{where} = {shown}: give a unit, e.g. "{shown} {first}"{alt}; a plain number is '
            "not read in SI for a dimensional quantity")


def _newton_metre(raw: str, unit: str) -> str:
    """``Nm`` -> ``N*m`` (and ``kNm`` -> ``kN*m``) in torque fields: engineers write Nm for
    newton-metre, which pint reads as nanometre."""
    if unit != "N*m":
        return raw
    return re.sub(r"(?<![A-Za-z])(k|M)?Nm(?![A-Za-z])", lambda m: f"{m.group(1) or ''}N*m", raw)


def parse_quantity(raw: str, unit: str, where: str, rng: str,
                   error: type[InputError] = InputError) -> float:
    """``raw`` (text with a unit, e.g. ``"6 mm"``) in the SI ``unit`` (``""``: dimensionless).

    ``where`` names the field and ``rng`` its valid range in messages; ``error`` is the
    exception class raised (an :class:`~gear_dyn.errors.InputError` subclass).

    Raises
    ------
    InputError
        Unparsable text, a wrong dimension, or Hz for a rotational speed (pint would read
        1 Hz as 1 rad/s).
    """
    import pint

    ureg = registry()
    try:
        q = ureg.Quantity(_newton_metre(raw.strip(), unit))
    except Exception:  # pint raises many types for unparsable text
        raise error(
            f"{where} = {raw!r}: not a number with a unit; expected {dimension_text(unit)}"
        ) from None
    if not isinstance(q, ureg.Quantity):
        q = ureg.Quantity(float(q))
    if unit and q.unitless:
        if float(q.magnitude) == 0.0:
            return 0.0  # zero is zero in every unit
        raise error(plain_number_message(where, float(q.magnitude), unit))
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
        raise error(
            f"{where} = {raw!r}: wrong unit; expected {dimension_text(unit)}, "
            f"valid range {rng}"
        ) from None
    except Exception:
        raise error(f"{where} = {raw!r}: not a number with a unit") from None
    return value
