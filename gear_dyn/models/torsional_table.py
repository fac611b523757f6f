"""Tabulated time functions of the torsional model: piecewise polynomials between switching
instants, built block by block from the vectorised excitations.

The coefficients of the torsional model that do not depend on the state (the eccentricity's
displacement ``e_ecc`` and its rate, the mesh stiffness ``k`` and the friction arms ``phi1``,
``phi2``) are smooth between the instants where a contact line enters, leaves or crosses the pitch
line (``TorsionalModel.switching_times``) and have kinks there. Evaluated one instant at a time
they cost a fixed-point solve of the eccentric kinematics and a loop over the contact lines at
every right-hand-side call. Here they are evaluated once, vectorised, at the Chebyshev points of
every smooth piece, and the right-hand side evaluates a polynomial of degree :data:`DEGREE` per
piece instead.

Interpolation error: on each piece the polynomial interpolates at ``DEGREE + 1`` Chebyshev
points; the error is measured at build time at the Chebyshev points of the next degree (which lie
between the interpolation nodes) and stated per quantity (:attr:`ExcitationTable.max_error`,
relative to each quantity's scale). tests/models/test_torsional_table.py checks it against the
direct evaluation at random instants.

Blocks of :data:`BLOCK_MESH_PERIODS` mesh periods are built when the solver first asks for a time
inside them, so the memory grows with the span actually integrated, never with a guess of it.
"""

from __future__ import annotations

import bisect
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.polynomial import chebyshev as cheb
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
Values = tuple[float, float, float, float, float]

#: degree of the polynomial on each smooth piece (pieces are <= ~1/2 mesh period long)
DEGREE = 10
#: mesh periods per block of the table
BLOCK_MESH_PERIODS = 8


def _node_matrix(degree: int) -> tuple[FloatArray, FloatArray]:
    """Chebyshev points (first kind) on [-1, 1] and the matrix taking values there to monomial
    coefficients in s, highest power first (Horner order)."""
    n = degree + 1
    s = np.cos(np.pi * (np.arange(n) + 0.5) / n)
    vand = cheb.chebvander(s, degree)  # values = vand @ cheb_coefs
    to_cheb = np.linalg.inv(vand)
    to_mono = np.zeros((n, n))
    for k in range(n):
        unit = np.zeros(n)
        unit[k] = 1.0
        to_mono[: k + 1, k] = cheb.cheb2poly(unit)
    return s, (to_mono @ to_cheb)[::-1]


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
    max_error: FloatArray = field(init=False)
    _blocks: dict[int, tuple[list[float], list[float], list[float], list[list[Values]]]] = \
        field(init=False, repr=False)

    def __post_init__(self) -> None:
        self._blocks = {}
        self.max_error = np.zeros(5)

    def _build(self, b: int) -> tuple[list[float], list[float], list[float], list[list[Values]]]:
        """Fit block ``b`` (times ``b block .. (b + 1) block``)."""
        t0, t1 = b * self.block, (b + 1) * self.block
        edges = np.concatenate([[t0], self.cuts(t0, t1), [t1]])
        mid = 0.5 * (edges[1:] + edges[:-1])
        half = 0.5 * (edges[1:] - edges[:-1])
        s, to_mono = _node_matrix(DEGREE)
        vals = self.values((mid[:, None] + half[:, None] * s[None, :]).ravel())
        vals = vals.reshape(5, mid.size, s.size)
        coefs = np.einsum("ij,qpj->piq", to_mono, vals)  # (pieces, DEGREE + 1, 5)
        s_chk, _ = _node_matrix(DEGREE + 1)
        exact = self.values((mid[:, None] + half[:, None] * s_chk[None, :]).ravel())
        approx = np.zeros((5, mid.size, s_chk.size))
        for k in range(DEGREE + 1):
            approx = approx * s_chk[None, None, :] + coefs[:, k, :].T[:, :, None]
        err = np.max(np.abs(approx - exact.reshape(approx.shape)), axis=(1, 2)) / self.scale
        self.max_error = np.maximum(self.max_error, err)
        table = ([float(e) for e in edges[:-1]], [float(m) for m in mid],
                 [float(1.0 / h) for h in half],
                 [[tuple(float(v) for v in row) for row in piece] for piece in coefs])
        self._blocks[b] = table  # type: ignore[assignment]
        return table  # type: ignore[return-value]

    def __call__(self, t: float) -> Values:
        """The five quantities at time ``t`` (s) from the table."""
        b = int(t // self.block)
        tab = self._blocks.get(b)
        if tab is None:
            tab = self._build(b)
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
