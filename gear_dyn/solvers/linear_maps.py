"""One-period maps of the linear single-DOF mesh model over many speeds at once: the inputs.

For ``m x'' + c (x' - f_m e'(p)) + k(p) (x - e(p)) = W`` (``p = f_m t + p0`` the mesh phase, ``e``
the transmission error in m, ``e'`` its slope in m per cycle) the coefficients are functions of
the mesh phase only, so the same phase tables serve every speed of a block; only the step
length ``h = (phase step) / f_m`` depends on speed. This module cuts one mesh period into steps
and writes them as rows in phase (:mod:`gear_dyn.solvers.kernel.linear`); the compiled kernel
takes every step as an affine map ``y -> E y + q`` of the state ``[x, v]`` (the closed-form 2x2
exponential, the one in gear_dyn) and composes them over the period for all speeds in one call
(:func:`~gear_dyn.solvers.kernel.linear.period_products`). The fixed point of the period map
is the periodic orbit, and the partial products carry it to the output samples
(:func:`periodic_orbit`).

- Piecewise-constant stiffness without transmission error (:func:`piecewise_orbits`): the
  period is cut at the stiffness switches and at the samples (:func:`cells`,
  :func:`constant_rows`); in each cell ``E = exp(A dt)`` and ``q = (I - E) y*`` with
  ``y* = [g / kappa, 0]`` the cell's equilibrium. Exact up to rounding.
- Varying stiffness or a transmission error (:func:`magnus_orbits`, where :func:`magnus_applies`):
  each cell is divided into equal substeps, each one step of the fourth-order Magnus integrator
  with two Gauss points (Blanes, Casas, Oteo & Ros 2009, eq. 4.6) on the augmented state
  ``[x, v, 1]``: ``Omega = h/2 (A1 + A2) + sqrt(3)/12 h^2 [A2, A1]``. Substeps:
  ``(omega h / 2)^4 <= rtol`` with ``omega = sqrt(max kappa)`` and ``h`` the longest substep at
  the block's lowest speed, the rule of :mod:`gear_dyn.solvers.gauss` for a fourth-order
  method; the local error of one step grows as ``(omega h)^5``.
- :func:`harmonic_orbits`: the same cells with the responses to unit harmonics of a
  transmission error (the tolerance study's superposition): the cells' maps from the kernel,
  which also carries every harmonic's offsets through them
  (:func:`~gear_dyn.solvers.kernel.linear.responses`).
- :func:`cell_monodromy`: the monodromy matrix of a staircase stiffness over any grid of
  masses, dampings and mesh frequencies (the stability charts).

Callers: the steady sweep's linear blocks (:func:`gear_dyn.analysis.sweep.batch.linear_block`),
the stability charts (:mod:`gear_dyn.analysis.chart`), the tolerance study
(:mod:`gear_dyn.analysis.tolerance`) and the ``periodic`` method's step maps
(:mod:`gear_dyn.solvers.periodic`: :func:`substep_grid` from the grid's start phase and
:func:`magnus_rows` at one speed). tests/analysis/test_sweep_batch.py and
test_sweep_smooth.py compare the orbits with the per-speed path (DOP853 at a tight tolerance).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from functools import lru_cache
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from gear_dyn.models.base import MeshModel, Model
from gear_dyn.solvers import kernel
from gear_dyn.solvers.kernel.linear import ROW_FIELDS, period_products, responses, step_maps

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: most substeps per period (memory and time bound: a sweep far below resonance would need more)
MAX_SUBSTEPS = 200_000
_G = math.sqrt(3) / 6  # Gauss points at 1/2 -+ _G of a step


def _kinks(model: MeshModel) -> FloatArray:
    """Phases in [0, 1) (relative to ``phase0``) where k or e jump or have kinks."""
    k = model.stiffness
    cuts = [np.asarray(k.switching_phases, dtype=float)]
    for _ph, _v in getattr(k, "samples", ()) or ():
        cuts.append(np.asarray(_ph, dtype=float))
    te = model.transmission_error
    if te is not None and hasattr(te, "knots"):
        cuts.append(np.asarray(te.knots, dtype=float))
    p = np.mod(np.concatenate(cuts) - model.phase0, 1.0) if cuts else np.zeros(0)
    return np.unique(np.round(p, 13))


def kink_times(model: MeshModel, t0: float, t1: float) -> FloatArray:
    """Instants in ``(t0, t1)`` (s) where k or the transmission error jump or have kinks (the
    phases of ``_kinks``), sorted."""
    fm = model.mesh_frequency
    ph = _kinks(model)
    if ph.size == 0:
        return np.zeros(0)
    j = np.arange(math.floor(fm * t0) - 1, math.ceil(fm * t1) + 1, dtype=float)
    t = ((j[:, None] + ph[None, :]) / fm).ravel()
    return np.sort(t[(t > t0) & (t < t1)])


def magnus_applies(models: Sequence[Model]) -> bool:
    """Whether :func:`magnus_orbits` applies: linear single-DOF mesh models of one stiffness,
    mass, damping, phase, load and transmission error (the same model at other speeds).

    The stiffness and transmission error are compared by value (:func:`same_values`): a model
    built twice from the same inputs qualifies, not only one object shared by the speeds.
    """
    if not models:
        return False
    first = models[0]
    if not (first.mesh_periodic and first.is_linear and len(first.state_labels) == 2):
        return False
    m0 = cast(MeshModel, first)
    need = ("stiffness", "mass", "damping", "phase0", "transmission_error")
    if not all(hasattr(m0, a) for a in need):
        return False
    for m in models[1:]:
        mm = cast(Any, m)
        if not (m.mesh_periodic and m.is_linear and mm.mass == m0.mass
                and mm.damping == m0.damping and mm.phase0 == m0.phase0
                and m.static_load == m0.static_load
                and same_values(mm.stiffness, m0.stiffness)
                and same_values(mm.transmission_error, m0.transmission_error)):
            return False
    return True


def same_values(a: Any, b: Any) -> bool:
    """Whether ``a`` and ``b`` define the same thing: the same object, or objects of one type
    whose defining values are equal (a dataclass's ``__init__`` fields, compared recursively;
    arrays element by element; otherwise ``==``). Caches and derived fields (not in
    ``__init__``) are left out: they follow from the rest."""
    if a is b:
        return True
    if type(a) is not type(b):
        return False
    if dataclasses.is_dataclass(a) and not isinstance(a, type):
        return all(same_values(getattr(a, f.name), getattr(b, f.name))
                   for f in dataclasses.fields(a) if f.init)
    if isinstance(a, np.ndarray):
        return a.shape == b.shape and bool(np.array_equal(a, b))
    if isinstance(a, tuple | list):
        return len(a) == len(b) and all(same_values(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same_values(a[k], b[k]) for k in a)
    try:
        return bool(a == b)
    except (TypeError, ValueError):  # an object whose == is not a truth value
        return False


def cells(model: MeshModel, spp: int) -> tuple[FloatArray, FloatArray, FloatArray,
                                               FloatArray] | None:
    """Cells of one mesh period in phase (0..1): (edges, kappa, gamma, g) or None.

    ``kappa`` = k / m (1/s^2), ``gamma`` = c / m (1/s), ``g`` = F / m (m/s^2) per cell; None when
    the model is not a piecewise-constant ``x'' = -kappa x - gamma x' + g``.
    """
    fm = model.mesh_frequency
    pieces = model.linear_segments(0.0, 1.0 / fm)
    if pieces is None or len(model.state_labels) != 2:
        return None
    starts = np.array([p[0] for p in pieces]) * fm
    a10 = [float(p[2][1, 0]) for p in pieces]
    a11 = [float(p[2][1, 1]) for p in pieces]
    g1 = [float(p[3][1]) for p in pieces]
    if any(float(p[2][0, 0]) != 0 or float(p[2][0, 1]) != 1 or float(p[3][0]) != 0
           for p in pieces) or max(a10) >= 0:
        return None
    edges, owner = phase_cells(np.round(starts[1:], 14).tobytes(), spp)
    return edges, -np.array(a10)[owner], -np.array(a11)[owner], np.array(g1)[owner]


@lru_cache(maxsize=64)
def phase_cells(cuts: bytes, spp: int) -> tuple[FloatArray, NDArray[np.intp]]:
    """Cell edges (phase) cut at the pieces' starts ``cuts`` and at the samples; the piece of
    each cell."""
    starts = np.concatenate([[0.0], np.frombuffer(cuts)])
    edges = np.union1d(starts, np.arange(spp + 1) / spp)
    edges = edges[(edges >= 0) & (edges <= 1)]
    owner = np.clip(np.searchsorted(starts, 0.5 * (edges[:-1] + edges[1:]), side="right") - 1,
                    0, starts.size - 1)
    return edges, owner


def piecewise_orbits(mesh: list[MeshModel], fm: FloatArray, spp: int
                     ) -> tuple[FloatArray, FloatArray] | None:
    """Exact orbits (S, 2, spp) and monodromy (S, 2, 2) of the models ``mesh`` at the mesh
    frequencies ``fm`` (Hz), piecewise-constant stiffness (:func:`cells`), or None where a
    model is not covered. Sample j is at t = j / (f_m spp), j = 0..spp-1."""
    found = [c for c in (cells(m, spp) for m in mesh) if c is not None]
    if len(found) < len(mesh) or any(not np.array_equal(c[0], found[0][0]) for c in found):
        return None  # not covered, or cells differ between speeds (not seen for sdof models)
    edges = found[0][0]
    rows = np.stack([constant_rows(np.diff(edges), *c[1:]) for c in found])  # (S, C, ROW)
    # the cells ending on a sample
    ends = np.flatnonzero(np.isin(np.round(edges[1:] * spp, 9), np.arange(1, spp + 1)))
    p, u = period_products(rows, fm, ends, np.arange(len(found)))
    return periodic_orbit(p, u)


def constant_rows(widths: FloatArray, kappa: FloatArray, gamma: FloatArray | float,
                  g: FloatArray | float) -> FloatArray:
    """Kernel step rows (:mod:`gear_dyn.solvers.kernel.linear`) of cells with constant
    coefficients: phase ``widths`` (cycles), ``kappa`` (1/s^2), ``gamma`` (1/s) and ``g``
    (m/s^2) of each cell, broadcast over leading axes; shape ``(..., C, ROW_FIELDS)``."""
    kappa = np.asarray(kappa, dtype=float)
    shape = np.broadcast_shapes(np.shape(widths), kappa.shape, np.shape(gamma), np.shape(g))
    rows = np.zeros((*shape, ROW_FIELDS))
    rows[..., 0] = widths
    rows[..., 1] = kappa
    rows[..., 2] = kappa
    rows[..., 3] = gamma
    rows[..., 4] = g
    rows[..., 5] = g
    return rows


def cell_monodromy(mass: float, edges: FloatArray, values: FloatArray, damping: FloatArray,
                   mesh_frequency: FloatArray
                   ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Monodromy matrix ``(p11, p12, p21, p22)`` of ``m x'' + c x' + k(f_m t) x = 0`` over one
    mesh period, for a piecewise-constant stiffness: the product of the cells' ``exp(A dt)``,
    taken by the kernel in one call (a table of cells per stiffness and damping, each lane one
    point of the grid).

    Parameters
    ----------
    mass : float
        m_e in kg.
    edges : ndarray (S+1,)
        Cell edges of the stiffness in mesh cycles, 0..1.
    values : ndarray (..., S)
        Stiffness of each cell in N/m; leading axes broadcast with ``damping`` and
        ``mesh_frequency``.
    damping : ndarray (...)
        c in N s/m.
    mesh_frequency : ndarray (...)
        f_m in Hz.
    """
    values = np.asarray(values, dtype=float)
    widths = np.diff(np.asarray(edges, dtype=float))
    damping = np.asarray(damping, dtype=float)
    fm = np.asarray(mesh_frequency, dtype=float)
    lead = np.broadcast_shapes(values.shape[:-1], damping.shape)  # one step table each
    shape = np.broadcast_shapes(lead, fm.shape)
    n_tab = math.prod(lead)
    kappa = np.broadcast_to(values, (*lead, widths.size)).reshape(n_tab, widths.size) / mass
    gamma = np.broadcast_to(damping / mass, lead).reshape(n_tab, 1)
    table = np.broadcast_to(np.arange(n_tab).reshape(lead), shape).ravel()
    p, _ = period_products(constant_rows(widths, kappa, gamma, 0.0),
                           np.broadcast_to(fm, shape).ravel(), np.array([widths.size - 1]),
                           table)
    p = p[:, 0].reshape(*shape, 2, 2)
    return p[..., 0, 0], p[..., 0, 1], p[..., 1, 0], p[..., 1, 1]


