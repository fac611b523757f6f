"""Time-varying contact lines of a helical pair with eccentricity (Liu et al. 2017, eqs. 14-17).

Transverse coordinate ``s`` along the line of action from the moving tangent point A; the field
of contact is ``L_AC <= s <= L_AD`` with ``L_AD = sqrt(r_a1^2 - r_b1^2)``,
``L_AC = |AB| - sqrt(r_a2^2 - r_b2^2)`` (it moves with the centre distance l(t)) and
``L_CD = L_AD - L_AC`` (the paper's printed forms are garbled: docs/eccentricity.md). Line i,
inclined at ``b_b`` and ``w = B tan b_b`` wide transversally, has its leading end at

    D_i(t) = r(t) + (i - 1) p_bt + L_AC0 - L_AC(t),   r = tau - m p_bt,  m = floor(tau / p_bt)

(``tau`` from :mod:`.kinematics`; i starts at 0, a pair can enter early) and the length

    L_i = max(0, min(D_i, L_CD) - max(D_i - w, 0)) / sin b_b                  (eqs. 15-16)

(``B`` for spur pairs); ``L(t) = sum_i L_i`` (eq. 17), whose mean without eccentricity is
``B eps_a / cos b_b`` (Maatar & Velex 1996).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.eccentricity.kinematics import EccentricMesh, Kinematics
from gear_dyn.stiffness.contact_line import mean_contact_line_length

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class LinePlace:
    """Where the field of contact is at one instant, as the scalar functions read it (a
    :class:`~gear_dyn.eccentricity.kinematics.Kinematics` from a float time has the same
    attributes): ``travel``, ``l_ac``,
    ``l_cd``, ``l_cp``, ``foot1``, ``foot2`` in m."""

    travel: float
    l_ac: float
    l_cd: float
    l_cp: float
    foot1: float
    foot2: float


@dataclass(frozen=True)
class LineLayout:
    """Constants of the contact-line bookkeeping of one eccentric pair.

    Attributes
    ----------
    pitch : float
        Transverse base pitch p_bt in m.
    width : float
        Transverse extent of one contact line, B tan b_b, in m (0 for spur).
    sin_bb : float
        sin of the base helix angle (0 for spur).
    face_width : float
        B in m.
    l_ac0 : float
        L_AC at t = 0 in m.
    index : ndarray of int
        Pair indices i evaluated (from 0; enough to hold every line that can be in contact).
    """

    pitch: float
    width: float
    sin_bb: float
    face_width: float
    l_ac0: float
    index: NDArray[np.int64]

    @classmethod
    def of(cls, mesh: EccentricMesh) -> LineLayout:
        """The layout of ``mesh``: its pitch, line width and the index range i = 0..n."""
        p = mesh.pair
        pitch = p.base_pitch
        width = p.face_width * math.tan(p.beta_b)
        lo, hi = mesh.l_ac_range
        shift = hi - lo  # |L_AC0 - L_AC| never exceeds this
        l_cd_max = p.tip_reach1 - lo
        i_max = int(math.ceil((l_cd_max + width + shift) / pitch)) + 1
        return cls(pitch=pitch, width=width, sin_bb=math.sin(p.beta_b), face_width=p.face_width,
                   l_ac0=mesh.l_ac0, index=np.arange(0, i_max + 1))


@dataclass(frozen=True)
class ContactLines:
    """Contact lines at one or many instants.

    Attributes
    ----------
    position : ndarray
        D_i, transverse distance of each line's leading end from C in m, shape (n_pairs, ...).
    lengths : ndarray
        L_i in m, same shape.
    total : ndarray or float
        L(t) = sum_i L_i in m, shape of the times.
    """

    position: FloatArray
    lengths: FloatArray
    total: Any


def line_positions(layout: LineLayout, kin: Kinematics) -> FloatArray:
    """D_i (m) for every pair index of ``layout``, shape (n_pairs,) + shape of the times."""
    tau = np.asarray(kin.travel, dtype=float)
    r = np.mod(tau, layout.pitch)
    shift = layout.l_ac0 - np.asarray(kin.l_ac, dtype=float)
    idx = layout.index.reshape((-1,) + (1,) * tau.ndim)
    return r + (idx - 1) * layout.pitch + shift


def overlap(front: FloatArray, width: float, lo: Any, hi: Any) -> FloatArray:
    """Transverse length (m) of the segment [front - width, front] inside [lo, hi] (>= 0)."""
    return np.maximum(np.minimum(front, hi) - np.maximum(front - width, lo), 0.0)


def line_lengths(layout: LineLayout, position: FloatArray, l_cd: Any) -> FloatArray:
    """L_i (m) of lines whose leading ends are at ``position`` (m from C); path length ``l_cd``."""
    if layout.width == 0.0:
        return np.where((position >= 0.0) & (position < l_cd), layout.face_width, 0.0)
    return overlap(position, layout.width, 0.0, l_cd) / layout.sin_bb


def contact_lines(layout: LineLayout, kin: Kinematics) -> ContactLines:
    """Positions, lengths and total length of the contact lines (Liu et al. 2017, eqs. 14-17).

    Parameters
    ----------
    layout : LineLayout
        From :meth:`LineLayout.of` for the same mesh.
    kin : Kinematics
        From :meth:`~gear_dyn.eccentricity.kinematics.EccentricMesh.kinematics` (one instant or
        an array of instants).

    Returns
    -------
    ContactLines

    Examples
    --------
    >>> import math
    >>> from gear_dyn.geometry import GearPair
    >>> from gear_dyn.eccentricity import Eccentricity, EccentricMesh
    >>> pair = GearPair(18, 70, 3e-3, math.radians(20), 0.04, math.radians(15))
    >>> mesh = EccentricMesh(pair, Eccentricity(), 50 * math.pi)
    >>> lines = contact_lines(LineLayout.of(mesh), mesh.kinematics([0.0, 1e-4]))
    >>> lines.total.shape
    (2,)
    """
    pos = line_positions(layout, kin)
    lengths = line_lengths(layout, pos, kin.l_cd)
    return ContactLines(position=pos, lengths=lengths, total=lengths.sum(axis=0))


def total_length_scalar(layout: LineLayout, kin: LinePlace | Kinematics) -> float:
    """L(t) in m at one instant (``kin`` from a float time), in plain Python for speed.

    Same numbers as ``contact_lines(layout, kin).total``; used inside model right-hand sides.
    """
    pitch, width = layout.pitch, layout.width
    tau = float(kin.travel)
    l_cd = float(kin.l_cd)
    d = tau % pitch - pitch + layout.l_ac0 - float(kin.l_ac) + int(layout.index[0]) * pitch
    total = 0.0
    for _ in range(layout.index.size):
        if width == 0.0:
            if 0.0 <= d < l_cd:
                total += layout.face_width
        else:
            ov = min(d, l_cd) - max(d - width, 0.0)
            if ov > 0.0:
                total += ov
        d += pitch
    return total if width == 0.0 else total / layout.sin_bb


def mean_length(mesh: EccentricMesh) -> float:
    """B eps_a / cos b_b in m: the mean of L(t) of the error-free pair
    (:func:`~gear_dyn.stiffness.contact_line.mean_contact_line_length`)."""
    return mean_contact_line_length(mesh.pair)
