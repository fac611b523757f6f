"""ctypes face of the kernel's linear single-DOF steps (``gd_linear.c``), many speeds per call.

:mod:`gear_dyn.solvers.linear_maps` cuts one mesh period into steps and writes each as a row of
:data:`ROW_FIELDS` floats in the mesh phase, shared by every speed of a table: the step length
(cycles), ``kappa = k/m`` at the step's two Gauss points (1/s^2), ``gamma = c/m`` (1/s), the
speed-free forcing ``g0`` (m/s^2) and the forcing per unit mesh frequency ``g1`` (m/s) at the
two points; the model is ``x'' = -kappa x - gamma x' + g0 + f_m g1``. At mesh frequency
``f_m`` the kernel takes each step as the exponential of its augmented generator in closed
form: the fourth-order Magnus step with two Gauss points (Blanes, Casas, Oteo & Ros 2009,
eq. 4.6), exact where the coefficients are constant in the step. These functions check shapes;
they hold no algorithm.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from gear_dyn.solvers.kernel import _LONG, _c, _ptr, library

FloatArray = NDArray[np.float64]

#: floats per step row (``GD_LIN_ROW``)
ROW_FIELDS = 8


def expm2(b: FloatArray) -> FloatArray:
    """``exp(B)`` of 2x2 matrices ``b`` (shape ``(..., 2, 2)``), in closed form (Cayley-Hamilton,
    exact up to rounding)."""
    b = _c(b)
    if b.shape[-2:] != (2, 2):
        raise ValueError(f"expm2: matrices of shape {b.shape}, need (..., 2, 2)")
    out = np.empty_like(b)
    library().gd_lin_expm2(b.size // 4, _ptr(b), _ptr(out))
    return out


def _lanes(rows: FloatArray, fm: FloatArray, table: NDArray[np.intp] | None
           ) -> tuple[FloatArray, FloatArray, NDArray[np.integer] | None, int, int]:
    rows, fm = _c(rows), _c(np.atleast_1d(fm))
    if rows.ndim == 2:
        rows = rows[None]
    if rows.ndim != 3 or rows.shape[2] != ROW_FIELDS or fm.ndim != 1:
        raise ValueError(f"linear steps: rows of shape {rows.shape}, need (tables, steps, "
                         f"{ROW_FIELDS}); mesh frequencies of shape {fm.shape}, need (lanes,)")
    own = None
    if table is not None:
        own = np.ascontiguousarray(table, dtype=_LONG)
        if own.shape != fm.shape or (own.size and (own.min() < 0 or own.max() >= rows.shape[0])):
            raise ValueError(f"linear steps: table indices of shape {own.shape} in "
                             f"0..{rows.shape[0] - 1}, need one per lane ({fm.size})")
    elif rows.shape[0] != 1:
        raise ValueError(f"linear steps: {rows.shape[0]} tables and no table index per lane")
    return rows, fm, own, fm.size, rows.shape[1]


def step_maps(rows: FloatArray, fm: FloatArray, table: NDArray[np.intp] | None = None
              ) -> tuple[FloatArray, FloatArray]:
    """Every step's map ``y -> F y + h`` at each lane's mesh frequency.

    Parameters
    ----------
    rows : ndarray (tables, N, ROW_FIELDS) or (N, ROW_FIELDS)
        Step rows (module docstring), N steps per table in time order.
    fm : ndarray (L,)
        Mesh frequency of each lane, Hz.
    table : ndarray (L,) of int, optional
        The table of each lane (None: one table for all).

    Returns
    -------
    F : ndarray (L, N, 2, 2)
    h : ndarray (L, N, 2)
    """
    rows, fm, own, n_lanes, n_steps = _lanes(rows, fm, table)
    f, h = np.empty((n_lanes, n_steps, 2, 2)), np.empty((n_lanes, n_steps, 2))
    library().gd_lin_maps(n_lanes, n_steps, _ptr(rows), None if own is None else _ptr(own),
                          _ptr(fm), _ptr(f), _ptr(h))
    return f, h


def period_products(rows: FloatArray, fm: FloatArray, keep: NDArray[np.intp],
                    table: NDArray[np.intp] | None = None) -> tuple[FloatArray, FloatArray]:
    """Partial products ``y_i = P_i y_0 + u_i`` of each lane's steps after the steps ``keep``.

    Parameters
    ----------
    rows, fm, table
        As :func:`step_maps`.
    keep : ndarray (K,) of int
        Increasing step indices in 0..N-1 (the last step: the map over all of them).

    Returns
    -------
    P : ndarray (L, K, 2, 2)
    u : ndarray (L, K, 2)
    """
    rows, fm, own, n_lanes, n_steps = _lanes(rows, fm, table)
    kp = np.ascontiguousarray(keep, dtype=_LONG)
    if kp.ndim != 1 or (kp.size and (kp[0] < 0 or kp[-1] >= n_steps
                                     or np.any(np.diff(kp) <= 0))):
        raise ValueError(f"period_products: keep of shape {kp.shape} not increasing in "
                         f"0..{n_steps - 1}")
    p, u = np.empty((n_lanes, kp.size, 2, 2)), np.empty((n_lanes, kp.size, 2))
    library().gd_lin_period(n_lanes, n_steps, _ptr(rows), None if own is None else _ptr(own),
                            _ptr(fm), kp.size, _ptr(kp), _ptr(p), _ptr(u))
    return p, u


def responses(f: FloatArray, h: FloatArray) -> FloatArray:
    """Responses from rest of many offset sequences to one sequence of 2x2 maps: lane ``s``
    from ``y[s, 0] = 0``, ``y[s, i+1] = f[i] y[s, i] + h[s, i]``.

    Parameters
    ----------
    f : ndarray (N, 2, 2)
        The maps' matrices, in time order, shared by the lanes.
    h : ndarray (L, N, 2)
        Each lane's offsets.

    Returns
    -------
    ndarray (L, N + 1, 2)
    """
    f, h = _c(f), _c(h)
    if f.ndim != 3 or f.shape[1:] != (2, 2) or h.ndim != 3 or h.shape[1:] != (f.shape[0], 2):
        raise ValueError(f"responses: maps of shape {f.shape}, offsets {h.shape}: need (N, 2, 2)"
                         ", (lanes, N, 2)")
    y = np.empty((h.shape[0], f.shape[0] + 1, 2))
    library().gd_lin_chain(h.shape[0], f.shape[0], _ptr(f), _ptr(h), _ptr(y))
    return y


__all__ = ["ROW_FIELDS", "expm2", "period_products", "responses", "step_maps"]
