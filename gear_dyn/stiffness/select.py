"""One selector for every mesh-stiffness method: ``build_stiffness(pair, method, **options)``.

Methods (each returns a :class:`~gear_dyn.stiffness.periodic.PeriodicStiffness`):
``rectangular`` (``single``/``double`` in N/m, else from ISO 6336 with mean ``c_gamma b``),
``iso6336``, ``potential_energy``, ``weber`` (Jiang et al. 2018) and ``contact_line``
(``k_l L(p)`` with mean ``c_gamma b``, or ``stiffness_per_length`` in N/m^2). ``fourier_terms``
replaces any curve by its truncated Fourier series. Unknown options are refused.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from functools import lru_cache, partial
from typing import Any

import numpy as np

from gear_dyn.choices import PAIR_STIFFNESS_METHODS, STIFFNESS_METHODS
from gear_dyn.errors import InputError, check_range
from gear_dyn.geometry import GearPair
from gear_dyn.stiffness.contact_line import (
    contact_line_breakpoints,
    contact_line_length,
    mean_contact_line_length,
)
from gear_dyn.stiffness.iso6336 import iso6336_stiffness
from gear_dyn.stiffness.mesh import mesh_stiffness_from_pair
from gear_dyn.stiffness.periodic import (
    FloatArray,
    PeriodicStiffness,
    PiecewiseStiffness,
    rectangular_stiffness,
    stepped_stiffness,
)
from gear_dyn.stiffness.potential_energy import potential_energy_pair_stiffness
from gear_dyn.stiffness.tooth import ToothOptions
from gear_dyn.stiffness.weber import MODULI, current_modulus, weber_pair_stiffness

#: the methods of :func:`build_stiffness` (``[stiffness] method``)
METHODS = STIFFNESS_METHODS

#: ISO 6336: c_gamma = c' (0.75 eps_a + 0.25). A rectangular wave with k_double = 1.75 k_single
#: and k_single = c' b has mean c' b (1 + 0.75 (eps_a - 1)) = c_gamma b for 1 <= eps_a < 2.
ISO_DOUBLE_FACTOR = 1.75

_TOOTH_KEYS = ("fillet_radius_coef", "bore_radius1", "bore_radius2", "plane_strain",
               "grid_points")
METHOD_OPTIONS: dict[str, tuple[str, ...]] = {
    "rectangular": ("single", "double", "line_load"),
    "iso6336": ("line_load",),
    "potential_energy": _TOOTH_KEYS + ("samples_per_cycle", "slices"),
    "weber": _TOOTH_KEYS + ("samples_per_cycle", "slices", "weber_slices", "weber_modulus",
                        "weber_foundation"),
    "contact_line": ("stiffness_per_length", "line_load"),
}


def _iso_wave(pair: GearPair, opts: Mapping[str, Any], name: str) -> PiecewiseStiffness:
    single, double = opts.get("single"), opts.get("double")
    if single is None:
        if double is not None:
            raise InputError("stiffness.double given without stiffness.single: give both or "
                             "only single (double = 1.75 single)")
        iso = iso6336_stiffness(pair, line_load=opts.get("line_load"))
        k_single = iso.k_single
        k_double = ISO_DOUBLE_FACTOR * k_single
        if pair.contact_ratio >= 2.0:  # n pairs: c' b (0.75 n + 0.25), mean c_gamma b for any eps_a
            return stepped_stiffness(pair.contact_ratio, lambda n: k_single * (0.75 * n + 0.25),
                                     name)
    else:
        k_single = check_range("single", single, "N/m", low=0.0, low_open=True)
        k_double = (ISO_DOUBLE_FACTOR * k_single if double is None
                    else check_range("double", double, "N/m", low=0.0, low_open=True))
    return rectangular_stiffness(pair.contact_ratio, k_single, k_double, name=name)


def tooth_options(opts: Mapping[str, Any]) -> ToothOptions:
    """The :class:`ToothOptions` in a method's options (fillet radius, bore radii, plane
    strain, grid points); other keys are ignored."""
    kw = {k: opts[k] for k in _TOOTH_KEYS if k in opts and opts[k] is not None}
    return ToothOptions(**kw)



def _int_opt(key: str, value: Any, default: int, low: int) -> int:
    """``value`` as an int >= ``low`` (``default`` for None), else an InputError naming ``key``."""
    if value is None:
        return default
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < low:
        raise InputError(f"{key} = {value!r}: valid range >= {low} (integer)")
    return int(value)


def _contact_line(pair: GearPair, opts: Mapping[str, Any]) -> PiecewiseStiffness:
    k_l = opts.get("stiffness_per_length")
    if k_l is None:
        iso = iso6336_stiffness(pair, line_load=opts.get("line_load"))
        if not iso.k_mesh > 0:  # line_load = 0 scales ISO's c' to zero: no stiffness at all
            raise InputError(f"line_load = {opts.get('line_load')!r} N/m gives an ISO 6336 "
                             "mesh stiffness of 0 N/m: valid range line_load > 0 N/m")
        k_l = iso.k_mesh / mean_contact_line_length(pair)
    else:
        k_l = check_range("stiffness_per_length", k_l, "N/m^2", low=0.0, low_open=True)
    edges = np.append(contact_line_breakpoints(pair), 1.0)
    lo, hi = edges[:-1], edges[1:]
    eps = 1e-12 * (hi - lo)  # just inside each piece (L(p) is linear between breakpoints)
    ends = k_l * contact_line_length(pair, np.stack([lo + eps, hi - eps], axis=1))
    return PiecewiseStiffness(edges, tuple(zip(np.stack([lo, hi], axis=1), ends, strict=True)),
                              name="contact_line")


@lru_cache(maxsize=128)
def _build_cached(pair: GearPair, method: str,
                  items: tuple[tuple[str, Any], ...]) -> PeriodicStiffness:
    """The stiffness of :func:`build_stiffness`, cached per pair, method and sorted options."""
    opts = dict(items)
    if method in ("rectangular", "iso6336"):
        return _iso_wave(pair, opts, method)
    if method == "contact_line":
        return _contact_line(pair, opts)
    samples = _int_opt("samples_per_cycle", opts.get("samples_per_cycle"), 200, 4)
    slices = opts.get("slices")
    slices = None if slices is None else _int_opt("slices", slices, 1, 1)
    return mesh_stiffness_from_pair(pair, _pair_fn(method, opts), samples_per_cycle=samples,
                                    name=method, slices=slices)


def _pair_fn(method: str, opts: Mapping[str, Any]) -> Any:
    """``K(pair, s)`` of the single-pair method ``potential_energy`` or ``weber`` with its
    tooth (and Weber) options."""
    tooth = tooth_options(opts)
    if method == "potential_energy":
        return partial(potential_energy_pair_stiffness, options=tooth)
    modulus = current_modulus(opts.get("weber_modulus") or "jiang2018", "weber_modulus")
    if modulus not in MODULI:
        raise InputError(f"weber_modulus = {modulus!r}: valid values are {', '.join(MODULI)}")
    return partial(weber_pair_stiffness, options=tooth, modulus=modulus,
                   slices=_int_opt("weber_slices", opts.get("weber_slices"), 20, 1),
                   foundation=bool(opts.get("weber_foundation", False)))


def _check_method(kind: str, method: str, methods: tuple[str, ...],
                  options: Mapping[str, Any]) -> None:
    """Refuse a method not in ``methods`` or an option it does not take (``kind``: "stiffness"
    or "pair stiffness", for the messages)."""
    if method not in methods:
        raise InputError(f"{kind} method = {method!r}: valid values are {', '.join(methods)}")
    unknown = sorted(set(options) - set(METHOD_OPTIONS[method]))
    if unknown:
        raise InputError(f"unknown option(s) {', '.join(unknown)} for {kind} method {method!r}; "
                         f"valid: {', '.join(METHOD_OPTIONS[method]) or 'none'}")


def pair_stiffness_function(pair: GearPair, method: str = "potential_energy",
                            options: Mapping[str, Any] | None = None) -> Callable[
        [FloatArray], FloatArray]:
    """The unmodified single-pair stiffness ``K(s)`` (N/m, s in m from T1) of a method.

    Parameters
    ----------
    pair : GearPair
    method : str
        ``"potential_energy"`` (Hertz, bending, shear, axial, fillet foundation; Wang et al.
        2024, eq. 5) or ``"weber"`` (Jiang et al. 2018).
    options : mapping or None
        Tooth options as for :func:`build_stiffness`: ``fillet_radius_coef``,
        ``bore_radius1``, ``bore_radius2`` (m), ``plane_strain``, ``grid_points``; Weber also
        ``weber_slices``, ``weber_modulus``, ``weber_foundation``. ``samples_per_cycle`` and
        ``slices`` (mesh options) are accepted and unused.

    Raises
    ------
    InputError
        Unknown method or option, bad option values.
    """
    opts = {k: v for k, v in (options or {}).items() if v is not None}
    _check_method("pair stiffness", method, PAIR_STIFFNESS_METHODS, opts)
    return partial(_pair_fn(method, opts), pair)


def build_stiffness(pair: GearPair, method: str = "iso6336", *,
                    fourier_terms: int | None = None, **options: Any) -> PeriodicStiffness:
    """Mesh stiffness of ``pair`` by ``method`` (cached per pair, method and options).

    Parameters
    ----------
    pair : GearPair
    method : str
        One of ``rectangular``, ``iso6336``, ``potential_energy``, ``weber``, ``contact_line``.
    fourier_terms : int or None
        If given (>= 1), return the Fourier series truncated at that many harmonics.
    **options
        Method options (None values mean "default"):

        - rectangular: ``single``, ``double`` (N/m), ``line_load`` (N/m, ISO load correction);
        - iso6336: ``line_load``;
        - potential_energy / weber: ``samples_per_cycle`` (200), ``slices`` (helical pairs:
          None = continuous face slicing, or a number of discrete slices),
          ``fillet_radius_coef``, ``bore_radius1``, ``bore_radius2`` (m),
          ``plane_strain`` (bool), ``grid_points``; weber also ``weber_slices`` (20) and
          ``weber_modulus`` ("jiang2018", "plane_stress", "plane_strain"), ``weber_foundation``
          (bool, add the Sainsot fillet-foundation term);
        - contact_line: ``stiffness_per_length`` (N/m^2), ``line_load``.

    Returns
    -------
    PeriodicStiffness
        Named after the method.

    Raises
    ------
    InputError
        Unknown method or option, bad values.

    Examples
    --------
    >>> import math
    >>> from gear_dyn.geometry import GearPair
    >>> pair = GearPair(19, 48, 3.2e-3, math.radians(20), 16e-3)
    >>> k = build_stiffness(pair, "iso6336")
    >>> from gear_dyn.stiffness.iso6336 import iso6336_stiffness
    >>> abs(k.mean / iso6336_stiffness(pair).k_mesh - 1) < 1e-12
    True
    """
    if method == "iso6336" and ("single" in options or "double" in options):
        raise InputError("stiffness method 'iso6336' takes no single/double values; use "
                         "method 'rectangular' to give them")
    _check_method("stiffness", method, METHODS, options)
    items = tuple(sorted((k, v) for k, v in options.items() if v is not None))
    try:
        hash(items)
    except TypeError:
        raise InputError(f"stiffness options must be numbers, strings or booleans, got "
                         f"{dict(items)!r}") from None
    k = _build_cached(pair, method, items)
    if fourier_terms is None:
        return k
    return k.truncated(_int_opt("fourier_terms", fourier_terms, 1, 1))


#: scene key -> build_stiffness option (the [stiffness] TOML table, gear_dyn/scene/core.py)
SCENE_KEYS = {
    "single": "single",
    "double": "double",
    "samples_per_cycle": "samples_per_cycle",
    "face_slices": "slices",
    "fillet_radius_coef": "fillet_radius_coef",
    "bore_radius_pinion": "bore_radius1",
    "bore_radius_gear": "bore_radius2",
    "plane_strain": "plane_strain",
    "weber_slices": "weber_slices",
    "weber_modulus": "weber_modulus",
    "weber_foundation": "weber_foundation",
    "per_length": "stiffness_per_length",
}


def stiffness_options_from_table(table: Mapping[str, Any]) -> tuple[str, dict[str, Any]]:
    """``(method, options)`` for :func:`build_stiffness` from a parsed ``[stiffness]`` table.

    Keys left at None are dropped; a key that the chosen method does not use is an error.

    Raises
    ------
    InputError
        A key given that the method does not take (names the key and the method).
    """
    method = str(table.get("method", "iso6336"))
    options: dict[str, Any] = {}
    for key, opt in SCENE_KEYS.items():
        val = table.get(key)
        if val is None:
            continue
        if method in METHOD_OPTIONS and opt not in METHOD_OPTIONS[method]:
            valid = sorted(k for k, o in SCENE_KEYS.items() if o in METHOD_OPTIONS[method])
            raise InputError(
                f"stiffness.{key} does not apply to method {method!r}; keys for this method: "
                f"{', '.join(valid) or 'none besides method and fourier_terms'}"
            )
        options[opt] = val
    return method, options
