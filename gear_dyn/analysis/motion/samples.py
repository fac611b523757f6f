"""Stroboscopic (Poincare) samples: the state once per mesh period.

The single-DOF mesh model is periodic in the mesh period T = 1/f_m, so the map ``y(kT) ->
y((k+1)T)`` is its Poincare map on the section ``t = 0 mod T`` and the samples ``y(kT)`` show the
motion's structure: one point for a period-1 orbit, n points for a period-n orbit, a closed
curve for quasi-periodic motion, a fractal set for chaos (Parker & Chua 1989, ch. 6).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.stability import flow_on_grid
from gear_dyn.errors import InputError, check_range
from gear_dyn.models.base import MeshModel, Model
from gear_dyn.solvers.contact_exact import contact_exact_applies, propagate_contact_exact

FloatArray = NDArray[np.float64]

#: largest number of mesh periods one call samples (memory: two floats per period)
MAX_PERIODS = 1_000_000


def propagator(model: Model) -> str:
    """The flow :func:`flow_periods` uses for ``model``: ``exact_contact`` (closed form between
    located contact changes, :mod:`gear_dyn.solvers.contact_exact`) where it applies, else
    ``DOP853`` (event-located, cut at the stiffness switches,
    :func:`gear_dyn.analysis.stability.flow_on_grid`)."""
    return "exact_contact" if contact_exact_applies(model) else "DOP853"


def flow_periods(model: Model, y0: FloatArray, periods: int, rtol: float = 1e-10
                 ) -> FloatArray:
    """States at t = 0, T, ..., periods T from ``y(0) = y0`` (T = 1/f_m).

    Parameters
    ----------
    model : Model
        Single-DOF mesh model (``mesh_periodic``), with or without backlash.
    y0 : ndarray
        State at t = 0 (mesh phase ``model.phase0``), SI units [m, m/s].
    periods : int
        Mesh periods to run (1..1e6).
    rtol : float
        Relative tolerance of DOP853 (unused by the exact flow: rounding only).

    Returns
    -------
    ndarray (n_states, periods + 1)

    Raises
    ------
    InputError
        Not a mesh-periodic single-DOF model, or ``periods`` out of range.
    SolverError
        Integration failure or a diverging response.
    """
    if not (isinstance(model, MeshModel) and model.mesh_periodic):
        raise InputError(f"stroboscopic samples need a mesh-periodic single-DOF model; got "
                         f"{type(model).__name__}")
    check_range("periods", periods, "", low=1, high=MAX_PERIODS)
    t = np.arange(int(periods) + 1) / model.mesh_frequency
    y0 = np.asarray(y0, dtype=float)
    if contact_exact_applies(model):
        y, _stats = propagate_contact_exact(model, t, None, y0)
        return y
    return flow_on_grid(model, y0, t, rtol)


def stroboscopic(model: Model, y0: FloatArray, settle: int, samples: int, rtol: float = 1e-10
                 ) -> FloatArray:
    """``samples`` stroboscopic samples after ``settle`` mesh periods from ``y(0) = y0``.

    Parameters
    ----------
    model : Model
        Single-DOF mesh model.
    y0 : ndarray
        Start state at t = 0, SI units.
    settle : int
        Mesh periods run first and discarded (0..1e6).
    samples : int
        Samples kept (1..1e6): states at t = (settle + k) T, k = 0..samples-1.
    rtol : float
        Relative tolerance of DOP853 where the exact flow does not apply.

    Returns
    -------
    ndarray (samples, n_states)
        One row per mesh period, SI units.

    Raises
    ------
    InputError, SolverError
        As :func:`flow_periods`.
    """
    check_range("settle", settle, "", low=0, high=MAX_PERIODS)
    check_range("samples", samples, "", low=1, high=MAX_PERIODS)
    y = np.asarray(y0, dtype=float)
    if settle > 0:
        y = flow_periods(model, y, int(settle), rtol)[:, -1]
    if samples == 1:
        return y[None, :].copy()
    return flow_periods(model, y, int(samples) - 1, rtol).T.copy()
