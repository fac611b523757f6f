"""Tables of the kernel's models in the mesh phase: the single-DOF model's piecewise polynomials.

The compiled kernel (``gd_kernel.c``) steps

    m_e x'' + c (x' - f_m e'(p)) + k(p) f(x - e(p)) = W,    p = mesh phase (cycles)

from a table over one mesh cycle: the breakpoints (the switching phases and every sample phase of
a piecewise-linear stiffness or transmission error) and, on each piece, the polynomial
coefficients of ``k(p)`` (N/m), ``e(p)`` (m) and ``de/dp`` (m per cycle) in the local variable
``s`` in [-1, 1] (Horner order, highest power first). The native FMU writes these arrays as C
text (:mod:`gear_dyn.fmu.export_c`); the solvers' ``kernel`` method hands them to the same kernel
through ctypes (:mod:`gear_dyn.solvers.kernel.run`). Which tables are exact and which fitted
(:data:`SMOOTH_PIECES`, :data:`SMOOTH_DEGREE`), and which pieces the kernel propagates in closed
form (*flat*): docs/native_fmu.md, "Tables".
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError
from gear_dyn.excitation import SampledSignal
from gear_dyn.models.sdof import SDOFModel
from gear_dyn.models.torsional_table import node_matrix
from gear_dyn.stiffness.periodic import PiecewiseStiffness

FloatArray = NDArray[np.float64]

#: equal pieces per mesh cycle for a smooth (Fourier, harmonic) stiffness or TE
SMOOTH_PIECES = 64
#: polynomial degree on those pieces
SMOOTH_DEGREE = 10
#: pieces closer than this (cycles) are merged
MIN_WIDTH = 1e-12
#: check points per piece of the contact-line form and the FMU's single-DOF tables
CHECK_POINTS = 24
#: the ends of :func:`check_points` sit this share of the half-width inside the piece: exactly
#: at a break, where a coefficient kinks or jumps, the model's value belongs to either side
END_INSET = 1e-9


def check_points(degree: int) -> FloatArray:
    """Where the error of a degree-``degree`` interpolant at the first-kind Chebyshev points
    (:func:`~gear_dyn.models.torsional_table.node_matrix`) is checked: the ``degree + 2``
    extrema of T_{degree+1}, ``cos(pi j / (degree + 1))``, the ends moved :data:`END_INSET`
    inside. The remainder is ``f^(n)(xi) / (2^(n-1) n!) T_n(s)`` with ``n = degree + 1``
    (Cauchy's remainder with the nodes' product written as T_n; Mason & Handscomb 2003,
    *Chebyshev Polynomials*, sec. 6.1), so where ``f^(n)`` varies little over the piece the
    error peaks at these points, the ends included."""
    u = np.cos(np.pi * np.arange(degree + 2) / (degree + 1))
    u[0], u[-1] = 1.0 - END_INSET, -1.0 + END_INSET
    return u


def piecewise_values(breaks: FloatArray, coef: FloatArray, phase: FloatArray,
                     period: float = 1.0) -> FloatArray:
    """Piecewise polynomials at phases (cycles, any real; ``period`` cycles per table),
    vectorised: array (quantities, n). ``coef`` (pieces, quantities, degree + 1) in
    ``s = (2 p - a - b) / (b - a)`` on the piece ``[a, b]`` of ``breaks``, highest power first."""
    p = np.mod(np.asarray(phase, dtype=float), period)
    i = np.clip(np.searchsorted(breaks, p, side="right") - 1, 0, breaks.size - 2)
    a, b = breaks[i], breaks[i + 1]
    s = (2 * p - a - b) / (b - a)
    c = coef[i]
    acc = c[:, :, 0].copy()
    for j in range(1, c.shape[2]):  # Horner
        acc = acc * s[:, None] + c[:, :, j]
    return acc.T


@dataclass(frozen=True)
class PhaseTable:
    """Piecewise polynomials of ``k``, ``e`` and ``de/dp`` over one mesh cycle.

    Attributes
    ----------
    breaks : ndarray (n + 1,)
        Piece edges in cycles, from 0 to 1.
    degree : int
        Polynomial degree (0 or 1: exact; :data:`SMOOTH_DEGREE`: fitted).
    coef : ndarray (n, 3, degree + 1)
        Coefficients of ``k`` (N/m), ``e`` (m), ``de/dp`` (m/cycle) in ``s = (2 p - a - b) /
        (b - a)`` on the piece ``[a, b]``, highest power first.
    flat : ndarray of bool (n,)
        ``k``, ``e`` constant and ``de/dp = 0`` on the piece.
    exact : bool
        True when every piece is exact (degree 0 or 1 pieces of a piecewise-linear model).
    max_error : dict
        Largest table error on the check points: ``k`` relative to the mean stiffness, ``e`` and
        ``de`` in m and m/cycle relative to the static deflection.
    """

    breaks: FloatArray
    degree: int
    coef: FloatArray
    flat: NDArray[np.bool_]
    exact: bool
    max_error: dict[str, float]

    def evaluate(self, phase: FloatArray) -> FloatArray:
        """``(k, e, de/dp)`` at phases (cycles, any real), vectorised: array (3, n)."""
        return piecewise_values(self.breaks, self.coef, phase)



def _knots(part: Any) -> tuple[FloatArray, bool] | None:
    """Sample phases of a piecewise-linear part and True, or (switching phases, False) for a
    smooth one; None for an absent part."""
    if part is None:
        return None
    if isinstance(part, PiecewiseStiffness):
        ph = np.concatenate([part.edges] + [np.asarray(s[0], float) for s in part.samples])
        return ph, True
    if isinstance(part, SampledSignal):
        phs: list[FloatArray] = [np.asarray(part.phase, dtype=float)]
        for name in ("edges", "seg_phase"):  # PiecewiseSignal's jumps and segments
            extra = getattr(part, name, None)
            if extra is not None and len(extra):
                phs.append(np.concatenate([np.atleast_1d(np.asarray(e, float)) for e in extra])
                          if name == "seg_phase" else np.asarray(extra, float))
        return np.concatenate(phs), True
    sw = getattr(part, "switching_phases", np.empty(0))
    return np.asarray(sw, dtype=float), False


def phase_table(model: SDOFModel) -> PhaseTable:
    """Tabulate ``k``, ``e`` and ``de/dp`` of a single-DOF model over one mesh cycle.

    Raises
    ------
    InputError
        A stiffness or transmission error the table cannot represent.
    """
    parts = [_knots(model.stiffness), _knots(model.transmission_error)]
    linear = all(p is None or p[1] for p in parts)
    edges = [np.array([0.0, 1.0])] + [p[0] for p in parts if p is not None]
    if not linear:
        edges.append(np.linspace(0.0, 1.0, SMOOTH_PIECES + 1))
    br = np.unique(np.mod(np.concatenate(edges), 1.0))
    br = np.append(br, 1.0)
    br = br[np.concatenate([[True], np.diff(br) > MIN_WIDTH])]
    br[-1] = 1.0
    if not np.all(np.isfinite(br)):
        raise InputError("native FMU table: non-finite switching phases")
    degree = 1 if linear else SMOOTH_DEGREE
    s, to_mono = node_matrix(degree)
    a, b = br[:-1], br[1:]
    mid, half = 0.5 * (a + b), 0.5 * (b - a)
    te = model.transmission_error

    def direct(ph: FloatArray) -> FloatArray:
        k = np.asarray(model.stiffness(ph), dtype=float)
        if te is None:
            return np.stack([k, np.zeros_like(k), np.zeros_like(k)])
        return np.stack([k, np.asarray(te.value(ph), float), np.asarray(te.slope(ph), float)])

    nodes = (mid[:, None] + half[:, None] * s[None, :])
    vals = direct(nodes.ravel()).reshape(3, a.size, s.size)
    coef = np.einsum("ij,qpj->pqi", to_mono, vals)  # (pieces, 3, degree + 1)
    flat = np.all(np.ptp(vals, axis=2) == 0.0, axis=0) & np.all(vals[2] == 0.0, axis=1)
    coef[flat, :, :-1] = 0.0
    coef[flat, :, -1] = vals[:, flat, 0].T
    table0 = PhaseTable(br, degree, coef, flat, linear, {})
    u = np.linspace(-0.98, 0.98, CHECK_POINTS)
    chk = (mid[:, None] + half[:, None] * u[None, :]).ravel()
    err = np.abs(table0.evaluate(chk) - direct(chk))
    x_s = max(model.static_load / model.mean_stiffness, 1e-12)
    scale = (model.mean_stiffness, x_s, x_s)
    max_error = {n: float(np.max(err[q])) / scale[q] for q, n in enumerate(("k", "e", "de"))}
    return PhaseTable(br, degree, coef, flat, linear, max_error)
