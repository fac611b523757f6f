"""The steady method for a block of speeds of a linear single-DOF model with *varying* stiffness.

For ``m x'' + c (x' - f_m e'(p)) + k(p) (x - e(p)) = W`` (``p = f_m t + p0`` the mesh phase,
``e`` the transmission error in m, ``e'`` its slope in m per cycle) the coefficients are
functions of the mesh phase only: ``kappa(p) = k(p) / m`` and the forcing
``g(p) = g0(p) + f_m g1(p)`` with ``g0 = (W + k e) / m`` and ``g1 = c e' / m``. These phase
tables are computed once per block and serve every speed of it; only the step length
``h = (phase step) / f_m`` depends on speed. (The model itself, with its stiffness tables or
loaded-contact analysis, is built once per sweep: ``model.at_mesh_frequency``.)

Per speed, the mesh period is cut at the output samples (``samples_per_period``), at the
stiffness switches and at the kinks of the tables (the samples of a piecewise-linear stiffness or
transmission error), and each cell into equal substeps. Each substep is one step of the
fourth-order Magnus integrator with two Gauss points (Blanes, Casas, Oteo & Ros 2009, eq. 4.6)
on the augmented state ``[x, v, 1]``: ``Omega = h/2 (A1 + A2) + sqrt(3)/12 h^2 [A2, A1]``, whose
2x2 exponential is taken in closed form. The substep maps compose into the one-period map
(monodromy matrix and response), whose fixed point is the periodic orbit; the same maps carry
it to the samples. All speeds of a block run through each substep at once (numpy over speeds).

Substeps: ``(omega h / 2)^4 <= rtol`` with ``omega = sqrt(max kappa)`` and ``h`` the longest
substep at the block's lowest speed, the rule of :mod:`gear_dyn.solvers.gauss` for a
fourth-order method; the local error of one step grows as ``(omega h)^5``.
tests/analysis/test_sweep_smooth.py compares the orbit with the per-speed path
(:func:`gear_dyn.analysis.sweep.points.steady_point`, DOP853 at a tight tolerance).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.chart import _expm2
from gear_dyn.models.base import MeshModel, Model

FloatArray = NDArray[np.float64]

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


def covered(models: Sequence[Model]) -> bool:
    """Whether :func:`orbits` applies: linear single-DOF mesh models of one stiffness, mass,
    damping and transmission error (the same model at other speeds)."""
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
        if not (m.mesh_periodic and m.is_linear and mm.stiffness is m0.stiffness
                and mm.mass == m0.mass and mm.damping == m0.damping
                and mm.phase0 == m0.phase0 and mm.transmission_error is m0.transmission_error
                and m.static_load == m0.static_load):
            return False
    return True


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


def orbits(models: Sequence[Model], spp: int, rtol: float
           ) -> tuple[FloatArray, FloatArray]:
    """(orbit samples (S, 2, spp), monodromy (S, 2, 2)) of the models (see :func:`covered`).

    Sample j is at t = j / (f_m spp), j = 0..spp-1.
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
    e11, e12, e21, e22 = _expm2(b11, b12, b21, b22)
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


__all__ = ["MAX_SUBSTEPS", "compose_period", "covered", "orbits", "substep_grid"]
