"""Sliding friction on the contact lines of an eccentric helical pair (Liu et al. 2017,
eqs. 18-27).

The normal load ``F`` is spread uniformly over the contact-line length ``L(t)``, ``mu`` is
constant, and each line is split at the pitch line (lengths ``L_i1`` beyond P, ``L_i2`` before
it), its friction acting at each segment's midpoint. Signs as in the paper (force positive
beyond the pitch line; torques positive in each gear's own sense of rotation):

    F_f  = mu F / L sum_i (L_i1 - L_i2)                          (eqs. 21, 23)
    T_f1 = mu F / L sum_i (L_i2 S_i2 - L_i1 S_i1)                (eqs. 25, 27)
    T_f2 = mu F / L sum_i (L_i1 Q_i1 - L_i2 Q_i2)

with ``S_ij``, ``Q_ij`` the arms from O1, O2 to the segments' midpoints. The power
``T_f1 w1 + T_f2 w2 <= 0`` is always dissipated. The readings of the paper's garbled eqs. 22,
24 and 26 are listed in docs/eccentricity.md.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.eccentricity.contact_lines import LineLayout, LinePlace, line_positions
from gear_dyn.eccentricity.kinematics import Kinematics
from gear_dyn.errors import check_range

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Segments:
    """Contact-line segments on both sides of the pitch line (per pair, per instant).

    Attributes
    ----------
    beyond, before : ndarray
        L_i1 (beyond P, towards D) and L_i2 (before P) in m, shape (n_pairs, ...).
    mid_beyond, mid_before : ndarray
        Transverse positions of the segment midpoints, from the tangent point A, in m.
    total : ndarray or float
        L(t) in m.
    """

    beyond: FloatArray
    before: FloatArray
    mid_beyond: FloatArray
    mid_before: FloatArray
    total: Any


@dataclass(frozen=True)
class FrictionFactors:
    """Friction per unit normal load: multiply by F (N) to get forces and torques.

    Attributes
    ----------
    force : friction force F_f / F (dimensionless)
    torque_pinion : T_f1 / F in m (torque on the pinion, positive in its sense of rotation)
    torque_gear : T_f2 / F in m (torque on the gear, positive in its sense of rotation)
    """

    force: Any
    torque_pinion: Any
    torque_gear: Any


def split_segments(layout: LineLayout, kin: Kinematics) -> Segments:
    """Split every contact line at the instantaneous pitch line (Liu et al. 2017,
    eq. 22, general form)."""
    pos = line_positions(layout, kin)
    l_cd = np.asarray(kin.l_cd, dtype=float)
    l_cp = np.asarray(kin.l_cp, dtype=float)
    l_ac = np.asarray(kin.l_ac, dtype=float)
    if layout.width == 0.0:
        b = layout.face_width
        before = np.where((pos >= 0.0) & (pos < l_cp), b, 0.0)
        beyond = np.where((pos >= l_cp) & (pos < l_cd), b, 0.0)
        mid_before = mid_beyond = pos + l_ac
    else:
        back = pos - layout.width
        lo2, hi2 = np.maximum(back, 0.0), np.minimum(pos, l_cp)
        lo1, hi1 = np.maximum(back, l_cp), np.minimum(pos, l_cd)
        # the overlaps of the line with [0, l_cp] and [l_cp, l_cd] (contact_lines.overlap)
        before = np.maximum(hi2 - lo2, 0.0) / layout.sin_bb
        beyond = np.maximum(hi1 - lo1, 0.0) / layout.sin_bb
        mid_before = 0.5 * (lo2 + hi2) + l_ac
        mid_beyond = 0.5 * (lo1 + hi1) + l_ac
    total = (before + beyond).sum(axis=0)
    return Segments(beyond=beyond, before=before, mid_beyond=mid_beyond, mid_before=mid_before,
                    total=total)


def friction_factors(layout: LineLayout, kin: Kinematics, mu: float,
                     segments: Segments | None = None) -> FrictionFactors:
    """Friction force and torques per newton of normal load (Liu et al. 2017, eqs. 18-27).

    Parameters
    ----------
    layout : LineLayout
    kin : Kinematics
        One instant or many.
    mu : float
        Mean friction coefficient (0..1).
    segments : Segments or None
        Precomputed :func:`split_segments` for the same ``kin``.

    Returns
    -------
    FrictionFactors

    Raises
    ------
    InputError
        ``mu`` outside 0..1.
    """
    check_range("friction.coefficient", mu, "", low=0.0, high=1.0)
    seg = segments if segments is not None else split_segments(layout, kin)
    q = mu / seg.total
    foot1 = np.asarray(kin.foot1, dtype=float)
    foot2 = np.asarray(kin.foot2, dtype=float)
    # sum_i (L_i1 - L_i2) and sum_i (L_i2 s_i2 - L_i1 s_i1), s the midpoints: the arms' feet
    # come out of the sums
    net = (seg.beyond - seg.before).sum(axis=0)
    moment = (seg.before * seg.mid_before - seg.beyond * seg.mid_beyond).sum(axis=0)
    force = q * net
    t1 = q * (moment + foot1 * net)
    t2 = q * (moment + foot2 * net)
    return FrictionFactors(force=force, torque_pinion=t1, torque_gear=t2)


def line_state_scalar(layout: LineLayout, kin: LinePlace | Kinematics,
                      mu: float) -> tuple[float, float, float, float]:
    """``(L, F_f / F, T_f1 / F, T_f2 / F)`` at one instant, in plain Python for speed.

    Same numbers as :func:`split_segments` and :func:`friction_factors` (without the range check
    of ``mu``); used inside model right-hand sides where numpy's per-call cost dominates.
    """
    pitch, w = layout.pitch, layout.width
    l_ac = float(kin.l_ac)
    l_cd = float(kin.l_cd)
    l_cp = float(kin.l_cp)
    f1 = float(kin.foot1)
    f2 = float(kin.foot2)
    d = float(kin.travel) % pitch - pitch + layout.l_ac0 - l_ac + int(layout.index[0]) * pitch
    total = force = t1 = t2 = 0.0
    for _ in range(layout.index.size):
        if w == 0.0:
            if 0.0 <= d < l_cd:
                b = layout.face_width
                s_mid = d + l_ac
                total += b
                if d < l_cp:
                    force -= b
                    t1 += b * (s_mid - f1)
                    t2 -= b * (f2 - s_mid)
                else:
                    force += b
                    t1 -= b * (s_mid - f1)
                    t2 += b * (f2 - s_mid)
        else:
            back = d - w
            lo2, hi2 = max(back, 0.0), min(d, l_cp)
            lo1, hi1 = max(back, l_cp), min(d, l_cd)
            if hi2 > lo2:
                seg = (hi2 - lo2) / layout.sin_bb
                s_mid = 0.5 * (lo2 + hi2) + l_ac
                total += seg
                force -= seg
                t1 += seg * (s_mid - f1)
                t2 -= seg * (f2 - s_mid)
            if hi1 > lo1:
                seg = (hi1 - lo1) / layout.sin_bb
                s_mid = 0.5 * (lo1 + hi1) + l_ac
                total += seg
                force += seg
                t1 -= seg * (s_mid - f1)
                t2 += seg * (f2 - s_mid)
        d += pitch
    q = mu / total
    return total, q * force, q * t1, q * t2
