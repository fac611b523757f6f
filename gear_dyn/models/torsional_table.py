"""Tabulated time functions of the torsional model: piecewise polynomials between switching
instants, built block by block from the vectorised excitations.

The state-independent coefficients (``e_ecc`` and its rate, ``k``, the friction arms ``phi1``,
``phi2``) are smooth between ``TorsionalModel.switching_times``. They are evaluated once,
vectorised, at the Chebyshev points of every piece, and the right-hand side evaluates a
polynomial of degree :data:`DEGREE` instead of the eccentric kinematics. The interpolation error
is measured at build time at the next degree's Chebyshev points (``ExcitationTable.max_error``,
relative to each quantity's scale). Blocks of :data:`BLOCK_MESH_PERIODS` mesh periods are built
when first needed; at most :data:`MAX_BLOCKS` are kept.
"""

from __future__ import annotations

import bisect
import functools
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
Values = tuple[float, float, float, float, float]

#: degree of the polynomial on each smooth piece (pieces are <= ~1/2 mesh period long)
DEGREE = 10
#: mesh periods per block of the table
BLOCK_MESH_PERIODS = 32
#: blocks kept (oldest dropped first, rebuilt if asked again): bounds the memory of long runs
MAX_BLOCKS = 64


@functools.lru_cache(maxsize=8)
def node_matrix(degree: int) -> tuple[FloatArray, FloatArray]:
    """Chebyshev points (first kind) on [-1, 1] and the matrix taking values there to monomial
    coefficients in s, highest power first (Horner order)."""
    n = degree + 1
    s = np.cos(np.pi * (np.arange(n) + 0.5) / n)
    return s, np.linalg.inv(np.vander(s, n))  # values = vander @ coefficients


