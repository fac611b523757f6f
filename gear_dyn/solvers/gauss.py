"""Step maps of affine models by Gauss-Legendre collocation, all steps at once (``gauss``).

For a model ``q' = v``, ``v' = u(t) F + g_v`` with one scalar force ``F = f(t) . y + f0(t)``
(``model.force_form(t)``: the torsional model, F the mesh force), the state after a step is an
affine map of the state before it. The output grid is cut at ``model.switching_times`` and each
interval divided into ``n`` substeps, each one ``s``-stage Gauss-Legendre step (order ``2 s``)
whose stage equations reduce to ``(I - G) F = B y0 + r`` for the stage forces: one s x s
elimination vectorised over all steps. Only the application of the maps is sequential (in the
compiled kernel). Where ``model.force_form_needs_compression`` and the force is not compressive at a
substep end, the run falls back to the ODE path (:mod:`~gear_dyn.solvers.ode`).

Substeps: ``n`` is the smallest with ``(omega_n h / 2)^(2 s) <= rtol``; the stated error is the
difference from a run at rtol / 100 (docs/solvers.md, "Eccentric torsional model").
"""

from __future__ import annotations

import functools
import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.models.base import Model
from gear_dyn.solvers import kernel
from gear_dyn.solvers.settings import SolverSettings

FloatArray = NDArray[np.float64]

#: Gauss-Legendre stages (order 2 STAGES)
STAGES = 4
#: substeps per batch (memory: CHUNK x (5 STAGES)^2 floats)
CHUNK = 4096


def gauss_applies(model: Model) -> bool:
    """True if ``model`` offers ``force_form`` (not None) and a natural frequency."""
    fn = getattr(model, "force_form", None)
    return (callable(fn) and model.natural_frequency is not None
            and fn(np.zeros(1)) is not None)


