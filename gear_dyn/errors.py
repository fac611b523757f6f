"""One error hierarchy for gear_dyn.

- :class:`GearDynError` is the root of every error the toolkit raises on purpose.
- :class:`InputError` (also a :class:`ValueError`) is a user mistake: a bad scene value, an
  impossible gear pair, a bad CLI flag or FMU parameter. The CLI maps it to exit code 2.
- :class:`SolverError` (also a :class:`RuntimeError`) is a numerical failure: the integrator
  gave up, returned non-finite values, or the linear system is unstable where that was not
  allowed. The CLI maps it to exit code 3.
"""

from __future__ import annotations

import math
import sys
import warnings
from pathlib import Path

#: folder of the package: a warning names the first caller outside it
_PACKAGE_DIR = str(Path(__file__).resolve().parent)


class GearDynError(Exception):
    """Root of all errors raised on purpose by gear_dyn.

    See Also
    --------
    :class:`~gear_dyn.errors.InputError` : A user mistake.
    :class:`~gear_dyn.errors.SolverError` : A failed numerical solution.

    Examples
    --------
    >>> import math
    >>> from gear_dyn import GearPair
    >>> try:
    ...     GearPair(19, 48, -3.2e-3, math.radians(20), 16e-3)
    ... except GearDynError as err:
    ...     print(type(err).__name__)
    InputError
    """


class InputError(GearDynError, ValueError):
    """A user mistake: bad value, unit, key or combination of parameters.

    A ``ValueError`` as well; the CLI turns it into exit status 2 and one line on stderr.

    See Also
    --------
    :class:`~gear_dyn.errors.SceneError` : The same in a scene file.
    :class:`~gear_dyn.errors.GearDynError` : The root of gear_dyn's errors.

    Examples
    --------
    >>> from gear_dyn import rectangular_stiffness
    >>> rectangular_stiffness(0.8, 1e8, 1.5e8)
    Traceback (most recent call last):
    ...
    gear_dyn.errors.InputError: contact_ratio = 0.8 ...
    """


class SceneError(InputError):
    """An error in a scene file; the message names the file and the key path.

    See Also
    --------
    :func:`~gear_dyn.scene.load_scene` : Raises it for a scene file.
    :func:`~gear_dyn.scene.parse_scene` : Raises it for a scene given as a dict.
    :class:`~gear_dyn.errors.InputError` : Its base class.

    Examples
    --------
    >>> from gear_dyn import parse_scene
    >>> parse_scene({"gear": {}})
    Traceback (most recent call last):
    ...
    gear_dyn.errors.SceneError: <dict>: ...
    """


class SolverError(GearDynError, RuntimeError):
    """The numerical solution failed; the message carries the solver's own text and advice.

    A ``RuntimeError`` as well.

    See Also
    --------
    :func:`~gear_dyn.analysis.study.simulate` : Raises it when the integration fails.
    :class:`~gear_dyn.solvers.settings.SolverSettings` : The method, tolerances and work budget.

    Examples
    --------
    >>> issubclass(SolverError, RuntimeError)
    True
    """


def _fmt(value: object) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    return repr(value)


def check_range(
    name: str,
    value: float,
    unit: str = "",
    *,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    high_open: bool = False,
) -> float:
    """Check that ``value`` is a finite number inside ``[low, high]``.

    Parameters
    ----------
    name : str
        Field name used in the message.
    value : float
        Value to check (SI units).
    unit : str
        SI unit of the value, for the message ("" for dimensionless).
    low, high : float or None
        Bounds; None means unbounded.
    low_open, high_open : bool
        Exclude the bound itself.

    Returns
    -------
    float
        ``value`` as a float.

    Raises
    ------
    InputError
        If the value is not a finite real number or lies outside the range.
    """
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(
            f"{name} = {_fmt(value)}: expected a number{_unit_txt(unit)}, "
            f"valid range {range_text(low, high, low_open, high_open, unit)}"
        ) from None
    if isinstance(value, bool):
        raise InputError(f"{name} = {value!r}: expected a number{_unit_txt(unit)}, not a boolean")
    if not (math.isfinite(v) and in_range(v, low, high, low_open, high_open)):
        raise InputError(
            f"{name} = {_fmt(v)}{(' ' + unit) if unit else ''} is out of range: "
            f"valid range {range_text(low, high, low_open, high_open, unit)}"
        )
    return v


def in_range(value: float, low: float | None, high: float | None, low_open: bool = False,
             high_open: bool = False) -> bool:
    """Whether ``value`` lies inside the bounds (None: unbounded; ``*_open``: bound excluded)."""
    return ((low is None or (value > low if low_open else value >= low))
            and (high is None or (value < high if high_open else value <= high)))


def current_name(name: str, renamed: dict[str, str], where: str, kind: str, source: str) -> str:
    """``name``, or the name an old name (``renamed``: old -> new) now has, with a
    :class:`FutureWarning` that names ``where`` (e.g. a scene's key path).

    The warning points at the first caller outside gear_dyn (a user's script, or the CLI's
    caller), not at the library line that noticed the old name.

    Parameters
    ----------
    kind, source : str
        What the name is (e.g. "rule") and where it comes from, for the message.
    """
    new = renamed.get(name)
    if new is None:
        return name
    level, frame = 2, sys._getframe(1)
    while frame.f_back is not None and frame.f_code.co_filename.startswith(_PACKAGE_DIR):
        frame, level = frame.f_back, level + 1
    warnings.warn(f"{where} = {name!r} is the old name of the {kind} {new!r} ({source}); "
                  f"write {new!r}: the old name will be removed", FutureWarning, stacklevel=level)
    return new


def _unit_txt(unit: str) -> str:
    return f" in {unit}" if unit else ""


def range_text(
    low: float | None,
    high: float | None,
    low_open: bool = False,
    high_open: bool = False,
    unit: str = "",
) -> str:
    """Human-readable interval, e.g. ``0 < x <= 1 m``."""
    u = f" {unit}" if unit else ""
    if low is None and high is None:
        return f"any finite number{u}"
    if high is None:
        return f"{'>' if low_open else '>='} {_fmt(low)}{u}"
    if low is None:
        return f"{'<' if high_open else '<='} {_fmt(high)}{u}"
    lo = "<" if low_open else "<="
    hi = "<" if high_open else "<="
    return f"{_fmt(low)} {lo} x {hi} {_fmt(high)}{u}"
