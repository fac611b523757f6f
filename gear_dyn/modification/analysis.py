"""Relief cases side by side: loaded contact, load sharing and contact stress along the path,
and the table row each case contributes (what ``gear-dyn contact`` and the examples report)."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.geometry import GearPair
from gear_dyn.modification.contact import LoadedContact, PathView, loaded_contact
from gear_dyn.modification.relief import (
    RULES,
    ProfileModification,
    height_from_length,
    recommended_relief,
)
from gear_dyn.modification.stress import contact_stress

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class ReliefCase:
    """Loaded-contact results of one relief case.

    Attributes
    ----------
    name : str
    modification : ProfileModification or None
    contact : LoadedContact
    path : PathView
        Load sharing along the path of contact.
    stress, half_width : ndarray
        Hertz contact stress (Pa) and half-width (m) along ``path.position``.
    """

    name: str
    modification: ProfileModification | None
    contact: LoadedContact
    path: PathView
    stress: FloatArray
    half_width: FloatArray

    def row(self) -> dict[str, Any]:
        """Table row: amounts, lengths, heights, peak stress, static TE, single-contact zone.

        Positions are in m from T1 along the line of action (``*_from_a_m``: from the start of
        contact A). Keys carry their SI unit.
        """
        pair = self.contact.pair
        out: dict[str, Any] = {"case": self.name}
        for gear, name in ((1, "pinion"), (2, "gear")):
            r = None if self.modification is None else getattr(self.modification, name)
            out[f"amount_{name}_m"] = 0.0 if r is None else r.amount
            out[f"length_{name}_m"] = 0.0 if r is None else r.length
            out[f"height_{name}_m"] = 0.0 if r is None else height_from_length(pair, gear,
                                                                               r.length)
            out[f"curve_{name}"] = None if r is None else r.curve
        out["peak_stress_pa"] = float(np.max(self.stress))
        out["peak_to_peak_static_te_m"] = self.contact.peak_to_peak_error
        out["mean_static_te_m"] = float(np.mean(self.contact.static_transmission_error().value(
            np.linspace(0, 1, 2001, endpoint=False))))
        out["mean_loaded_stiffness_n_per_m"] = self.contact.mesh_stiffness().mean
        zone = self.contact.single_contact_zone()
        s_a = pair.start_of_contact
        out["single_contact_start_m"] = None if zone is None else zone[0]
        out["single_contact_end_m"] = None if zone is None else zone[1]
        out["single_contact_start_from_a_m"] = None if zone is None else zone[0] - s_a
        out["single_contact_end_from_a_m"] = None if zone is None else zone[1] - s_a
        return out


def relief_case(name: str, pair: GearPair, pair_stiffness: Callable[[FloatArray], FloatArray],
                torque: float, modification: ProfileModification | None) -> ReliefCase:
    """Loaded contact, load sharing and Hertz stress of one case (see :class:`ReliefCase`).

    Raises
    ------
    InputError
        As :func:`~gear_dyn.modification.contact.loaded_contact`.
    """
    lc = loaded_contact(pair, pair_stiffness, torque, modification)
    view = lc.along_path()
    sigma, half = contact_stress(pair, view.position, view.force, modification)
    return ReliefCase(name, modification, lc, view, sigma, half)


def rule_cases(pair: GearPair, pair_stiffness: Callable[[FloatArray], FloatArray], torque: float,
               curve: str = "linear", extra: Mapping[str, ProfileModification] | None = None,
               rule_options: Mapping[str, float] | None = None) -> dict[str, ReliefCase]:
    """The unmodified pair, any ``extra`` modifications and every rule of
    :data:`~gear_dyn.modification.relief.RULES`, in that order.

    Parameters
    ----------
    curve : str
        Relief curve used with the rules' amounts and lengths.
    rule_options : mapping or None
        ``handbook_a``, ``handbook_b``, ``face_load_factor`` (see
        :func:`~gear_dyn.modification.relief.recommended_relief`).
    """
    cases = {"unmodified": relief_case("unmodified", pair, pair_stiffness, torque, None)}
    for name, mod in (extra or {}).items():
        cases[name] = relief_case(name, pair, pair_stiffness, torque, mod)
    for rule in RULES:
        mod = recommended_relief(pair, torque, rule, **(rule_options or {})).modification(curve)
        cases[rule] = relief_case(rule, pair, pair_stiffness, torque, mod)
    return cases
