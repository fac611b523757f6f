"""Total contact-line length of an error-free involute pair.

In the plane of action the field of contact is a rectangle ``g_a`` wide and ``B`` high; the lines
are inclined at the base helix angle ``b_b`` and follow each other at ``p_bt``. At mesh phase
``p`` they sit at ``u_j = (p + j) p_bt`` from A on the front face (the phase convention of
:mod:`gear_dyn.stiffness.periodic`). ``L(p)`` is piecewise linear with kinks (jumps for spur) at
``frac(0), frac(eps_a), frac(eps_b), frac(eps_a + eps_b)``, and ``mean L = B eps_a / cos b_b``.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from gear_dyn.geometry import GearPair
from gear_dyn.stiffness.periodic import FloatArray, distinct_phases


def _line_lengths(u: FloatArray, g_a: float, width: float, tan_bb: float,
                  cos_bb: float) -> FloatArray:
    """Length (m) inside the field of a contact line whose front-face end is at ``u`` (m)."""
    if tan_bb == 0.0:
        return np.where((u >= 0.0) & (u <= g_a), width, 0.0)
    z_lo = np.maximum(0.0, (u - g_a) / tan_bb)
    z_hi = np.minimum(width, u / tan_bb)
    return np.maximum(z_hi - z_lo, 0.0) / cos_bb


def contact_line_length(pair: GearPair, phase: ArrayLike) -> FloatArray:
    """Total contact-line length L(p) of the error-free pair at mesh phase ``phase``.

    Parameters
    ----------
    pair : GearPair
        Spur or helical pair (its operating centre distance sets ``g_a``).
    phase : array_like
        Mesh phase in cycles (any real value; period 1). Phase 0: a line enters at A on the front
        face.

    Returns
    -------
    ndarray
        Total length in m of all contact lines inside the field of contact, same shape as
        ``phase``. For spur pairs the value at a switching phase counts the entering line (the
        interval is closed at both ends of the path).

    Examples
    --------
    >>> import math
    >>> from gear_dyn.geometry import GearPair
    >>> pair = GearPair(19, 48, 3.2e-3, math.radians(20), 16e-3)
    >>> float(contact_line_length(pair, 0.9)) * 1e3  # one pair in contact: the face width
    16.0
    """
    p = np.mod(np.asarray(phase, dtype=float), 1.0)
    g_a = pair.path_of_contact
    pb = pair.base_pitch
    bb = pair.beta_b
    tan_bb, cos_bb = math.tan(bb), math.cos(bb)
    reach = g_a + pair.face_width * tan_bb  # a line is in the field for u in [0, reach]
    n_lines = int(math.floor(reach / pb)) + 2
    j = np.arange(n_lines, dtype=float)
    u = (p[..., None] + j) * pb
    return np.sum(_line_lengths(u, g_a, pair.face_width, tan_bb, cos_bb), axis=-1)


def contact_line_breakpoints(pair: GearPair) -> FloatArray:
    """Sorted distinct phases in [0, 1) where L(p) has a kink or a jump.

    These are ``frac(0), frac(eps_a), frac(eps_b), frac(eps_a + eps_b)`` (spur: the first two).
    """
    ea, eb = pair.contact_ratio, pair.overlap_ratio
    return distinct_phases([0.0, ea, eb, ea + eb] if eb > 0 else [0.0, ea], 1e-12)


def mean_contact_line_length(pair: GearPair) -> float:
    """Closed-form mean ``B eps_a / cos b_b`` of :func:`contact_line_length`, in m."""
    return pair.face_width * pair.contact_ratio / math.cos(pair.beta_b)
