"""Parts of the torsional model: the contact-line stiffness law, the excitation closure and the
level crossings of the switching instants."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.eccentricity.contact_lines import total_length_scalar
from gear_dyn.eccentricity.friction import line_state_scalar
from gear_dyn.errors import check_range
from gear_dyn.models.sdof import scalar_stiffness
from gear_dyn.stiffness.periodic import PeriodicStiffness

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class ContactLineStiffness:
    """Mesh stiffness proportional to the total contact-line length, ``k = k_l L(t)``.

    Parameters
    ----------
    per_length : float
        k_l in N/m per m of contact line (N/m^2), > 0. ISO 6336 gives
        ``k_l = c_gamma cos b_b / eps_a`` (so that the mean is ``c_gamma B``).
    """

    per_length: float

    def __post_init__(self) -> None:
        check_range("stiffness.per_length", self.per_length, "N/m^2", low=0.0, high=1e16,
                    low_open=True)


def _levels(h: Callable[[FloatArray], FloatArray], rate: float, t0: float, t1: float,
            residues: FloatArray, period: float) -> FloatArray:
    """Times in (t0, t1) where the increasing function h(t) equals ``r + n period`` for any
    residue r and integer n; ``rate`` approximates dh/dt (Newton with a fixed slope: h differs
    from ``rate t`` by an O(e) periodic term, so each step gains a factor ~e / r_b)."""
    h0, h1 = h(np.array([t0, t1]))
    levels = []
    for r in np.unique(np.asarray(residues, dtype=float)):
        n0 = math.floor((h0 - r) / period) + 1
        n1 = math.ceil((h1 - r) / period) - 1
        if n1 >= n0:
            levels.append(r + period * np.arange(n0, n1 + 1))
    if not levels:
        return np.empty(0)
    lv = np.concatenate(levels)
    t = t0 + (lv - h0) / rate
    for _ in range(50):
        step = (h(t) - lv) / rate
        t = t - step
        if np.max(np.abs(step)) <= 1e-15 * max(abs(t1), 1e-3):
            break
    return np.asarray(t[(t > t0) & (t < t1)], dtype=float)


#: t -> (e_ecc, e_ecc', k, phi1, phi2): the state-free coefficients of the torsional model
Excite = Callable[[float], tuple[float, float, float, float, float]]


def excite_closure(stiff: Any, lay: Any, mu: float | None, ecc: bool,
                   place: Callable[[float], Any], fm: float, pitch: float,
                   l_ac0: float) -> Excite:
    """Closure t -> (e_ecc, e_ecc', k, phi1, phi2) of the torsional model, with only the
    enabled parts: ``stiff`` a PeriodicStiffness or ContactLineStiffness, ``lay`` the contact
    line layout (None without contact lines), ``mu`` the friction coefficient (None: none),
    ``ecc`` whether the pair is eccentric, ``place(t)`` the field of contact at t, ``fm`` the
    mesh frequency (Hz), ``pitch`` the base pitch (m), ``l_ac0`` the nominal L_AC (m)."""

    if isinstance(stiff, PeriodicStiffness) and mu is None and not ecc:
        pst = scalar_stiffness(stiff)

        def excite_plain(t: float) -> tuple[float, float, float, float, float]:
            return 0.0, 0.0, pst(fm * t), 0.0, 0.0
        return excite_plain

    fast_k = scalar_stiffness(stiff) if isinstance(stiff, PeriodicStiffness) else None

    def periodic_k(t: float, kin: Any) -> float:
        assert fast_k is not None
        if ecc:
            return fast_k((kin.travel + l_ac0 - kin.l_ac) / pitch)
        return fast_k(fm * t)

    k_l = stiff.per_length if isinstance(stiff, ContactLineStiffness) else None
    if mu is None:
        def excite_frictionless(t: float) -> tuple[float, float, float, float, float]:
            kin = place(t)
            e, ed = (kin.e_ecc, kin.e_ecc_rate) if ecc else (0.0, 0.0)
            if k_l is not None:
                assert lay is not None
                return e, ed, k_l * total_length_scalar(lay, kin), 0.0, 0.0
            return e, ed, periodic_k(t, kin), 0.0, 0.0
        return excite_frictionless

    assert lay is not None
    mu_f = float(mu)

    def excite(t: float) -> tuple[float, float, float, float, float]:
        kin = place(t)
        e, ed = (kin.e_ecc, kin.e_ecc_rate) if ecc else (0.0, 0.0)
        total, _, p1, p2 = line_state_scalar(lay, kin, mu_f)
        k = k_l * total if k_l is not None else periodic_k(t, kin)
        return e, ed, k, p1, p2
    return excite

