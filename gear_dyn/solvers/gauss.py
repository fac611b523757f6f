"""Step maps of affine models by Gauss-Legendre collocation, all steps at once (``gauss``).

For a model ``q' = v``, ``v' = u(t) F + g_v`` with one scalar force ``F = f(t) . y + f0(t)``
(``model.force_form(t)``: the torsional model, F the mesh force), the state after a step is an
affine map of the state before it. The output grid is cut at ``model.switching_times`` and each
interval divided into ``n`` substeps, each one ``s``-stage Gauss-Legendre step (order ``2 s``)
whose stage equations reduce to ``(I - G) F = B y0 + r`` for the stage forces: one batched
s x s solve for all steps. Only the application of the maps is sequential (in the compiled
kernel). Where ``model.force_form_needs_compression`` and the force is not compressive at a
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
    """Augmented 5x5 affine maps of the substeps starting at ``ta`` with lengths ``h`` (s)."""
    c, a, b = tableau(STAGES)
    s, m = STAGES, ta.size
    u, f, f0, gv = model.force_form((ta[:, None] + h[:, None] * c[None, :]).ravel())  # type: ignore[attr-defined]
    u, f, f0 = u.reshape(m, s, 2), f.reshape(m, s, 4), f0.reshape(m, s)
    fq, fv = f[:, :, :2], f[:, :, 2:]
    aa = a @ a
    h1, h2 = h[:, None, None], (h * h)[:, None, None]
    # G_il = h^2 (aa)_il fq_i . u_l + h a_il fv_i . u_l
    ut = u.transpose(0, 2, 1)
    g = h2 * aa[None] * (fq @ ut) + h1 * a[None] * (fv @ ut)
    rhs = np.empty((m, s, 5))
    rhs[:, :, :2] = fq
    rhs[:, :, 2:4] = h1 * c[None, :, None] * fq + fv
    rhs[:, :, 4] = f0 + (h2[:, :, 0] * (aa.sum(axis=1))[None, :] * (fq @ gv)
                         + h1[:, :, 0] * c[None, :] * (fv @ gv))
    forces = np.linalg.solve(np.eye(s) - g, rhs)  # (m, s, 5): F_l as a map of [y0, 1]
    ba = b @ a
    out = np.zeros((m, 5, 5))
    eye2 = np.eye(2)
    out[:, :2, :2] = eye2
    out[:, :2, 2:4] = h1 * eye2
    out[:, 2:4, 2:4] = eye2
    out[:, 4, 4] = 1.0
    out[:, :2, :] += h2 * ((ut * ba[None, None, :]) @ forces)
    out[:, 2:4, :] += h1 * ((ut * b[None, None, :]) @ forces)
    out[:, :2, 4] += 0.5 * h2[:, :, 0] * gv[None, :]
    out[:, 2:4, 4] += h1[:, :, 0] * gv[None, :]
    return out


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