def harmonic_orbits(model: MeshModel, orders: FloatArray, spp: int
                    ) -> tuple[FloatArray, FloatArray, ComplexArray, ComplexArray, float] | None:
    """The load's periodic orbit and the responses to unit harmonics of the transmission error,
    exactly, cell by cell (:func:`cells`), for the linear single-DOF model with
    piecewise-constant stiffness and no transmission error of its own; None for any other model.

    With ``u = x - e`` the model reads ``u'' + gamma u' + kappa u = g - e''``. For the unit
    harmonic ``e = e^{i Omega t}`` (``Omega = 2 pi q f_m``, ``q`` a mesh order) the particular
    solution in a cell is ``U e^{i Omega t}``, ``U = Omega^2 / (kappa - Omega^2 + i gamma
    Omega)``, and the rest follows the cell's exponential (its map from the kernel). The
    response is quasi-periodic, ``Z(t + T) = e^{2 pi i q} Z(t)``: its state at the period
    start solves ``(e^{2 pi i q} I - M) Z0 = r`` with ``M`` the monodromy matrix and ``r`` the
    response over one period from rest.

    Parameters
    ----------
    model : MeshModel
    orders : ndarray (Q,)
        Mesh orders q.
    spp : int
        Samples per mesh period (phases ``j / spp`` after ``phase0``).

    Returns
    -------
    y0 : ndarray (2,)
        The load's orbit [x, v] (m, m/s) at t = 0.
    ys : ndarray (2, spp)
        That orbit at the samples.
    z0 : ndarray (2, Q), complex
        ``[u, u']`` of each unit response at t = 0 (m per m of e, 1/s).
    zs : ndarray (2, Q, spp), complex
        Those responses at the samples.
    rho : float
        Spectral radius of the monodromy matrix.
    """
    found = cells(model, spp) if model.transmission_error is None else None
    if found is None or model.backlash is not None:
        return None
    edges, kappa, gamma, g = found
    fm = model.mesh_frequency
    f, q = (a[0] for a in step_maps(constant_rows(np.diff(edges), kappa, gamma, g),
                                    np.array([fm])))
    om = 2 * math.pi * np.asarray(orders, dtype=float) * fm
    rot = np.exp(1j * om[None, :] * (edges / fm)[:, None])  # (C+1, Q)
    u_part = om[None, :] ** 2 / (kappa[:, None] - om[None, :] ** 2
                                 + 1j * gamma[:, None] * om[None, :])  # (C, Q)

    def particular(r: ComplexArray) -> ComplexArray:  # [u, u'] of the particular solution
        return np.stack([u_part * r, 1j * om * u_part * r], axis=-1)  # (C, Q, 2)

    # the cell's map of a unit response: z -> p_b + F (z - p_a), p_a, p_b the particular
    # solution at the cell's start and end
    h_z = particular(rot[1:]) - np.einsum("cij,cqj->cqi", f, particular(rot[:-1]))
    # products of the cells' maps: the load's orbit, then the real and imaginary parts of each
    # unit response (the same matrices, other offsets)
    mono, r_y = kernel.products(f, q)
    parts = responses(f, np.concatenate([h_z.real, h_z.imag], axis=1).transpose(1, 0, 2))
    r_z = (parts[:om.size] + 1j * parts[om.size:]).transpose(1, 0, 2)  # (C+1, Q, 2)
    rho = float(np.max(np.abs(np.linalg.eigvals(mono[-1]))))
    y0 = np.asarray(np.linalg.solve(np.eye(2) - mono[-1], r_y[-1]), dtype=np.float64)
    lam = np.exp(2j * math.pi * np.asarray(orders, dtype=float))
    z0 = np.stack([np.linalg.solve(lq * np.eye(2) - mono[-1], r_z[-1, i])
                   for i, lq in enumerate(lam)], axis=1) if om.size else np.zeros((2, 0), complex)
    at = np.flatnonzero(np.isin(np.round(edges[:-1] * spp, 9), np.arange(spp)))  # sample cells
    ys = (np.einsum("sij,j->is", mono[at], y0) + r_y[at].T).astype(np.float64)  # (2, spp)
    zs = np.einsum("sij,jq->iqs", mono[at], z0) + r_z[at].transpose(2, 1, 0)  # (2, Q, spp)
    return y0, ys, z0, zs, rho


