"""Mesh stiffness over a mesh cycle from a single-pair stiffness function (pairs add in parallel).

At mesh phase ``p`` in [0, 1) the pairs in contact sit at
``s_j = start_of_contact + (p + j) p_bt`` while ``s_j <= end_of_contact`` (phase 0: a new pair
enters at A); the switching phases are 0 and ``eps_a - floor(eps_a)``. The result is a
:class:`~gear_dyn.stiffness.PiecewiseStiffness`, linear between samples, with the jumps kept exact.

Helical pairs: thin slices of the face, each lagging by ``eps_b z / B`` cycles, add; by default
continuously, ``k(p) = (C(p) - C(p - eps_b)) / eps_b`` with ``C`` the antiderivative of the
transverse curve (no slice ripple), or with ``slices = n`` discrete slices (docs/stiffness.md).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike

from gear_dyn.errors import InputError
from gear_dyn.geometry import GearPair
from gear_dyn.stiffness.contact_line import contact_line_breakpoints
from gear_dyn.stiffness.periodic import FloatArray, PiecewiseStiffness, contact_segments

PairFunction = Callable[[GearPair, ArrayLike], FloatArray]


def spur_mesh_values(pair: GearPair, pair_fn: PairFunction, phase: FloatArray,
                     pairs: int) -> FloatArray:
    """Sum of ``pair_fn`` over ``pairs`` pairs in contact at ``phase`` (N/m)."""
    a, e, pb = pair.start_of_contact, pair.end_of_contact, pair.base_pitch
    j = np.arange(pairs)
    s = a + (phase[:, None] + j[None, :]) * pb
    s = np.clip(s, a, e)
    k = np.asarray(pair_fn(pair, s.ravel()), dtype=float).reshape(s.shape)
    return np.sum(k, axis=1)


def mesh_stiffness_from_pair(pair: GearPair, pair_fn: PairFunction, samples_per_cycle: int = 200,
                             name: str = "mesh",
                             slices: int | None = None) -> PiecewiseStiffness:
    """Mesh stiffness k(p) built from the single-pair stiffness ``pair_fn(pair, s)``.

    Parameters
    ----------
    pair : GearPair
        The pair; its operating centre distance fixes the path of contact and contact ratio.
    pair_fn : callable
        ``pair_fn(pair, s) -> K`` in N/m for contact positions ``s`` (m from T1), vectorised.
    samples_per_cycle : int
        Samples over one mesh cycle (>= 4), shared between segments in proportion to length.
    name : str
        Method name for reports.
    slices : int or None
        Helical pairs: None (default) slices the face continuously; n >= 1 uses n discrete
        slices. Ignored for spur pairs.

    Returns
    -------
    PiecewiseStiffness
        Switching phases at pair entry (0) and exit (frac(eps_a)) for spur pairs.

    Raises
    ------
    InputError
        Too few samples or slices.

    Examples
    --------
    >>> import math
    >>> from gear_dyn.geometry import GearPair
    >>> pair = GearPair(19, 48, 3.2e-3, math.radians(20), 16e-3)
    >>> k = mesh_stiffness_from_pair(pair, lambda p, s: 1e8 + 0 * s)
    >>> round(k.mean / 1e8, 6) == round(pair.contact_ratio, 6)
    True
    """
    if not isinstance(samples_per_cycle, int) or samples_per_cycle < 4:
        raise InputError(f"samples_per_cycle = {samples_per_cycle!r}: valid range >= 4")
    if pair.helix_angle != 0.0:
        return _helical(pair, pair_fn, samples_per_cycle, name, slices)
    return _transverse(pair, pair_fn, samples_per_cycle, name)


def _transverse(pair: GearPair, pair_fn: PairFunction, samples_per_cycle: int,
                name: str) -> PiecewiseStiffness:
    """The transverse (unsliced) curve: pairs add, switching at entry and exit."""
    edges = [0.0]
    samples = []
    for lo, hi, pairs in contact_segments(pair.contact_ratio):
        m = max(2, int(math.ceil(samples_per_cycle * (hi - lo))) + 1)
        ph = np.linspace(lo, hi, m)
        samples.append((ph, spur_mesh_values(pair, pair_fn, ph, pairs)))
        edges.append(hi)
    return PiecewiseStiffness(np.asarray(edges), tuple(samples), name=name)


def _helical(pair: GearPair, pair_fn: PairFunction, samples_per_cycle: int, name: str,
             slices: int | None) -> PiecewiseStiffness:
    if slices is not None and (not isinstance(slices, int) or slices < 1):
        raise InputError(f"slices = {slices!r}: valid range >= 1, or None (continuous)")
    eps_b = pair.overlap_ratio
    # the transverse curve once, finely sampled; the slices are shifted copies of it
    fine = _transverse(pair, pair_fn, max(1000, 5 * samples_per_cycle), name)
    values: Callable[[FloatArray], FloatArray]
    if slices is None:
        values = _continuous_average(fine, eps_b)
    else:
        lags = eps_b * (np.arange(slices) + 0.5) / slices

        def values(ph: FloatArray) -> FloatArray:
            q = (ph[:, None] - lags[None, :]).ravel()
            return np.asarray(fine(q)).reshape(ph.size, slices).mean(axis=1)

    bp = contact_line_breakpoints(pair)
    edges = np.append(bp, 1.0)
    phases = (np.linspace(lo, hi, max(2, int(math.ceil(samples_per_cycle * (hi - lo))) + 1))
              for lo, hi in zip(edges[:-1], edges[1:], strict=True))
    return PiecewiseStiffness(edges, tuple((ph, values(ph)) for ph in phases), name=name)


def _continuous_average(curve: PiecewiseStiffness,
                        width: float) -> Callable[[FloatArray], FloatArray]:
    """``p -> (1/width) int_0^width curve(p - l) dl`` via the exact antiderivative of the pieces."""
    knots, cums = [], []
    total = 0.0
    for ph, val in curve.samples:
        ph = np.asarray(ph, dtype=float)
        val = np.asarray(val, dtype=float)
        piece = np.concatenate([[0.0], np.cumsum(0.5 * (val[1:] + val[:-1]) * np.diff(ph))])
        knots.append(ph)
        cums.append(total + piece)
        total += float(piece[-1])
    x = np.concatenate(knots)
    c = np.concatenate(cums)
    mean = total  # integral over one cycle = mean (period 1)

    def antiderivative(q: FloatArray) -> FloatArray:
        n = np.floor(q)
        r = q - n
        # C on one cycle is piecewise quadratic; between knots integrate the linear piece exactly
        j = np.clip(np.searchsorted(x, r, side="right") - 1, 0, x.size - 2)
        x0 = x[j]
        mid = curve(x0 + 0.5 * (r - x0))  # value at the piece's midpoint: exact for linear
        return n * mean + c[j] + mid * (r - x0)

    def values(ph: FloatArray) -> FloatArray:
        return (antiderivative(ph) - antiderivative(ph - width)) / width

    return values
