"""One selector for every mesh-stiffness method: ``build_stiffness(pair, method, **options)``.

Methods (each returns a :class:`~gear_dyn.stiffness.periodic.PeriodicStiffness`):
``rectangular`` (``single``/``double`` in N/m, else from ISO 6336 with mean ``c_gamma b``),
``iso6336``, ``potential_energy``, ``weber`` (Jiang et al. 2018) and ``contact_line``
(``k_l L(p)`` with mean ``c_gamma b``, or ``stiffness_per_length`` in N/m^2). ``fourier_terms``
replaces any curve by its truncated Fourier series. Unknown options are refused.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
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
from gear_dyn.stiffness.weber import (
    MODULI,
    current_modulus,
    weber_modulus,
    weber_pair_stiffness,
)

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


@dataclass(frozen=True)
class StiffnessChoice:
    """The mesh-stiffness method of a pair and why it was chosen (:func:`choose_stiffness`).

    Attributes
    ----------
    method : str
        One of :data:`METHODS`.
    reason : str
        Why, in one line (e.g. ``"helical pair, eps_beta = 1.27: contact-line length"``).
    by_default : bool
        True when no method was given and the rule chose it.
    """

    method: str
    reason: str
    by_default: bool


def choose_stiffness(pair: GearPair, method: str | None = None) -> StiffnessChoice:
    """The mesh-stiffness method of ``pair``: ``method`` if given, else the default rule.

    The rule, the one place that decides the default (scenes without ``[stiffness] method``
    and :func:`build_stiffness` without ``method`` both come here):

    - a helical pair (helix angle not 0, so eps_beta > 0) gets ``contact_line``,
      ``k(t) = k_l L(t)`` with the ISO 6336-1 mean c_gamma b. Its contact lines enter and
      leave the field of contact gradually, so the stiffness varies with the total
      contact-line length L(t) (Liu et al. 2017), not in the steps of a spur pair. The
      ``iso6336`` wave steps by 1.75 between floor(eps_a) and floor(eps_a) + 1 transverse
      pairs and ignores eps_beta: a spur wave, too harsh an excitation for a helical pair;
    - a spur pair gets ``iso6336``: the ISO 6336-1 rectangular wave with mean c_gamma b and
      ISO's own step of 1.75 (from c_gamma = c' (0.75 eps_a + 0.25)); the lines of a spur
      pair do enter and leave the field at once, so a rectangular wave is its shape.

    A method given is kept as given; its reason says so, and for a helical pair given a
    rectangular wave it adds that the wave is a spur wave.

    Parameters
    ----------
    pair : GearPair
    method : str or None
        The method asked for (None: the rule above). Not validated here
        (:func:`build_stiffness` does).

    Returns
    -------
    StiffnessChoice

    Examples
    --------
    >>> import math
    >>> from gear_dyn.geometry import GearPair
    >>> choose_stiffness(GearPair(19, 48, 3.2e-3, math.radians(20), 16e-3)).method
    'iso6336'
    >>> choose_stiffness(GearPair(18, 70, 3e-3, math.radians(20), 40e-3,
    ...                           helix_angle=math.radians(15))).method
    'contact_line'
    """
    helical = pair.helix_angle != 0.0
    eps_b = f"eps_beta = {pair.overlap_ratio:.3g}"
    if method is not None:
        reason = "as given"
        if helical and method in ("iso6336", "rectangular"):
            reason += (f"; a spur wave for a helical pair ({eps_b}): contact_line follows its "
                       "contact-line length")
        return StiffnessChoice(method, reason, False)
    if helical:
        return StiffnessChoice("contact_line", f"helical pair, {eps_b}: contact-line length",
                               True)
    return StiffnessChoice("iso6336", "spur pair: ISO 6336-1 rectangular wave", True)


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
    """The :class:`~gear_dyn.stiffness.tooth.ToothOptions` in a method's options (fillet radius,
    bore radii, plane
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


