"""The ``[deviations]`` scene table: manufacturing deviations as a transmission error.

The grade (``deviations.grade``, else ``[iso] accuracy_grade``) gives each gear's ISO 1328-1:2013
tolerances (:func:`gear_dyn.modification.deviations.iso1328_tolerances`); explicit values with
units replace them for both gears. The pattern (``random`` with a seed, ``sine``) turns them into
per-tooth pitch deviations and a profile harmonic (:mod:`gear_dyn.modification.deviations`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from gear_dyn.errors import InputError, SceneError
from gear_dyn.geometry import GearPair
from gear_dyn.modification.deviations import (
    PATTERNS,
    PairDeviations,
    Tolerances,
    pair_tolerances,
    sample_deviations,
)
from gear_dyn.scene.fields import Field, Section
from gear_dyn.scene.registry import register_section
from gear_dyn.scene.validated import Scene, scene_error

DEVIATIONS = register_section(Section("deviations", (
    Field("grade", kind="int", default=None, low=1, high=11,
          doc="ISO 1328-1:2013 flank tolerance class of both gears (default [iso] "
              "accuracy_grade)"),
    Field("pattern", kind="str", default="random", choices=PATTERNS,
          doc="random: within the grade, from the seed; sine: F_p once per revolution, "
              "profile harmonics in phase (deterministic); none: no deviations"),
    Field("seed", kind="int", default=1, low=0, high=2**63 - 1,
          doc="seed of the random pattern"),
    Field("f_pt", "m", default=None, low=0.0, high=1e-3,
          doc="single pitch deviation limit (e.g. \"8 um\"; default from the grade)"),
    Field("F_p", "m", default=None, low=0.0, high=1e-2,
          doc="cumulative pitch deviation (default from the grade)"),
    Field("f_falpha", "m", default=None, low=0.0, high=1e-3,
          doc="profile form deviation (default from the grade)"),
    Field("F_beta", "m", default=None, low=0.0, high=1e-2,
          doc="helix deviation, reported only (default from the grade; no single-DOF "
              "excitation)"),
), doc="manufacturing deviations as excitation: pitch (shaft orders, over the hunting period) "
       "and profile form (mesh order) (present = enabled)"))

_KEYS = ("f_pt", "F_p", "f_falpha", "F_beta")


def scene_tolerances(scene: Scene, pair: GearPair) -> tuple[tuple[Tolerances, Tolerances], str]:
    """(pinion, gear) tolerances of the ``[deviations]`` table and where they came from.

    Raises
    ------
    SceneError
        No grade (neither ``deviations.grade`` nor ``[iso] accuracy_grade``) for a value not
        given explicitly.
    """
    t = scene.tables["deviations"]
    grade = t["grade"] if t["grade"] is not None else scene.get("iso")["accuracy_grade"]
    given = {k: t[k] for k in _KEYS if t[k] is not None}
    if grade is None and len(given) < len(_KEYS):
        missing = ", ".join(k for k in _KEYS if k not in given)
        raise SceneError(f"{scene.source}: deviations.grade: missing (set it, or [iso] "
                         f"accuracy_grade, or give {missing} with units)")
    try:
        if grade is None:
            tol = Tolerances(**given)
            return (tol, tol), "[deviations] values"
        base = pair_tolerances(pair, int(grade))
    except InputError as exc:
        raise scene_error(scene.source, exc) from None
    src = f"ISO 1328-1:2013 grade {grade}"
    if given:
        src += f", {', '.join(given)} from [deviations]"
        base = tuple(Tolerances(**{k: given.get(k, getattr(b, k)) for k in _KEYS})
                     for b in base)  # type: ignore[assignment]
    return base, src


def scene_deviations(scene: Scene, pair: GearPair) -> PairDeviations | None:
    """The realisation of the scene's ``[deviations]`` (None without the table)."""
    if not scene.has("deviations"):
        return None
    t = scene.tables["deviations"]
    tol, _src = scene_tolerances(scene, pair)
    try:
        return sample_deviations(pair, tol, t["pattern"], t["seed"])
    except InputError as exc:
        raise scene_error(scene.source, exc) from None


def deviations_summary(scene: Scene, pair: GearPair) -> dict[str, Any] | None:
    """The ``deviations`` entry of a run summary (SI units in the names), or None."""
    if not scene.has("deviations"):
        return None
    t = scene.tables["deviations"]
    tol, src = scene_tolerances(scene, pair)
    dev = scene_deviations(scene, pair)
    assert dev is not None
    return {
        "pattern": t["pattern"], "seed": t["seed"] if t["pattern"] == "random" else None,
        "sources": src,
        "tolerances_m": {name: {k: getattr(x, k) for k in _KEYS}
                         for name, x in zip(("pinion", "gear"), tol, strict=True)},
        "hunting_period_mesh_cycles": math.lcm(pair.z1, pair.z2),
        "pitch_range_line_of_action_m": [float(np.ptp(dev.pitch_pinion)),
                                         float(np.ptp(dev.pitch_gear))],
        "profile_harmonic_amplitude_m": abs(dev.profile),
        "note": "F_beta is reported, not an excitation of the single-DOF model (it enters "
                "ISO 6336-1 K_Hbeta)",
    }
