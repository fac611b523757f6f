"""Step maps of affine models by Gauss-Legendre collocation, all steps at once (``gauss``).

For a model of the form ``q' = v``, ``v' = u(t) F + g_v`` with one scalar force
``F = f(t) . y + f0(t)``, ``y = [q, v]`` (``model.force_form(t)``; the two-DOF torsional model,
F the mesh force, valid while it is compressive so that the friction torques follow it), the
right-hand side is affine in the state, so the state after a step is an affine map of the state
before it, whatever that state is. All maps of a run are computed at once, vectorised over the
steps, and only their application is sequential:

- the output grid is cut at the switching instants (``model.switching_times``: the coefficients
  have kinks there) and each interval is divided into ``n`` equal substeps;
- each substep is one step of ``s``-stage Gauss-Legendre collocation (order ``2 s``, A-stable).
  Its stage equations are linear; with ``q' = v`` and one scalar force they reduce to ``s``
  equations for the stage forces ``F_i``: ``(I - G) F = B y0 + r`` with
  ``G_il = h^2 (a a)_il f_q,i . u_l + h a_il f_v,i . u_l``, one batched s x s solve (5 right-hand
  sides: the map of y0 and the constant); then
  ``v1 = v0 + h sum b_l (u_l F_l + g_v)``, ``q1 = q0 + h v0 + h^2 sum (b a)_l (u_l F_l + g_v)``;
- the maps are applied in order (one 4x4 product per substep), and, where the model says the
  form needs it (``model.force_form_needs_compression``: friction), the mesh force
  ``F = f_row . y + f0`` is checked at every substep end: where it is not compressive the affine
  form does not hold and the run falls back to the ODE path (:mod:`~gear_dyn.solvers.ode`).

Substeps: the local error of one Gauss step grows as ``(omega_n h)^(2 s + 1)`` (with the error
constant ``(s!)^4 / ((2 s + 1) ((2 s)!)^3)``, 5.6e-10 for s = 4); ``n`` is the smallest number
with ``(omega_n h / 2)^(2 s) <= rtol`` (``omega_n`` the model's natural angular frequency, ``h``
the longest substep), far on the safe side of that constant, and such that a run at rtol / 100
takes about 1.8 times the substeps, so that the two runs differ. The error is not otherwise
controlled; the stated error of a run (:mod:`gear_dyn.analysis.accuracy`) is its difference
from a second run at rtol / 100, i.e. with more substeps; tests/models/test_torsional_table.py
checks both against an independent reference (DOP853 at rtol 1e-13, coefficients evaluated
directly). Where both runs take the same ``n``, ``(omega_n h / 2)^(2 s) <= rtol / 100`` holds
and the error is below the rounding floor that the estimate states then.
"""

from __future__ import annotations

import functools
import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.models.base import Model
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
    """States after each of the ``maps`` in turn, from the augmented state ``z``: (m, 4)."""
    out = np.empty((maps.shape[0], 4))
    phi, c = maps[:, :4, :4], maps[:, :4, 4]
    y = z[:4].copy()
    for i in range(maps.shape[0]):
        y = phi[i] @ y + c[i]
        out[i] = y
    return out


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