@dataclass(eq=False)
class ExcitationTable:
    """Piecewise polynomials of ``(e_ecc, e_ecc', k, phi1, phi2)`` in time.

    Parameters
    ----------
    values : callable
        ``values(t)`` for an array of times (s): array (5, n) of the five quantities (m, m/s, N/m,
        m, m), evaluated exactly (vectorised).
    cuts : callable
        ``cuts(t0, t1)``: the switching instants in (t0, t1) (s), where the quantities have kinks.
    block : float
        Length of one block of the table in s.
    scale : ndarray (5,)
        Typical magnitude of each quantity (for the stated relative interpolation error).
    """

    values: Callable[[FloatArray], FloatArray]
    cuts: Callable[[float, float], FloatArray]
    block: float
    scale: FloatArray
    max_error: FloatArray = field(init=False, default_factory=lambda: np.zeros(5))
    _blocks: dict[int, tuple[list[float], list[float], list[float], list[list[Values]]]] = \
        field(init=False, repr=False, default_factory=dict)
    _arrays: dict[int, tuple[FloatArray, FloatArray, FloatArray, FloatArray]] = \
        field(init=False, repr=False, default_factory=dict)

    def _build(self, b: int) -> None:
        """Fit block ``b`` (times ``b block .. (b + 1) block``)."""
        t0, t1 = b * self.block, (b + 1) * self.block
        edges = np.concatenate([[t0], self.cuts(t0, t1), [t1]])
        mid = 0.5 * (edges[1:] + edges[:-1])
        half = 0.5 * (edges[1:] - edges[:-1])
        s, to_mono = node_matrix(DEGREE)
        vals = self.values((mid[:, None] + half[:, None] * s[None, :]).ravel())
        vals = vals.reshape(5, mid.size, s.size)
        coefs = np.einsum("ij,qpj->piq", to_mono, vals)  # (pieces, DEGREE + 1, 5)
        s_chk, _ = node_matrix(DEGREE + 1)
        exact = self.values((mid[:, None] + half[:, None] * s_chk[None, :]).ravel())
        approx = np.einsum("ij,pjq->qpi", np.vander(s_chk, DEGREE + 1), coefs)
        err = np.max(np.abs(approx - exact.reshape(approx.shape)), axis=(1, 2)) / self.scale
        self.max_error = np.maximum(self.max_error, err)
        if len(self._arrays) >= MAX_BLOCKS:
            old = next(iter(self._arrays))
            del self._arrays[old]
            self._blocks.pop(old, None)
        self._arrays[b] = (edges[:-1], mid, 1.0 / half, coefs)

    def _scalar_block(self, b: int) -> tuple[list[float], list[float], list[float],
                                            list[list[Values]]]:
        """Block ``b`` as Python lists (the scalar right-hand side is faster on floats)."""
        if b not in self._arrays:
            self._build(b)
        starts, mid, inv_half, coefs = self._arrays[b]
        table = (starts.tolist(), mid.tolist(), inv_half.tolist(),
                 [[tuple(row) for row in piece] for piece in coefs.tolist()])
        self._blocks[b] = table
        return table

    def __call__(self, t: float) -> Values:
        """The five quantities at time ``t`` (s) from the table."""
        b = int(t // self.block)
        tab = self._blocks.get(b)
        if tab is None:
            tab = self._scalar_block(b)
        starts, mids, inv_half, coefs = tab
        i = max(bisect.bisect_right(starts, t) - 1, 0)
        s = (t - mids[i]) * inv_half[i]
        rows = coefs[i]
        e, ed, k, p1, p2 = rows[0]
        for r in rows[1:]:
            e = e * s + r[0]
            ed = ed * s + r[1]
            k = k * s + r[2]
            p1 = p1 * s + r[3]
            p2 = p2 * s + r[4]
        return e, ed, k, p1, p2

    def evaluate(self, t: FloatArray) -> FloatArray:
        """The five quantities at many times ``t`` (s), vectorised: array (5, n)."""
        t = np.asarray(t, dtype=float)
        out = np.empty((5, t.size))
        blocks = np.floor_divide(t, self.block).astype(np.int64)
        if t.size == 0:
            return out
        lo, hi = int(blocks.min()), int(blocks.max())
        for b in ([lo] if lo == hi else np.unique(blocks).tolist()):  # one block: no sort
            if b not in self._arrays:
                self._build(b)
            starts, mids, inv_half, coefs = self._arrays[b]
            sel = slice(None) if lo == hi else np.nonzero(blocks == b)[0]
            tb = t[sel]
            i = np.maximum(np.searchsorted(starts, tb, side="right") - 1, 0)
            s = (tb - mids[i]) * inv_half[i]
            # Horner with the points last (long inner loops): the block's coefficients as
            # (DEGREE + 1, 5, pieces), gathered once at the points' pieces
            rows = np.take(np.ascontiguousarray(coefs.transpose(1, 2, 0)), i, axis=2)
            acc = rows[0]
            for k in range(1, DEGREE + 1):
                acc *= s
                acc += rows[k]
            out[:, sel] = acc
        return out


def table_of(model: Any) -> ExcitationTable | None:
    """The table of a :class:`~gear_dyn.models.torsional.TorsionalModel`, or None where the
    direct evaluation is already cheap (no eccentricity, friction or contact lines)."""
    if model._layout is None and not model.eccentric:
        return None
    names = ("e_ecc", "e_ecc_rate", "stiffness", "phi1", "phi2")

    def values(t: FloatArray) -> FloatArray:
        ex = model.excitations(t)
        return np.array([ex[n] for n in names])
    x_s = max(model.static_load / model.mean_stiffness, 1e-12)
    scale = np.array([x_s, x_s * 2 * math.pi * model.natural_frequency, model.mean_stiffness,
                      model.pair.rb1, model.pair.rb2])
    return ExcitationTable(values, model.switching_times,
                           BLOCK_MESH_PERIODS / model.mesh_frequency, scale)


def force_form(coef: FloatArray, rb: tuple[float, float], inertias: tuple[float, float],
               torques: tuple[float, float], damping: float
               ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """The torsional right-hand side in the form ``q' = v``, ``v' = u F + g_v`` with the mesh
    force ``F = f^T y + f0``, valid while ``F > 0`` (the friction torques ``F phi`` act only
    then); affine in ``y = [q1, q2, v1, v2]``.

    Parameters
    ----------
    coef : ndarray (5, n)
        ``e_ecc`` (m), ``e_ecc'`` (m/s), ``k`` (N/m), ``phi1``, ``phi2`` (m) at n instants.
    rb, inertias, torques : (float, float)
        Base radii (m), I1, I2 (kg m^2), T1, T2 (N m).
    damping : float
        c_m in N s/m.

    Returns
    -------
    u : ndarray (n, 2)
        ``((phi1 - r_b1) / I1, (r_b2 + phi2) / I2)``: angular accelerations per newton of F.
    f : ndarray (n, 4)
        ``(k r_b1, -k r_b2, c r_b1, -c r_b2)``: F per unit of each state.
    f0 : ndarray (n,)
        ``k e_ecc + c e_ecc'`` in N.
    g_v : ndarray (2,)
        ``(T1 / I1, -T2 / I2)`` in rad/s^2.
    """
    e, ed, k, p1, p2 = coef
    rb1, rb2 = rb
    i1, i2 = inertias
    n = e.size
    f = np.stack([k * rb1, -k * rb2, np.full(n, damping * rb1), np.full(n, -damping * rb2)],
                 axis=1)
    u = np.stack([(p1 - rb1) / i1, (rb2 + p2) / i2], axis=1)
    return u, f, k * e + damping * ed, np.array([torques[0] / i1, -torques[1] / i2])
