"""The steady method for a block of speeds of a linear single-DOF model, vectorised over speed.

The orbits and monodromy matrices of all speeds of a block come at once from the solvers' period
maps (:mod:`gear_dyn.solvers.linear_maps`): exact cells where the stiffness is piecewise
constant (``linear_segments`` not None), fourth-order Magnus substeps where it varies within a
piece or there is a transmission error. This module turns them into sweep points (stability,
dynamic factor, DTE figures, spectra), so the per-speed cost is a few array rows instead of a
sequence of small matrix calls. The result equals the per-speed path
(:func:`gear_dyn.analysis.sweep.points.steady_point`) up to rounding (tests/analysis/
test_sweep_batch.py compares them).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import cast

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.stability import (
    OrbitShape,
    PeriodicSolution,
    contact_states,
    floquet_stable,
)
from gear_dyn.analysis.sweep.points import _nan_point, _order_spectrum
from gear_dyn.analysis.sweep.types import Point, SweepOptions
from gear_dyn.models.base import MeshModel, Model
from gear_dyn.solvers import SolverSettings
from gear_dyn.solvers.linear_maps import magnus_applies, magnus_orbits, piecewise_orbits

FloatArray = NDArray[np.float64]


def linear_block(models: Sequence[Model], speeds: Sequence[float], settings: SolverSettings,
                 opts: SweepOptions) -> list[Point] | None:
    """Steady points of a linear single-DOF model at ``speeds`` (rad/s), all at once.

    Piecewise-constant stiffness without transmission error: the exact cells
    (:func:`~gear_dyn.solvers.linear_maps.piecewise_orbits`). Varying stiffness or a
    transmission error (potential_energy, Weber, tip relief): the fourth-order Magnus step maps
    over phase tables shared by the block (:func:`~gear_dyn.solvers.linear_maps.magnus_orbits`).
    Returns None when a model is not covered (backlash, not single-DOF): the caller then
    takes the per-speed path.
    """
    if not models or any(not (m.mesh_periodic and m.is_linear) for m in models):
        return None
    mesh = [cast(MeshModel, m) for m in models]
    spp = settings.samples_per_period
    fm = np.array([m.mesh_frequency for m in mesh])
    orbit = piecewise_orbits(mesh, fm, spp)
    how = "expm"
    if orbit is None:
        if not magnus_applies(mesh):
            return None
        orbit = magnus_orbits(mesh, spp, settings.rtol)
        how = "magnus"
    y, phi = orbit
    mult = np.linalg.eigvals(phi).astype(np.complex128)
    rho = np.max(np.abs(mult), axis=1)
    if not np.all(np.linalg.cond(np.eye(2)[None] - phi) < 1e14):
        return None  # a multiplier at 1: the per-speed path raises the SolverError
    ok = floquet_stable(rho)
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
    points = []
    for i, m in enumerate(mesh):
        sol = PeriodicSolution(y[i, :, 0].copy(), 1.0 / float(fm[i]), phi[i], mult[i], True, 0,
                               how)
        if not ok[i]:
            points.append(_nan_point(m, float(speeds[i]), "unstable", opts, orbit=sol))
            continue
        t = np.arange(spp) / (fm[i] * spp)
        shape = OrbitShape.of_samples(contact_states(m, t, y[i], force[i]), dte[i])
        points.append(Point(float(speeds[i]), float(fm[i]), float(df[i]), "periodic", 0,
                            spec[i], replace(sol, shape=shape), 1))
    return points


__all__ = ["linear_block"]
