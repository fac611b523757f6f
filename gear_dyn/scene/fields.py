"""Declarative scene fields: name, unit, kind, default and valid range.

Text with a unit is converted at the edge only, by the one rule of :mod:`gear_dyn.units` (an
exact 0 needs no unit: zero in every unit). Values that are already SI floats (an FMU's
parameters, a scene rebuilt from its SI tables) are parsed with ``si=True``.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from gear_dyn.errors import SceneError, in_range
from gear_dyn.units import dimension_text as _dim_text
from gear_dyn.units import is_dimensional, needs_unit_message, parse_quantity, range_in_user_unit

#: the default of a field the scene must give (a required key)
REQUIRED: Any = object()

#: no scene quantity is meaningful below this magnitude in SI units (1e-30 m, N m, kg m^2, ...);
#: such values only underflow the physics to 0 or inf
TINY = 1e-30


def _did_you_mean(word: str, options: Sequence[str]) -> str | None:
    """The closest option, ignoring case (``dop853`` -> ``DOP853``), or None."""
    lower = {o.lower(): o for o in options}
    hint = difflib.get_close_matches(word.lower(), list(lower), n=1)
    return lower[hint[0]] if hint else None


@dataclass(frozen=True)
class Field:
    """One scene key.

    Parameters
    ----------
    name : str
        TOML key.
    unit : str
        SI unit the value is converted to ("" = dimensionless, "rad" for angles).
    kind : str
        ``"float"``, ``"int"``, ``"str"``, ``"bool"``, ``"floatlist"``.
    default : object
        Default value (SI), ``REQUIRED`` if the key must be given, None if optional.
    low, high : float or None
        Valid range in SI units.
    low_open, high_open : bool
        Exclude the bound.
    choices : tuple of str or None
        Allowed strings for kind ``"str"``.
    renamed : callable or None
        For kind ``"str"``: ``renamed(value, where)`` gives the current name of an old choice
        (with a FutureWarning naming ``where``) and returns any other value unchanged.
    doc : str
        One-line description (for the README and error messages).
    """

    name: str
    unit: str = ""
    kind: str = "float"
    default: Any = REQUIRED
    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    choices: tuple[str, ...] | None = None
    doc: str = ""
    renamed: Callable[[str, str], str] | None = None

    def parse(self, raw: Any, where: str, si: bool = False) -> Any:
        """Convert a raw TOML value to SI and check it; ``where`` is 'file: section.key'.

        ``si``: plain numbers are SI values (not refused for want of a unit).
        """
        if self.kind == "str":
            if not isinstance(raw, str):
                raise SceneError(f"{where} = {raw!r}: expected a string")
            if self.renamed is not None:
                raw = self.renamed(raw, where)
            if self.choices is not None and raw not in self.choices:
                hint = _did_you_mean(raw, self.choices)
                mean = f" (did you mean {hint!r}?)" if hint else ""
                raise SceneError(
                    f"{where} = {raw!r}: valid choices are {', '.join(self.choices)}{mean}"
                )
            return raw
        if self.kind == "bool":
            if not isinstance(raw, bool):
                raise SceneError(f"{where} = {raw!r}: expected true or false")
            return raw
        if self.kind == "floatlist":
            if not isinstance(raw, list) or not raw:
                raise SceneError(
                    f"{where} = {raw!r}: expected a non-empty list of {_dim_text(self.unit)}"
                )
            return [self._number(v, f"{where}[{i}]", si) for i, v in enumerate(raw)]
        value = self._number(raw, where, si)
        if self.kind == "int":
            if value != int(value):
                raise SceneError(f"{where} = {raw!r}: expected a whole number")
            return int(value)
        return value

    def _number(self, raw: Any, where: str, si: bool = False) -> float:
        unit_txt = f" {self.unit}" if self.unit else ""
        # the range in the unit the user wrote ("50 deg" -> "0 <= x <= 45 deg"), else SI
        rng = range_in_user_unit(raw, self.unit, self.low, self.high, self.low_open,
                                 self.high_open)
        if isinstance(raw, bool) or not isinstance(raw, int | float | str):
            raise SceneError(
                f"{where} = {raw!r}: expected {_dim_text(self.unit)}; valid range {rng}"
            )
        if isinstance(raw, str):
            value = parse_quantity(raw, self.unit, where, rng, SceneError, self._in_range)
        else:
            value = float(raw)
            if not si and is_dimensional(self.unit) and value != 0.0 and math.isfinite(value):
                raise SceneError(needs_unit_message(where, raw, self.unit, self._in_range))
        if not math.isfinite(value):
            raise SceneError(f"{where} = {raw!r}: must be a finite number; valid range {rng}")
        if value != 0.0 and abs(value) < TINY:
            raise SceneError(
                f"{where} = {raw!r}: {abs(value):.3g}{unit_txt} is below the smallest meaningful "
                f"magnitude {TINY:g}{unit_txt} (use 0 if you mean zero); valid range {rng}"
            )
        if not self._in_range(value):
            shown = raw if isinstance(raw, str) else f"{value:.6g}{unit_txt}"
            raise SceneError(f"{where} = {shown!r} is out of range: valid range {rng}")
        return value

    def _in_range(self, value: float) -> bool:
        """Whether the SI ``value`` lies in the field's valid range."""
        return in_range(value, self.low, self.high, self.low_open, self.high_open)


@dataclass(frozen=True)
class Section:
    """A TOML table of the scene: its fields, and whether it may be left out."""

    name: str
    fields: tuple[Field, ...]
    optional: bool = True
    doc: str = ""
    #: model kinds (``[scene] model``) this table applies to; None = every model. A table
    #: present in a scene whose model does not use it is refused, never silently ignored.
    models: tuple[str, ...] | None = None

    def parse(self, raw: Any, source: str, si: bool = False) -> dict[str, Any]:
        """Validated dict of SI values with defaults filled in (``si``: see :meth:`Field.parse`)."""
        where = f"{source}: [{self.name}]"
        if not isinstance(raw, Mapping):
            raise SceneError(f"{where}: expected a table, got {type(raw).__name__}")
        known = {f.name: f for f in self.fields}
        for key in raw:
            if key not in known:
                hint = _did_you_mean(str(key), list(known))
                mean = f"; did you mean {hint!r}?" if hint else ""
                raise SceneError(
                    f"{source}: {self.name}.{key}: unknown key{mean} (valid keys: "
                    f"{', '.join(known)})"
                )
        out: dict[str, Any] = {}
        for f in self.fields:
            if f.name in raw:
                out[f.name] = f.parse(raw[f.name], f"{source}: {self.name}.{f.name}", si)
            elif f.default is REQUIRED:
                raise SceneError(
                    f"{source}: {self.name}.{f.name}: missing required key ({f.doc or f.name}"
                    f"{', ' + f.unit if f.unit else ''})"
                )
            else:
                out[f.name] = f.default
        return out