@functools.lru_cache(maxsize=4)
def tableau(s: int) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Nodes ``c``, matrix ``a`` and weights ``b`` of ``s``-stage Gauss-Legendre collocation."""
    x, w = np.polynomial.legendre.leggauss(s)
    c, b = 0.5 * (x + 1.0), 0.5 * w
    powers = np.arange(s)
    lagrange = np.linalg.inv(c[:, None] ** powers[None, :])  # l_j(t) = sum_k L[k, j] t^k
    integral = c[:, None] ** (powers[None, :] + 1) / (powers[None, :] + 1)
    return c, integral @ lagrange, b


def substeps(model: Model, h_max: float, rtol: float) -> int:
    """Substeps per interval: the smallest n with ``(omega_n h_max / (2 n))^(2 s) <= rtol``."""
    omega = 2 * math.pi * float(model.natural_frequency or 0.0)
    return max(1, math.ceil(omega * h_max / (2 * rtol ** (1.0 / (2 * STAGES)))))


def _edges(model: Model, t_grid: FloatArray) -> FloatArray:
    """The output grid with the switching instants inserted (none closer than 1e-12 s*f to a
    grid point)."""
    t0, t1 = float(t_grid[0]), float(t_grid[-1])
    cuts = np.asarray(model.switching_times(t0, t1), dtype=float)
    tol = 1e-12 * max(abs(t1), 1.0 / model.mesh_frequency)
    if cuts.size:
        i = np.clip(np.searchsorted(t_grid, cuts), 1, t_grid.size - 1)
        near = np.minimum(np.abs(cuts - t_grid[i - 1]), np.abs(t_grid[i] - cuts))
        cuts = cuts[near > tol]
    return np.sort(np.concatenate([t_grid, cuts]))


def _maps(model: Model, ta: FloatArray, h: FloatArray) -> FloatArray:
    """Augmented 5x5 affine maps of the substeps starting at ``ta`` with lengths ``h`` (s).

    The stage forces ``F_l`` solve ``(I - G) F = R [y0, 1]`` with ``G_il = h^2 (a a)_il
    f_q,i . u_l + h a_il f_v,i . u_l``: one s x s system per substep, all substeps at once by
    Gaussian elimination written out over the stage indices (arrays of the substeps: no
    per-matrix library call). ``G`` is small on the substeps of :func:`substeps` (entries of
    order ``(omega_n h)^2`` and ``xi omega_n h``), so elimination without pivoting is stable;
    :func:`_solve_stages` checks its pivots and falls back to a pivoted solve."""
    c, a, b = tableau(STAGES)
    s, m = STAGES, ta.size
    # stage-major order: every array below is (stage, ..., substep), contiguous in the substeps
    u, f, f0, gv = model.force_form((ta[None, :] + c[:, None] * h[None, :]).ravel())  # type: ignore[attr-defined]
    u = np.ascontiguousarray(u.reshape(s, m, 2).transpose(0, 2, 1))  # (s, 2, m)
    f = np.ascontiguousarray(f.reshape(s, m, 4).transpose(0, 2, 1))  # (s, 4, m)
    fq, fv, f0 = f[:, :2], f[:, 2:], f0.reshape(s, m)
    h2 = h * h
    # G_il = h^2 (aa)_il fq_i . u_l + h a_il fv_i . u_l
    uq = np.einsum("ikm,lkm->ilm", fq, u)
    uv = np.einsum("ikm,lkm->ilm", fv, u)
    aa = a @ a
    g = aa[:, :, None] * uq * h2 + a[:, :, None] * uv * h
    rhs = np.empty((s, 5, m))
    rhs[:, :2] = fq
    rhs[:, 2:4] = c[:, None, None] * fq * h + fv
    rhs[:, 4] = f0 + (aa.sum(axis=1)[:, None] * np.einsum("ikm,k->im", fq, gv) * h2
                      + c[:, None] * np.einsum("ikm,k->im", fv, gv) * h)
    forces = _solve_stages(g, rhs)  # (s, 5, m): F_l as a map of [y0, 1]
    ba = b @ a
    out = np.zeros((m, 5, 5))
    out[:, 0, 0] = out[:, 1, 1] = out[:, 2, 2] = out[:, 3, 3] = out[:, 4, 4] = 1.0
    out[:, 0, 2] = out[:, 1, 3] = h
    # sum_l u_l (ba_l, b_l) F_l: the position rows over h^2, the velocity rows over h
    pos = np.einsum("lkm,l,lpm->mkp", u, ba, forces)
    vel = np.einsum("lkm,l,lpm->mkp", u, b, forces)
    out[:, :2, :] += h2[:, None, None] * pos
    out[:, 2:4, :] += h[:, None, None] * vel
    out[:, :2, 4] += 0.5 * h2[:, None] * gv[None, :]
    out[:, 2:4, 4] += h[:, None] * gv[None, :]
    return out


def _solve_stages(g: FloatArray, rhs: FloatArray) -> FloatArray:
    """``X`` with ``(I - G) X = R`` for every substep: ``g`` (s, s, m), ``rhs`` (s, r, m).

    Gaussian elimination without pivoting over the stage indices, vectorised over the m
    substeps; where a pivot falls below 1/2 (``G`` not small: never with the substeps of
    :func:`substeps`), the batched LAPACK solve with partial pivoting instead."""
    s = g.shape[0]
    mat = -g
    for k in range(s):
        mat[k, k] += 1.0
    x = rhs.copy()
    for k in range(s):
        piv = mat[k, k].copy()
        if not np.min(np.abs(piv)) >= 0.5:
            full = np.linalg.solve(np.eye(s) - g.transpose(2, 0, 1), rhs.transpose(2, 0, 1))
            return np.asarray(full.transpose(1, 2, 0), dtype=float)
        mat[k] /= piv
        x[k] /= piv
        below = mat[k + 1:, k].copy()  # (s - k - 1, m)
        mat[k + 1:] -= below[:, None, :] * mat[k][None, :, :]
        x[k + 1:] -= below[:, None, :] * x[k][None, :, :]
    for k in range(s - 1, 0, -1):  # upper unit-triangular: back substitution
        x[:k] -= mat[:k, k][:, None, :] * x[k][None, :, :]
    return x


def _apply(maps: FloatArray, z: FloatArray) -> FloatArray:
    """States after each of the ``maps`` in turn, from the augmented state ``z``: (m, 4), in
    the compiled kernel (:func:`gear_dyn.solvers.kernel.chain`)."""
    return kernel.chain(maps[:, :4, :4], maps[:, :4, 4], z[:4])[1:]


def propagate_gauss(
    model: Model, t_grid: FloatArray, settings: SolverSettings, y0: FloatArray | None = None
) -> tuple[FloatArray, dict[str, Any]] | None:
    """States on ``t_grid`` by Gauss-Legendre step maps, or None where the mesh force is not
    compressive somewhere (the caller then uses the ODE path).

    Returns
    -------
    y : ndarray (n_states, n_t)
    stats : dict with nfev (right-hand-side coefficient evaluations), n_segments, n_substeps
    """
    edges = _edges(model, np.asarray(t_grid, dtype=float))
    n = substeps(model, float(np.max(np.diff(edges))), settings.rtol)
    frac = np.arange(n) / n
    starts = (edges[:-1, None] + np.diff(edges)[:, None] * frac[None, :]).ravel()
    lengths = np.repeat(np.diff(edges) / n, n)
    ends = np.append(starts[1:], edges[-1])
    needs_compression = bool(getattr(model, "force_form_needs_compression", True))
    y_start = np.array(model.initial_state() if y0 is None else y0, dtype=float)
    z = np.append(y_start, 1.0)
    states = np.empty((starts.size, 4))
    for lo in range(0, starts.size, CHUNK):
        hi = min(lo + CHUNK, starts.size)
        states[lo:hi] = _apply(_maps(model, starts[lo:hi], lengths[lo:hi]), z)
        z = np.append(states[hi - 1], 1.0)
        if not needs_compression:
            continue
        _, f_row, f0, _ = model.force_form(ends[lo:hi])  # type: ignore[attr-defined]
        if not np.all(np.einsum("ij,ij->i", f_row, states[lo:hi]) + f0 > 0.0):
            return None
    at_edge = np.vstack([y_start, states[n - 1::n]])
    idx = np.searchsorted(edges, t_grid)
    stats = {"nfev": int(starts.size * STAGES + ends.size), "njev": 0, "nlu": int(starts.size),
             "n_segments": int(edges.size - 1), "n_substeps": int(starts.size)}
    return np.ascontiguousarray(at_edge[idx].T), stats
