"""Exact propagation of linear models with piecewise-constant coefficients.

On each piece ``[ta, tb]`` the model is ``y' = A y + g`` with constant ``A`` and ``g`` (e.g. the
single-DOF model with a rectangular-wave stiffness, no backlash, no transmission error). Its
solution is exact:

    [y(ta + s); 1] = expm(M s) [y(ta); 1],   M = [[A, g], [0, 0]]

so the state is carried from piece to piece by one (n+1) x (n+1) matrix each, and the output grid
points are filled by batched matrix exponentials. There is no truncation error, only rounding
(about 1e-15 relative per product); it is the reference every integrator is measured against and
the fastest solver where it applies (registered as method ``exact``).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import expm

from .errors import InputError, SolverError
from .models.base import Model

FloatArray = NDArray[np.float64]


def _augmented(a: FloatArray, g: FloatArray) -> FloatArray:
    n = a.shape[0]
    m = np.zeros((n + 1, n + 1))
    m[:n, :n] = a
    m[:n, n] = g
    return m


def propagate_exact(
    model: Model, t_grid: FloatArray, settings: Any = None, y0: FloatArray | None = None
) -> tuple[FloatArray, dict[str, Any]]:
    """States of ``model`` on ``t_grid`` by exact piecewise matrix exponentials.

    Parameters
    ----------
    model : Model
        Must provide ``linear_segments(t0, t1)`` returning the pieces.
    t_grid : ndarray
        Increasing output times in s; the first is the initial time.
    settings : SolverSettings, unused
        Accepted for the solver registry's signature.
    y0 : ndarray or None
        Initial state; None uses ``model.initial_state()``.

    Returns
    -------
    y : ndarray (n_states, n_t)
    stats : dict
        ``nfev`` = number of matrix exponentials, ``n_segments``.

    Raises
    ------
    InputError
        The model is not linear with piecewise-constant coefficients.
    SolverError
        Non-finite states (a diverging response).
    """
    del settings
    getter = getattr(model, "linear_segments", None)
    t0, t1 = float(t_grid[0]), float(t_grid[-1])
    pieces = getter(t0, t1) if getter is not None else None
    if pieces is None:
        raise InputError(
            "solver.method = 'exact' needs a linear model with piecewise-constant coefficients "
            "(piecewise-constant stiffness, no backlash, no transmission error); "
            "use DOP853 or LSODA"
        )
    y = np.array(model.initial_state() if y0 is None else y0, dtype=float)
    n = y.size
    out = np.empty((n, t_grid.size))
    # group pieces with identical (A, g): the same matrices recur every mesh period
    keys: dict[bytes, int] = {}
    mats: list[FloatArray] = []
    piece_id = np.empty(len(pieces), dtype=int)
    starts = np.empty(len(pieces))
    ends = np.empty(len(pieces))
    for j, (ta, tb, a, g) in enumerate(pieces):
        m = _augmented(np.asarray(a, float), np.asarray(g, float))
        key = m.tobytes()
        if key not in keys:
            keys[key] = len(mats)
            mats.append(m)
        piece_id[j] = keys[key]
        starts[j], ends[j] = ta, tb
    mats_arr = np.stack(mats)
    # end-of-piece propagators, batched
    steps = mats_arr[piece_id] * (ends - starts)[:, None, None]
    phi = expm(steps)
    # which piece each grid point belongs to (a point on a cut belongs to the later piece)
    owner = np.clip(np.searchsorted(starts, t_grid, side="right") - 1, 0, len(pieces) - 1)
    tau = t_grid - starts[owner]
    grid_prop = expm(mats_arr[piece_id[owner]] * tau[:, None, None])
    # states at piece starts
    ys = np.empty((len(pieces), n + 1))
    z = np.append(y, 1.0)
    for j in range(len(pieces)):
        ys[j] = z
        z = phi[j] @ z
    out = np.einsum("kij,kj->ik", grid_prop, ys[owner])[:n]
    if not np.all(np.isfinite(out)):
        raise SolverError("exact propagation produced non-finite states: the response diverges")
    return out, {"nfev": int(len(pieces) + t_grid.size), "njev": 0, "nlu": 0,
                 "n_segments": len(pieces)}