def substep_grid(model: MeshModel, spp: int, fm_min: float, rtol: float, start: float = 0.0
                 ) -> tuple[FloatArray, FloatArray, NDArray[np.intp]]:
    """Substeps of one period in phase: (starts, lengths, index of the substep ending at each
    output sample 1..spp).

    The period runs from the phase ``start`` (cycles after ``phase0``; the first output
    sample) to ``start + 1``, the samples at ``start + j / spp``; every cell between samples
    and kinks (``_kinks``) is divided into equal substeps of at most
    ``2 rtol^(1/4) f_m / omega`` cycles (``(omega h / 2)^4 <= rtol`` at the lowest mesh
    frequency ``fm_min``, ``omega = sqrt(max k / m)``), at most :data:`MAX_SUBSTEPS` in all."""
    omega = math.sqrt(float(np.max(model.stiffness._dense())) / model.mass)
    h_max = 2 * rtol ** 0.25 * fm_min / omega  # phase length of the longest substep
    samples = start + np.arange(spp + 1) / spp
    kinks = start + np.mod(_kinks(model) - start, 1.0)
    cuts = np.union1d(samples, kinks)
    cuts = cuts[(cuts >= start) & (cuts <= start + 1)]
    cuts = np.unique(np.concatenate([[start], cuts, [start + 1.0]]))
    width = np.diff(cuts)
    keep = width > 1e-14
    edges_a, width = cuts[:-1][keep], width[keep]
    n = np.maximum(1, np.ceil(width / h_max).astype(int))
    if int(n.sum()) > MAX_SUBSTEPS:
        n = np.maximum(1, np.floor(n * MAX_SUBSTEPS / n.sum()).astype(int))
    ends = np.cumsum(n) - 1  # substep ending each cell
    local = np.arange(int(ends[-1]) + 1) - np.repeat(ends + 1 - n, n)  # substep within its cell
    starts = np.repeat(edges_a, n) + np.repeat(width, n) * local / np.repeat(n, n)
    lengths = np.repeat(width / n, n)
    # the cell ending nearest each sample
    cell_end = edges_a + width
    right = np.clip(np.searchsorted(cell_end, samples[1:]), 0, cell_end.size - 1)
    left = np.maximum(right - 1, 0)
    nearer_left = np.abs(cell_end[left] - samples[1:]) <= np.abs(cell_end[right] - samples[1:])
    return starts, lengths, ends[np.where(nearer_left, left, right)]


