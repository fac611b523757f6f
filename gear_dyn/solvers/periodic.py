"""Linear mesh-periodic models on a commensurate grid: one period of step maps, then reused.

A linear model whose coefficients have the mesh period ``T`` (``model.mesh_periodic and
model.is_linear``: the single-DOF mesh model without backlash), sampled ``S`` times per period:
every grid step is one of ``S`` affine maps that recur every period. They are integrated once and
the whole span is filled by matrix products (method ``periodic``).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import SolverError
from gear_dyn.models.base import Model
from gear_dyn.solvers.ode import integrate_ode
from gear_dyn.solvers.settings import SolverSettings

FloatArray = NDArray[np.float64]


def periodic_map_applies(model: Model, t_grid: FloatArray) -> bool:
    """True for a linear single-DOF model (no backlash) on a uniform grid commensurate with the
    mesh period (an integer number of samples per period): then every grid step is one of a
    few affine maps that recur every period (see :func:`propagate_periodic`)."""
    if not (model.mesh_periodic and model.is_linear) or t_grid.size < 3:
        return False
    dt = np.diff(t_grid)
    if np.ptp(dt) > 1e-9 * dt[0]:
        return False
    s = 1.0 / (model.mesh_frequency * float(dt.mean()))
    return abs(s - round(s)) < 1e-6 and round(s) >= 1


def _step_maps(model: Any, t0: float, dt: float, n_steps: int, rtol: float
               ) -> tuple[FloatArray, FloatArray, int]:
    """Affine maps ``y(t0 + (j+1) dt) = F_j y(t0 + j dt) + h_j``, j = 0..n_steps-1, of a linear
    single-DOF model: ``[F_j h_j]`` integrated from ``[I 0]`` with DOP853, all steps at once
    (one vectorised system), restarted at the switching instants of every step."""
    from scipy.integrate import solve_ivp

    n = 2
    m, c, w, fm, p0 = model.mass, model.damping, model.static_load, model.mesh_frequency, \
        model.phase0
    k = model.stiffness
    te = model.transmission_error
    starts = t0 + dt * np.arange(n_steps)
    # cut each step at its switching instants (offsets from the step start)
    offs: list[FloatArray] = []
    for ta in starts:
        cuts = model.switching_times(float(ta), float(ta + dt)) - ta
        offs.append(np.concatenate([[0.0], cuts, [dt]]))
    scale = np.asarray(model.state_scale, dtype=float)
    col = np.append(1.0 / scale, 1.0)
    atol_one = rtol * (scale[:, None] * col[None, :]).ravel()
    maps = np.empty((n_steps, n, n + 1))
    nfev = 0
    # group the steps by their number of cuts; integrate each group as one stacked system in
    # the local variable s, piece by piece (piece boundaries differ per step: handled by
    # mapping each piece to s in [0, 1])
    groups: dict[int, list[int]] = {}
    for j, o in enumerate(offs):
        groups.setdefault(o.size, []).append(j)
    for _size, idx in groups.items():
        ids = np.asarray(idx)
        bounds = np.stack([offs[j] for j in idx])  # (g, pieces+1)
        z = np.tile(np.hstack([np.eye(n), np.zeros((n, 1))]).ravel(), ids.size)
        for q in range(bounds.shape[1] - 1):
            a_off = starts[ids] + bounds[:, q]
            length = bounds[:, q + 1] - bounds[:, q]

            def rhs(s: float, zz: FloatArray, a_off: FloatArray = a_off,
                    length: FloatArray = length) -> FloatArray:
                # evaluate just inside the piece: at its ends k may jump (a switching instant)
                t = a_off + min(max(s, 1e-12), 1.0 - 1e-12) * length
                p = fm * t + p0
                kt = np.asarray(k(p), dtype=float)
                zr = zz.reshape(-1, n, n + 1)
                out = np.empty_like(zr)
                out[:, 0, :] = zr[:, 1, :]
                out[:, 1, :] = (-kt[:, None] * zr[:, 0, :] - c * zr[:, 1, :]) / m
                force = np.full(t.shape, w)
                if te is not None:
                    force = force + kt * np.asarray(te.value(p)) + c * fm * np.asarray(
                        te.slope(p))
                out[:, 1, n] += force / m
                return (out * length[:, None, None]).ravel()

            sol = solve_ivp(rhs, (0.0, 1.0), z, method="DOP853", rtol=rtol,
                            atol=np.tile(atol_one, ids.size))
            nfev += sol.nfev
            if sol.status != 0:
                raise SolverError(f"periodic maps: solve_ivp (DOP853) failed: {sol.message}")
            z = sol.y[:, -1]
        maps[ids] = z.reshape(-1, n, n + 1)
    return maps[:, :, :n], maps[:, :, n], nfev


def propagate_periodic(
    model: Model, t_grid: FloatArray, settings: SolverSettings | None = None,
    y0: FloatArray | None = None
) -> tuple[FloatArray, dict[str, Any]]:
    """States of a linear periodic model on a commensurate uniform grid by recurring step maps.

    A linear model whose coefficients have the mesh period ``T`` and a grid with ``S`` samples
    per period: the step from ``t_i`` to ``t_{i+1}`` is the affine map ``(F_j, h_j)`` with
    ``j = i mod S``, the same in every period. The ``S`` maps are integrated once (DOP853 at
    ``settings.rtol``, one stacked system, restarted at the switching instants), composed into
    the one-period map and its partial products, and the whole span is then filled by matrix
    products: one period of integration instead of all of them. Falls back to LSODA
    (restarted) where it does not apply (:func:`periodic_map_applies`).

    Raises
    ------
    SolverError
        Failed integration of the maps or non-finite states.
    """
    t_grid = np.asarray(t_grid, dtype=float)
    settings = settings if settings is not None else SolverSettings()
    rtol = settings.rtol
    if not periodic_map_applies(model, t_grid):
        y, st = integrate_ode(model, t_grid, replace(settings, method="LSODA"), y0)
        return y, {**st, "method": "LSODA"}
    y = np.array(model.initial_state() if y0 is None else y0, dtype=float)
    n = y.size
    dt = float(t_grid[1] - t_grid[0])
    s_per = int(round(1.0 / (model.mesh_frequency * dt)))
    n_steps = t_grid.size - 1
    s_used = min(s_per, n_steps)
    f, h, nfev = _step_maps(model, float(t_grid[0]), dt, s_used, rtol)
    # partial products within a period: state at offset j from the period start y_c:
    # y = Q_j y_c + r_j
    q = np.empty((s_used + 1, n, n))
    r = np.empty((s_used + 1, n))
    q[0], r[0] = np.eye(n), np.zeros(n)
    for j in range(s_used):
        q[j + 1] = f[j] @ q[j]
        r[j + 1] = f[j] @ r[j] + h[j]
    n_per = -(-n_steps // s_per) if s_used == s_per else 1
    starts = np.empty((n_per, n))
    z = y
    for cnum in range(n_per):
        starts[cnum] = z
        z = q[s_used] @ z + r[s_used]
    out = np.empty((n, t_grid.size))
    i = np.arange(t_grid.size)
    cyc = np.minimum(i // s_per, n_per - 1)
    off = i - cyc * s_per
    out[:] = (np.einsum("kij,kj->ki", q[off], starts[cyc]) + r[off]).T
    if not np.all(np.isfinite(out)):
        raise SolverError("periodic-map propagation produced non-finite states: the response "
                          "diverges (parametric instability?)")
    return out, {"nfev": int(nfev), "njev": 0, "nlu": 0, "n_segments": s_used,
                 "method": "periodic"}
