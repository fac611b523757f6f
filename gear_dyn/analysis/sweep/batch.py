"""The steady method for a block of speeds of a linear single-DOF model, vectorised over speed.

Where the stiffness is piecewise constant (``linear_segments`` not None) the periodic orbit is
exact: per speed, the mesh period is cut at the stiffness switches and at the output samples
(``samples_per_period`` per period), every cell is an affine map ``y -> y* + E (y - y*)`` with
``E`` the closed-form 2x2 exponential (``gear_dyn.analysis.chart._expm2()``) and
``y* = [g / kappa, 0]`` the cell's equilibrium; their product is the one-period map, its fixed
point the orbit, and the same cells carry the orbit to the samples. All speeds of a block go
through each cell at once (numpy over speeds), so the per-speed cost is a few array rows instead
of a sequence of small matrix calls. (Stiffness that varies within a piece, or a transmission
error: :mod:`gear_dyn.analysis.sweep.smooth`, the same idea with fourth-order Magnus steps.)
The result equals the per-speed path
(:func:`gear_dyn.analysis.sweep.points.steady_point`) up to rounding (tests/analysis/
test_sweep_batch.py compares them).
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import lru_cache
from typing import cast

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.chart import _expm2
from gear_dyn.analysis.stability import UNIT_CIRCLE_TOL
from gear_dyn.analysis.sweep import smooth
from gear_dyn.analysis.sweep.points import _nan_point, _order_spectrum
from gear_dyn.analysis.sweep.types import Point, SweepOptions
from gear_dyn.models.base import MeshModel, Model
from gear_dyn.solvers import SolverSettings

FloatArray = NDArray[np.float64]


def _cells(model: MeshModel, spp: int) -> tuple[FloatArray, FloatArray, FloatArray,
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
    edges, owner = _phase_cells(np.round(starts[1:], 14).tobytes(), spp)
    return edges, -np.array(a10)[owner], -np.array(a11)[owner], np.array(g1)[owner]


@lru_cache(maxsize=64)
def _phase_cells(cuts: bytes, spp: int) -> tuple[FloatArray, NDArray[np.intp]]:
    """Cell edges (phase) cut at the pieces' starts ``cuts`` and at the samples; the piece of
    each cell."""
    starts = np.concatenate([[0.0], np.frombuffer(cuts)])
    edges = np.union1d(starts, np.arange(spp + 1) / spp)
    edges = edges[(edges >= 0) & (edges <= 1)]
    owner = np.clip(np.searchsorted(starts, 0.5 * (edges[:-1] + edges[1:]), side="right") - 1,
                    0, starts.size - 1)
    return edges, owner


def _piecewise_orbits(mesh: list[MeshModel], fm: FloatArray, spp: int
                      ) -> tuple[FloatArray, FloatArray] | None:
    """Exact orbits (S, 2, spp) and monodromy (S, 2, 2) for piecewise-constant stiffness, or
    None."""
    cells = [c for c in (_cells(m, spp) for m in mesh) if c is not None]
    if len(cells) < len(mesh) or any(not np.array_equal(c[0], cells[0][0]) for c in cells):
        return None  # not covered, or cells differ between speeds (not seen for sdof models)
    edges = cells[0][0]
    kappa, gamma, g = (np.stack([c[i] for c in cells]) for i in (1, 2, 3))  # (S, C): speed, cell
    dt = np.diff(edges)[None, :] / fm[:, None]
    e11, e12, e21, e22 = _expm2(0.0, dt, -kappa * dt, -gamma * dt)  # exp of A dt
    xs = g / kappa  # equilibrium deflection of each cell
    # cell map y -> E y + d with d = (I - E) y*, y* = [xs, 0]; the cells ending on a sample
    ends = np.flatnonzero(np.isin(np.round(edges[1:] * spp, 9), np.arange(1, spp + 1)))
    return smooth.compose_period((e11, e12, e21, e22, (1 - e11) * xs, -e21 * xs), ends, spp)


def linear_block(models: Sequence[Model], speeds: Sequence[float], settings: SolverSettings,
                 opts: SweepOptions) -> list[Point] | None:
    """Steady points of a linear single-DOF model at ``speeds`` (rad/s), all at once.

    Piecewise-constant stiffness without transmission error: the exact cells above. Varying
    stiffness or a transmission error (potential_energy, Weber, tip relief): the fourth-order
    Magnus step maps of :mod:`gear_dyn.analysis.sweep.smooth` over phase tables shared by the
    block. Returns None when a model is not covered (backlash, not single-DOF): the caller then
    takes the per-speed path.
    """
    if not models or any(not (m.mesh_periodic and m.is_linear) for m in models):
        return None
    mesh = [cast(MeshModel, m) for m in models]
    spp = settings.samples_per_period
    fm = np.array([m.mesh_frequency for m in mesh])
    orbit = _piecewise_orbits(mesh, fm, spp)
    if orbit is None:
        if not smooth.covered(mesh):
            return None
        orbit = smooth.orbits(mesh, spp, settings.rtol)
    y, phi = orbit
    mult = np.linalg.eigvals(phi)
    rho = np.max(np.abs(mult), axis=1)
    if not np.all(np.linalg.cond(np.eye(2)[None] - phi) < 1e14):
        return None  # a multiplier at 1: the per-speed path raises the SolverError
    ok = rho <= 1.0 + UNIT_CIRCLE_TOL
    dte = np.full((fm.size, spp), np.nan)
    force = np.full((fm.size, spp), np.nan)
    for i in np.flatnonzero(ok).tolist():
        out = mesh[i].outputs(np.arange(spp) / (fm[i] * spp), y[i])
        dte[i], force[i] = out["dte"], out["mesh_force"]
    if not (np.all(np.isfinite(dte[ok])) and np.all(np.isfinite(force[ok]))):
        return None  # overflow: the per-speed path reports it
    load = np.array([m.static_load for m in mesh])
    with np.errstate(invalid="ignore", divide="ignore"):
        df = np.where(load > 0, np.max(force, axis=1) / load, np.nan)
    spec = _order_spectrum(np.tile(dte, (1, opts.window_periods)), opts)
    rms, ptp, mean = np.std(dte, axis=1), np.ptp(dte, axis=1), np.mean(dte, axis=1)
    sep = np.mean(force < 0, axis=1)
    points = []
    for i, m in enumerate(mesh):
        if not ok[i]:
            points.append(_nan_point(m, float(speeds[i]), float(rho[i]), "unstable", opts))
            continue
        points.append(Point(float(speeds[i]), float(fm[i]), float(df[i]), float(rms[i]),
                            float(ptp[i]), float(mean[i]), float(rho[i]), True, True,
                            "periodic", float(sep[i]), 0.0, 0, spec[i], y[i, :, 0].copy(), 1))
    return points


__all__ = ["linear_block"]