def build_stiffness(pair: GearPair, method: str | None = None, *,
                    fourier_terms: int | None = None, **options: Any) -> PeriodicStiffness:
    """Mesh stiffness of ``pair`` by ``method`` (cached per pair, method and options).

    Parameters
    ----------
    pair : GearPair
        The gear pair.
    method : str or None
        One of ``rectangular``, ``iso6336``, ``potential_energy``, ``weber``,
        ``contact_line``; None: the default of :func:`~gear_dyn.stiffness.select.choose_stiffness`
        (``contact_line`` for a
        helical pair, ``iso6336`` for a spur pair).
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

    See Also
    --------
    :func:`~gear_dyn.stiffness.iso6336.iso6336_stiffness`
        The ISO 6336-1 values behind ``iso6336``.
    :func:`~gear_dyn.stiffness.periodic.rectangular_stiffness`
        The rectangular wave behind ``rectangular``.
    :class:`~gear_dyn.stiffness.periodic.PeriodicStiffness` : The face of the result.

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
    method = choose_stiffness(pair, method).method
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


def method_scope(pair: GearPair, method: str,
                 options: Mapping[str, Any] | None = None) -> tuple[str, str]:
    """What ``method`` includes and what it leaves out, one line each, for ``pair``.

    Read from the code of each method (:mod:`.iso6336`, :mod:`.potential_energy`,
    :mod:`.weber`, :mod:`.contact_line`, :mod:`.mesh`), so that the spread of their means
    (``gear-dyn stiffness``) is explained, not only shown. ``options`` (as for
    :func:`build_stiffness`) changes the Weber and rectangular lines.

    Returns
    -------
    (includes, leaves_out) : tuple of str

    Raises
    ------
    InputError
        Unknown method.
    """
    opts = dict(options or {})
    helical = pair.helix_angle != 0.0
    iso_in = ("empirical (ISO 6336-1 method B): c' = C_M C_R C_B cos(beta) (E/E_steel) / q', "
              "q' fitted in the virtual teeth numbers and profile shifts, C_M = 0.8 (solid "
              "blank), C_R = 1; c_gamma = c' (0.75 eps_alpha + 0.25)")
    wave_out = ("variation along the path of contact (one level per number of pairs: a "
                "rectangular wave stepping by 1.75)"
                + (", eps_beta (a spur wave for this helical pair)" if helical else "")
                + ", rim and web flexibility (C_R = 1), load (unless a line load is given)")
    slices = ("; helical: the transverse curve averaged over uncoupled face slices"
              if helical else "")
    slices_out = ("coupling between face slices (independent springs), the helical tooth's "
                  "normal section (the transverse section is used: stiffer as beta grows), "
                  if helical else "")
    if method == "iso6336":
        return iso_in, wave_out
    if method == "rectangular":
        if opts.get("single") is not None:
            given = "the single and double levels given (double = 1.75 single by default)"
            return given, "tooth geometry: every figure is the user's; " + wave_out
        return "as iso6336 (the ISO levels c' b and 1.75 c' b)", wave_out
    if method == "potential_energy":
        return ("Hertz 2/(pi B E*), tooth bending, shear and axial energy of a variable-section "
                "cantilever clamped at the root chord (both gears), fillet foundation (Sainsot "
                "et al. 2004)" + slices,
                slices_out + "load dependence (Hertz term constant along the path and linear), "
                "rim and web beyond the foundation term")
    if method == "weber":
        modulus = str(opts.get("weber_modulus") or "jiang2018")
        e_w = {"jiang2018": weber_modulus(1.0, pair.poisson1), "plane_stress": 1.0,
               "plane_strain": 1.0 / (1 - pair.poisson1**2)}.get(modulus, float("nan"))
        foundation = bool(opts.get("weber_foundation", False))
        includes = (f"sliced-cantilever bending, shear and axial (Jiang et al. 2018) with the "
                    f"{modulus} modulus {e_w:.3g} E, Hertz 4 (1 - nu^2)/(pi E B)"
                    + (", fillet foundation (Sainsot et al. 2004)" if foundation else "")
                    + slices)
        out = slices_out + ("" if foundation else
                            "the fillet-foundation (body) deflection, the largest compliance "
                            "term (weber_foundation = true adds it), ")
        return includes, out + "load dependence"
    if method == "contact_line":
        if opts.get("stiffness_per_length") is not None:
            includes = "the stiffness per contact-line length given, times L(t)"
        else:
            includes = ("the ISO 6336-1 mean c_gamma b scaled by the total contact-line "
                        "length: k = k_l L(t), k_l = c_gamma b / mean L")
        return includes, ("variation along each line and along the path (tip and root softer "
                          "than the pitch point), tooth geometry beyond ISO's empirical mean")
    raise InputError(f"stiffness method = {method!r}: valid values are {', '.join(METHODS)}")


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


def stiffness_options_from_table(table: Mapping[str, Any], pair: GearPair | None = None
                                 ) -> tuple[str, dict[str, Any]]:
    """``(method, options)`` for :func:`build_stiffness` from a parsed ``[stiffness]`` table.

    Keys left at None are dropped; a key that the chosen method does not use is an error.
    A table without ``method`` takes the default of :func:`choose_stiffness` for ``pair``.

    Raises
    ------
    InputError
        A key given that the method does not take (names the key and the method); no method
        and no pair to choose the default for.
    """
    method = table.get("method")
    if method is None:
        if pair is None:
            raise InputError("stiffness.method not given and no gear pair to choose the "
                             "default method for")
        method = choose_stiffness(pair).method
    method = str(method)
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
