"""Units: the one unit registry of the process and text -> SI conversion (pint).

pint is imported on first use, and the registry is built once per process.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

from gear_dyn.errors import InputError


@lru_cache(maxsize=1)
def registry() -> Any:
    """The process's pint ``UnitRegistry`` (built on first use).

    pint keeps its parsed definition files in its on-disk cache (``cache_folder=":auto:"``, the
    user's cache folder), which makes a new process's registry about 3x faster to build; the
    definitions, hence every conversion and message, are the same. Where the cache cannot be
    used (e.g. a read-only home), the registry is built from the definition files as before.
    """
    import pint

    try:
        return pint.UnitRegistry(cache_folder=":auto:")
    except Exception:  # pragma: no cover - unusable cache folder: build without it
        return pint.UnitRegistry()


_DIM_NAMES = {
    "[length]": "a length (e.g. '6 mm')",
    "": "a dimensionless number",
    "[mass]": "a mass (e.g. '2 kg')",
    "[time]": "a time (e.g. '0.1 s')",
    "1 / [time]": "a rotational speed or rate (e.g. '3319 rpm', '50 rad/s')",
    "[length] ** 2 * [mass] / [time] ** 2": "a torque (e.g. '1474.4 N*m')",
    "[mass] / [length] / [time] ** 2": "a pressure or modulus (e.g. '207 GPa')",
    "[mass] / [length] ** 3": "a density (e.g. '7850 kg/m^3')",
    "[length] ** 2 * [mass]": "an inertia (e.g. '0.05 kg*m^2')",
    "[mass] / [time] ** 2": "a stiffness (e.g. '8e8 N/m')",
    "[length] * [mass] / [time] ** 2": "a force (e.g. '1 kN')",
    "[length] ** 2 * [mass] / [time] ** 3": "a power (e.g. '10 kW')",
}


def dimension_text(unit: str) -> str:
    ureg = registry()
    dim = str(ureg.Quantity(1, unit).dimensionality) if unit else ""
    if dim == "dimensionless":
        dim = ""
    return _DIM_NAMES.get(dim, f"a quantity in {unit}")


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
        q = ureg.Quantity(raw.strip())
    except Exception:  # pint raises many types for unparsable text
        raise error(
            f"{where} = {raw!r}: not a number with a unit; expected {dimension_text(unit)}"
        ) from None
    if not isinstance(q, ureg.Quantity):
        q = ureg.Quantity(float(q))
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
