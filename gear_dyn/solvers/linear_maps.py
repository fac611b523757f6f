"""One-period maps of the linear single-DOF mesh model over many speeds at once.

For ``m x'' + c (x' - f_m e'(p)) + k(p) (x - e(p)) = W`` (``p = f_m t + p0`` the mesh phase, ``e``
the transmission error in m, ``e'`` its slope in m per cycle) the coefficients are functions of
the mesh phase only, so the same phase tables serve every speed of a block; only the step
length ``h = (phase step) / f_m`` depends on speed. Every step is an affine map
``y -> E y + q`` of the state ``[x, v]``, taken with the closed-form 2x2 exponential
(:func:`expm2`, the one in gear_dyn), for all speeds at once (numpy over speeds); the maps of one
mesh period compose into the one-period map (monodromy matrix and response,
:func:`compose_period`), whose fixed point is the periodic orbit, and the same maps carry it to
the output samples.

- Piecewise-constant stiffness without transmission error (:func:`piecewise_orbits`): the
  period is cut at the stiffness switches and at the samples (:func:`cells`); in each cell
  ``E = exp(A dt)`` and ``q = (I - E) y*`` with ``y* = [g / kappa, 0]`` the cell's equilibrium.
  Exact up to rounding.
- Varying stiffness or a transmission error (:func:`magnus_orbits`, where :func:`magnus_applies`):
  each cell is divided into equal substeps, each one step of the fourth-order Magnus integrator
  with two Gauss points (Blanes, Casas, Oteo & Ros 2009, eq. 4.6) on the augmented state
  ``[x, v, 1]``: ``Omega = h/2 (A1 + A2) + sqrt(3)/12 h^2 [A2, A1]``. Substeps:
  ``(omega h / 2)^4 <= rtol`` with ``omega = sqrt(max kappa)`` and ``h`` the longest substep at
  the block's lowest speed, the rule of :mod:`gear_dyn.solvers.gauss` for a fourth-order
  method; the local error of one step grows as ``(omega h)^5``.
- :func:`harmonic_orbits`: the same cells with the responses to unit harmonics of a
  transmission error (the tolerance study's superposition).
- :func:`cell_monodromy`: the monodromy matrix of a staircase stiffness over any grid of
  masses, dampings and mesh frequencies (the stability charts).

Callers: the steady sweep's linear blocks (:func:`gear_dyn.analysis.sweep.batch.linear_block`),
the stability charts (:mod:`gear_dyn.analysis.chart`) and the tolerance study
(:mod:`gear_dyn.analysis.tolerance`). tests/analysis/test_sweep_batch.py and
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

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: most substeps per period (memory and time bound: a sweep far below resonance would need more)
MAX_SUBSTEPS = 200_000
_G = math.sqrt(3) / 6  # Gauss points at 1/2 -+ _G of a step
_C3 = math.sqrt(3) / 12


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


def expm2(b11: FloatArray | float, b12: FloatArray, b21: FloatArray, b22: FloatArray
          ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """``exp(B)`` of 2x2 matrices ``B = [[b11, b12], [b21, b22]]`` given by components, in
    closed form, elementwise over any broadcast shape; returns ``(e11, e12, e21, e22)``.

    With ``mu = tr(B) / 2`` and ``d2 = mu^2 - det(B)``: ``exp(B) = e^mu (C I + S (B - mu I))``,
    ``C = cos(sqrt(-d2))``, ``S = sin(sqrt(-d2)) / sqrt(-d2)`` where ``d2 < 0`` (cosh and sinh
    where ``d2 >= 0``; the series of ``S`` where ``|d2|`` is small), from Cayley-Hamilton
    (``(B - mu I)^2 = d2 I``); exact up to rounding.
    """
    mu = 0.5 * (b11 + b22)
    det = b11 * b22 - b12 * b21
    d2 = mu * mu - det
    s = np.sqrt(np.abs(d2))
    small = s < 1e-4
    osc = d2 < 0
    s_osc, s_hyp = np.where(osc, s, 0.0), np.where(osc, 0.0, s)  # each only where it is taken
    with np.errstate(invalid="ignore", divide="ignore"):
        ch = np.where(osc, np.cos(s_osc), np.cosh(s_hyp))
        sh = np.where(small, 1 + d2 / 6 + d2 * d2 / 120,
                      np.where(osc, np.sin(s_osc), np.sinh(s_hyp)) / np.where(small, 1.0, s))
    em = np.exp(mu)
    return (em * (ch + sh * (b11 - mu)), em * sh * b12, em * sh * b21,
            em * (ch + sh * (b22 - mu)))


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
    kappa, gamma, g = (np.stack([c[i] for c in found]) for i in (1, 2, 3))  # (S, C): speed, cell
    dt = np.diff(edges)[None, :] / fm[:, None]
    e11, e12, e21, e22 = expm2(0.0, dt, -kappa * dt, -gamma * dt)  # exp of A dt
    xs = g / kappa  # equilibrium deflection of each cell
    # cell map y -> E y + d with d = (I - E) y*, y* = [xs, 0]; the cells ending on a sample
    ends = np.flatnonzero(np.isin(np.round(edges[1:] * spp, 9), np.arange(1, spp + 1)))
    return compose_period((e11, e12, e21, e22, (1 - e11) * xs, -e21 * xs), ends, spp)


def cell_monodromy(mass: float, edges: FloatArray, values: FloatArray, damping: FloatArray,
                   mesh_frequency: FloatArray
                   ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Monodromy matrix ``(p11, p12, p21, p22)`` of ``m x'' + c x' + k(f_m t) x = 0`` over one
    mesh period, for a piecewise-constant stiffness: the product of the cells' ``exp(A dt)``,
    vectorised.

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
    shape = np.broadcast_shapes(values.shape[:-1], damping.shape, fm.shape)
    p11 = np.ones(shape)
    p12 = np.zeros(shape)
    p21 = np.zeros(shape)
    p22 = np.ones(shape)
    gamma = damping / mass
    for j, w in enumerate(widths):
        dt = w / fm  # exp of [[0, 1], [-k/m, -c/m]] dt
        e11, e12, e21, e22 = expm2(0.0, dt, -values[..., j] / mass * dt, -gamma * dt)
        p11, p12, p21, p22 = (e11 * p11 + e12 * p21, e11 * p12 + e12 * p22,
                              e21 * p11 + e22 * p21, e21 * p12 + e22 * p22)
    return p11, p12, p21, p22


def harmonic_orbits(model: MeshModel, orders: FloatArray, spp: int
                    ) -> tuple[FloatArray, FloatArray, ComplexArray, ComplexArray, float] | None:
    """The load's periodic orbit and the responses to unit harmonics of the transmission error,
    exactly, cell by cell (:func:`cells`), for the linear single-DOF model with
    piecewise-constant stiffness and no transmission error of its own; None for any other model.

    With ``u = x - e`` the model reads ``u'' + gamma u' + kappa u = g - e''``. For the unit
    harmonic ``e = e^{i Omega t}`` (``Omega = 2 pi q f_m``, ``q`` a mesh order) the particular
    solution in a cell is ``U e^{i Omega t}``, ``U = Omega^2 / (kappa - Omega^2 + i gamma
    Omega)``, and the rest follows the cell's exponential (:func:`expm2`). The response is
    quasi-periodic, ``Z(t + T) = e^{2 pi i q} Z(t)``: its state at the period start solves
    ``(e^{2 pi i q} I - M) Z0 = r`` with ``M`` the monodromy matrix and ``r`` the response over
    one period from rest.

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
    dt = np.diff(edges) / fm
    e11, e12, e21, e22 = expm2(0.0, dt, -kappa * dt, -gamma * dt)
    om = 2 * math.pi * np.asarray(orders, dtype=float) * fm
    t_edge = edges / fm
    rot = np.exp(1j * om[None, :] * t_edge[:, None])  # (C+1, Q)
    u_part = om[None, :] ** 2 / (kappa[:, None] - om[None, :] ** 2
                                 + 1j * gamma[:, None] * om[None, :])  # (C, Q)
    xs = g / kappa
    at_sample = np.isin(np.round(edges * spp, 9), np.arange(spp))

    def sweep_cells(y: FloatArray, z: ComplexArray, record: bool
                    ) -> tuple[FloatArray, ComplexArray, list[Any]]:
        kept = []
        for c in range(dt.size):
            if record and at_sample[c]:
                kept.append((y.copy(), z.copy()))
            d1, d2 = y[0] - xs[c], y[1]
            y = np.array([xs[c] + e11[c] * d1 + e12[c] * d2, e21[c] * d1 + e22[c] * d2])
            pa0, pa1 = u_part[c] * rot[c], 1j * om * u_part[c] * rot[c]
            pb0, pb1 = u_part[c] * rot[c + 1], 1j * om * u_part[c] * rot[c + 1]
            w1, w2 = z[0] - pa0, z[1] - pa1
            z = np.array([pb0 + e11[c] * w1 + e12[c] * w2, pb1 + e21[c] * w1 + e22[c] * w2])
        return y, z, kept

    mono = np.eye(2)
    for c in range(dt.size):
        mono = np.array([[e11[c], e12[c]], [e21[c], e22[c]]]) @ mono
    rho = float(np.max(np.abs(np.linalg.eigvals(mono))))
    y_end, z_end, _ = sweep_cells(np.zeros(2), np.zeros((2, om.size), dtype=complex), False)
    y0 = np.asarray(np.linalg.solve(np.eye(2) - mono, y_end), dtype=np.float64)
    lam = np.exp(2j * math.pi * np.asarray(orders, dtype=float))
    z0 = np.stack([np.linalg.solve(lq * np.eye(2) - mono, z_end[:, i])
                   for i, lq in enumerate(lam)], axis=1) if om.size else z_end
    _, _, kept = sweep_cells(y0, z0, True)
    ys = np.stack([k[0] for k in kept], axis=1)  # (2, spp)
    zs = np.stack([k[1] for k in kept], axis=2)  # (2, Q, spp)
    return y0, ys, z0, zs, rho