def magnus_rows(model: MeshModel, starts: FloatArray, lengths: FloatArray) -> FloatArray:
    """Kernel step rows (:mod:`gear_dyn.solvers.kernel.linear`) of the Magnus substeps with
    phase ``starts`` (cycles after ``phase0``) and ``lengths`` (cycles): the stiffness, load
    and transmission error at the two Gauss points of each, speed-free (the mesh frequency
    enters in the kernel). Shape ``(N, ROW_FIELDS)``."""
    gp = [starts + (0.5 - _G) * lengths, starts + (0.5 + _G) * lengths]
    mass, c, w = model.mass, model.damping, model.static_load
    te = model.transmission_error
    kap, g0, g1 = [], [], []
    for p in gp:
        ph = p + model.phase0
        k = np.asarray(model.stiffness(ph), dtype=float)
        kap.append(k / mass)
        if te is None:
            g0.append(np.full_like(k, w / mass))
            g1.append(np.zeros_like(k))
        else:
            g0.append((w + k * np.asarray(te.value(ph), dtype=float)) / mass)
            g1.append(c * np.asarray(te.slope(ph), dtype=float) / mass)
    return np.stack([lengths, kap[0], kap[1], np.full_like(lengths, c / mass), g0[0], g0[1],
                     g1[0], g1[1]], axis=-1)


