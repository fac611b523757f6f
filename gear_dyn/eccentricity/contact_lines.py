"""Time-varying contact lines of a helical pair with eccentricity (Liu et al. 2017, eqs. 14-17).

Plane of action, transverse coordinate ``s`` measured along the line of action from the pinion's
tangent point A (it moves with the eccentric centres), axial coordinate ``z`` across the face width
``B``. The field of contact is ``L_AC <= s <= L_AD``:

- ``L_AD = sqrt(r_a1^2 - r_b1^2)``: end of contact D, where the pinion tip circle cuts the line
  (constant: tip and base circle share the centre O1');
- ``L_AC = |AB| - sqrt(r_a2^2 - r_b2^2)``, ``|AB| = sqrt(l^2 - (r_b1 + r_b2)^2)``: start of contact
  C, where the gear tip circle cuts the line; it moves with the actual centre distance l(t);
- ``L_CD = L_AD - L_AC``: the instantaneous transverse path of contact (the paper's ``L_CD``).

The paper prints ``L_AC = sqrt(l^2 - (r_b1+r_b2)^2) - sqrt((r_a1 + r_a2)^2)``,
``L_AC0 = sqrt(l(0)^2 - (r_b1+r_b2)^2) - sqrt(r_a1^2 + r_a2^2)`` and ``L_CD = L_AC - L_AD``: all
three are garbled. The definitions above follow from the geometry (distance from the tangent point
A to the start of contact C on the moving line of action, Fig. 3 of the paper) and reduce, for
``e1 = e2 = 0``, to ``L_AC = T1A`` and ``L_CD = g_a`` of the error-free pair
(:attr:`GearPair.start_of_contact`, :attr:`GearPair.path_of_contact`).

Each contact line is straight in the plane of action, inclined at the base helix angle, and spans
the transverse width ``w = B tan b_b``. The transverse distance of its leading end (front face)
from C is (the paper's ``D_i``, with the travel ``tau`` from :mod:`.kinematics`)::

    D_i(t) = r(t) + (i - 1) p_bt + L_AC0 - L_AC(t),   r = tau - m p_bt,  m = floor(tau / p_bt)

so at t = 0 pair 1 enters at C. A shorter centre distance moves C towards A (L_AC < L_AC0), so
pair i = 0 can already be in contact: the index starts at 0 (the paper's text after eq. 14). The
line covers ``[D_i - w, D_i]`` transversally; its length in the field is the overlap with
``[0, L_CD]`` divided by ``sin b_b``::

    L_i = max(0, min(D_i, L_CD) - max(D_i - w, 0)) / sin b_b                  (eqs. 15-16)

which is the paper's four-piece function (ramp ``D_i / sin b_b``, plateau
``min(w, L_CD) / sin b_b``, ramp ``(L_CD + w - D_i) / sin b_b``, zero) written as one overlap, and
also gives zero before entry (``D_i < 0``), a case eq. 16 leaves out. Spur pairs (``b_b = 0``):
a line in contact has length ``B``. ``L(t) = sum_i L_i`` (eq. 17).

Mean length (e1 = e2 = 0): every line sweeps the field once per passage; integrating its length
over one passage gives ``L_CD w / sin b_b`` in m^2 of transverse travel, and a new line arrives
each ``p_bt``, so ``mean L = L_CD B tan b_b / (p_bt sin b_b) = B eps_a / cos b_b``
(Maatar & Velex 1996; ISO 6336-2's contact-ratio factor
``Z_eps = sqrt(1/eps_a)`` for ``eps_b >= 1`` rests on the same mean length).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from gear_dyn.eccentricity.kinematics import EccentricMesh, Kinematics

FloatArray = NDArray[np.float64]


class LinePlace(Protocol):
    """Where the field of contact is at one instant (a :class:`Kinematics` from a float time
    satisfies it): ``travel``, ``l_ac``, ``l_cd``, ``l_cp``, ``foot1``, ``foot2`` in m."""

    @property
    def travel(self) -> Any: ...

    @property
    def l_ac(self) -> Any: ...

    @property
    def l_cd(self) -> Any: ...

    @property
    def l_cp(self) -> Any: ...

    @property
    def foot1(self) -> Any: ...

    @property
    def foot2(self) -> Any: ...


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
        From :meth:`EccentricMesh.kinematics` (one instant or an array of instants).

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


def total_length_scalar(layout: LineLayout, kin: LinePlace) -> float:
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
    """B eps_a / cos b_b in m: the mean of L(t) of the error-free pair."""
    p = mesh.pair
    return p.face_width * p.contact_ratio / math.cos(p.beta_b)