def substep_grid(model: MeshModel, spp: int, fm_min: float, rtol: float
                 ) -> tuple[FloatArray, FloatArray, NDArray[np.intp]]:
    """Substeps of one period in phase: (starts, lengths, index of the substep ending at each
    output sample 1..spp)."""
    omega = math.sqrt(float(np.max(model.stiffness._dense())) / model.mass)
    h_max = 2 * rtol ** 0.25 * fm_min / omega  # phase length of the longest substep
    cuts = np.union1d(np.arange(spp + 1) / spp, _kinks(model))
    cuts = cuts[(cuts >= 0) & (cuts <= 1)]
    cuts = np.unique(np.concatenate([[0.0], cuts, [1.0]]))
    width = np.diff(cuts)
    keep = width > 1e-14
    edges_a, width = cuts[:-1][keep], width[keep]
    n = np.maximum(1, np.ceil(width / h_max).astype(int))
    if int(n.sum()) > MAX_SUBSTEPS:
        n = np.maximum(1, np.floor(n * MAX_SUBSTEPS / n.sum()).astype(int))
    starts = np.concatenate([a + w * np.arange(k) / k for a, w, k in zip(
        edges_a.tolist(), width.tolist(), n.tolist(), strict=True)])
    lengths = np.repeat(width / n, n)
    ends = np.cumsum(n) - 1  # substep ending each cell
    cell_end = edges_a + width
    sample_cells = [int(np.argmin(np.abs(cell_end - j / spp))) for j in range(1, spp + 1)]
    return starts, lengths, ends[sample_cells]