def magnus_orbits(models: Sequence[Model], spp: int, rtol: float
                  ) -> tuple[FloatArray, FloatArray]:
    """(orbit samples (S, 2, spp), monodromy (S, 2, 2)) of the models by Magnus substeps
    (where :func:`magnus_applies`). Sample j is at t = j / (f_m spp), j = 0..spp-1.
    """
    mesh = [cast(MeshModel, m) for m in models]
    m0 = mesh[0]
    fm = np.array([m.mesh_frequency for m in mesh])
    starts, lengths, at_sample = substep_grid(m0, spp, float(np.min(fm)), rtol)
    p, u = period_products(magnus_rows(m0, starts, lengths), fm, at_sample)
    return periodic_orbit(p, u)


def periodic_orbit(p: FloatArray, u: FloatArray) -> tuple[FloatArray, FloatArray]:
    """(orbit samples (S, 2, spp), monodromy (S, 2, 2)) from the partial products of one
    period's step maps after each sample 1..spp
    (:func:`~gear_dyn.solvers.kernel.linear.period_products`: ``p`` (S, spp, 2, 2), ``u``
    (S, spp, 2); the last, the period): the fixed point ``y0 = P y0 + u`` of the period map
    and the samples ``P_j y0 + u_j``."""
    phi = p[:, -1]
    y0 = np.linalg.solve(np.eye(2)[None] - phi, u[:, -1][:, :, None])[:, :, 0]
    out = np.empty((p.shape[0], 2, p.shape[1]))
    out[:, :, 0] = y0
    out[:, :, 1:] = (np.einsum("sjik,sk->sij", p[:, :-1], y0) + u[:, :-1].transpose(0, 2, 1))
    return out, phi


__all__ = ["MAX_SUBSTEPS", "cell_monodromy", "cells", "constant_rows", "harmonic_orbits",
           "kink_times", "magnus_applies", "magnus_orbits", "magnus_rows", "periodic_orbit",
           "phase_cells", "piecewise_orbits", "same_values", "substep_grid"]