def magnus_orbits(models: Sequence[Model], spp: int, rtol: float
                  ) -> tuple[FloatArray, FloatArray]:
    """(orbit samples (S, 2, spp), monodromy (S, 2, 2)) of the models by Magnus substeps
    (where :func:`magnus_applies`). Sample j is at t = j / (f_m spp), j = 0..spp-1.
    """
    mesh = [cast(MeshModel, m) for m in models]
    m0 = mesh[0]
    fm = np.array([m.mesh_frequency for m in mesh])
    starts, lengths, at_sample = substep_grid(m0, spp, float(np.min(fm)), rtol)
    # phase tables at the two Gauss points of every substep, shared by every speed
    gp = [starts + (0.5 - _G) * lengths, starts + (0.5 + _G) * lengths]
    mass, c, w = m0.mass, m0.damping, m0.static_load
    te = m0.transmission_error
    kap, g0, g1 = [], [], []
    for p in gp:
        ph = p + m0.phase0
        k = np.asarray(m0.stiffness(ph), dtype=float)
        kap.append(k / mass)
        if te is None:
            g0.append(np.full_like(k, w / mass))
            g1.append(np.zeros_like(k))
        else:
            g0.append((w + k * np.asarray(te.value(ph), dtype=float)) / mass)
            g1.append(c * np.asarray(te.slope(ph), dtype=float) / mass)
    gam = c / mass
    h = lengths[None, :] / fm[:, None]  # (S, N) seconds
    ga = g0[0][None, :] + fm[:, None] * g1[0][None, :]
    gb = g0[1][None, :] + fm[:, None] * g1[1][None, :]
    d = (kap[0] - kap[1])[None, :]
    c3 = _C3 * h * h
    b11 = -c3 * d
    b12 = h
    b21 = -0.5 * h * (kap[0] + kap[1])[None, :] + c3 * gam * d
    b22 = -h * gam + c3 * d
    f1 = c3 * (ga - gb)
    f2 = 0.5 * h * (ga + gb) - c3 * gam * (ga - gb)
    e11, e12, e21, e22 = expm2(b11, b12, b21, b22)
    # affine part: B^-1 (E - I) f
    det = b11 * b22 - b12 * b21
    r1 = (e11 - 1) * f1 + e12 * f2
    r2 = e21 * f1 + (e22 - 1) * f2
    q1 = (b22 * r1 - b12 * r2) / det
    q2 = (-b21 * r1 + b11 * r2) / det
    return compose_period((e11, e12, e21, e22, q1, q2), at_sample, spp)


def compose_period(maps: tuple[FloatArray, ...], at_sample: NDArray[np.intp], spp: int
                   ) -> tuple[FloatArray, FloatArray]:
    """(orbit samples (S, 2, spp), monodromy (S, 2, 2)) of the affine maps ``y -> E_i y + q_i``
    of one period: ``maps = (E11, E12, E21, E22, q1, q2)``, each (S, N) over the speeds and the
    N steps in time order; ``at_sample[j - 1]`` is the step ending at sample j = 1..spp."""
    n_s, n = maps[0].shape
    # compose: y_k = P_k y0 + u_k after step k; keep them at the samples
    p11, p12, p21, p22 = (np.ones(n_s), np.zeros(n_s), np.zeros(n_s), np.ones(n_s))
    u1, u2 = np.zeros(n_s), np.zeros(n_s)
    keep = np.zeros(n, dtype=bool)
    keep[at_sample] = True
    saved = []
    cols = [a.T.copy() for a in maps]  # (N, S): contiguous rows
    for i in range(n):
        a11, a12, a21, a22, v1, v2 = (col[i] for col in cols)
        p11, p12, p21, p22 = (a11 * p11 + a12 * p21, a11 * p12 + a12 * p22,
                              a21 * p11 + a22 * p21, a21 * p12 + a22 * p22)
        u1, u2 = a11 * u1 + a12 * u2 + v1, a21 * u1 + a22 * u2 + v2
        if keep[i]:
            saved.append((p11, p12, p21, p22, u1, u2))
    phi = np.stack([np.stack([p11, p12], -1), np.stack([p21, p22], -1)], 1)
    y0 = np.linalg.solve(np.eye(2)[None] - phi, np.stack([u1, u2], -1)[:, :, None])[:, :, 0]
    out = np.empty((n_s, 2, spp))
    out[:, :, 0] = y0
    for j, (s11, s12, s21, s22, w1, w2) in enumerate(saved[:-1], start=1):
        out[:, 0, j] = s11 * y0[:, 0] + s12 * y0[:, 1] + w1
        out[:, 1, j] = s21 * y0[:, 0] + s22 * y0[:, 1] + w2
    return out, phi


__all__ = ["MAX_SUBSTEPS", "cell_monodromy", "cells", "compose_period", "expm2",
           "harmonic_orbits", "magnus_applies", "magnus_orbits", "phase_cells",
           "piecewise_orbits", "same_values", "substep_grid"]
