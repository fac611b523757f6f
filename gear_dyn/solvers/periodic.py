"""Linear mesh-periodic models on a commensurate grid: one period of step maps, then reused
(method ``periodic``, :func:`propagate_periodic`)."""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import SolverError
from gear_dyn.models.base import Model
from gear_dyn.solvers import kernel
from gear_dyn.solvers.ode import integrate_ode
from gear_dyn.solvers.settings import SolverSettings

FloatArray = NDArray[np.float64]

#: Gauss-Legendre stages of :func:`gauss_step_maps` (order 2 GAUSS_STAGES)
GAUSS_STAGES = 6


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


def coefficients(model: Any, t: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Stiffness ``k(t)`` (N/m) and excitation force (N) of the linear single-DOF model at the
    times ``t`` (s), vectorised: ``m x'' = force - c x' - k x`` with
    ``force = W + k e + c f_m e'`` (``e`` the transmission error, if any)."""
    p = model.mesh_frequency * t + model.phase0
    kt = np.asarray(model.stiffness(p), dtype=float)
    force = np.full(np.shape(t), float(model.static_load))
    te = model.transmission_error
    if te is not None:
        force = force + kt * np.asarray(te.value(p)) + model.damping * model.mesh_frequency \
            * np.asarray(te.slope(p))
    return kt, force


def _step_maps(model: Any, t0: float, dt: float, n_steps: int, rtol: float
               ) -> tuple[FloatArray, FloatArray, int]:
    """Affine maps ``y(t0 + (j+1) dt) = F_j y(t0 + j dt) + h_j``, j = 0..n_steps-1, of a linear
    single-DOF model, in the compiled kernel, and the coefficient evaluations they took.

    Each grid step is the product of fourth-order Magnus substeps with two Gauss points
    (Blanes, Casas, Oteo & Ros 2009, eq. 4.6): the period from ``t0`` is cut at the samples
    and at the phases where k or the transmission error jump or kink, every cell divided into
    equal substeps with ``(omega h / 2)^4 <= rtol`` (``omega = sqrt(max k / m)``; the substep
    grid and rows of :mod:`gear_dyn.solvers.linear_maps`, :func:`substep_grid` and
    :func:`magnus_rows`, the sweeps' rule). The kernel takes each substep's map
    (:func:`gear_dyn.solvers.kernel.linear.step_maps`: exact where the coefficients are
    constant in it) and composes the substeps of every grid step
    (:func:`gear_dyn.solvers.kernel.compose`).

    Error rule: the local error of a Magnus substep grows as ``(omega h)^5``, so
    ``(omega h / 2)^4 <= rtol`` keeps it near ``rtol`` per radian of the natural oscillation,
    relative to the state; the substeps follow ``rtol``, and the error does not depend on the
    number of output samples. Measured against DOP853 at rtol 1e-13 on the helicopter tail pair
    with the 5-term Fourier stiffness, the error relative to the static deflection stays below
    ``rtol`` (tests/analysis/test_solvers_bench.py). At most
    :data:`~gear_dyn.solvers.linear_maps.MAX_SUBSTEPS` substeps per period (beyond, the rule
    is not met: the run's stated error, an independent check, shows it).

    The third value is the coefficient evaluations, two per substep (``nfev``)."""
    # imported here: the slim FMU, which steps by the session and never takes this method,
    # leaves these two modules out (gear_dyn/fmu/staging.py)
    from gear_dyn.solvers.kernel.linear import step_maps
    from gear_dyn.solvers.linear_maps import magnus_rows, substep_grid

    fm = float(model.mesh_frequency)
    s_per = int(round(1.0 / (fm * dt)))
    start = math.fmod(fm * t0, 1.0)  # phase of the grid start after phase0, cycles
    starts, lengths, at_sample = substep_grid(model, s_per, fm, rtol, start)
    owner = np.searchsorted(at_sample, np.arange(starts.size), side="left")
    used = owner < n_steps  # a span shorter than a period: its steps only
    rows = magnus_rows(model, starts[used], lengths[used])
    f, h = (a[0] for a in step_maps(rows, np.array([fm])))
    parts = np.zeros((f.shape[0], 3, 3))
    parts[:, :2, :2] = f
    parts[:, :2, 2] = h
    parts[:, 2, 2] = 1.0
    total = kernel.compose(parts, owner[used], n_steps)
    if not np.all(np.isfinite(total)):
        raise SolverError("periodic maps: non-finite step maps (stiffness or load not finite "
                          "over the mesh period?)")
    return total[:, :2, :2].copy(), total[:, :2, 2].copy(), 2 * int(f.shape[0])


def gauss_step_maps(model: Any, t0: float, dt: float, n_steps: int, substeps: int = 1
                    ) -> tuple[FloatArray, FloatArray]:
    """The step maps of ``_step_maps()`` by ``GAUSS_STAGES``-stage Gauss-Legendre
    collocation instead of Magnus substeps: a second method, without error control of its own
    (the independent check of a ``periodic`` run's stated error).

    Each step is cut at its switching instants and at the kinks of k and the transmission error
    (:func:`~gear_dyn.solvers.linear_maps.kink_times`), and every piece divided into ``substeps``
    equal parts; on each part the collocation equations of ``y' = A(t) y + g(t)`` are linear (one
    batched ``2 s x 2 s`` solve for all parts at once, three right-hand sides: the map of the two
    states and the constant). Order ``2 s`` (12) where the coefficients are smooth within
    the parts; the error is checked by comparing two ``substeps`` (the caller's business,
    :mod:`gear_dyn.analysis.accuracy`).

    Returns
    -------
    f : ndarray (n_steps, 2, 2)
    h : ndarray (n_steps, 2)
        ``y(t0 + (j+1) dt) = f[j] y(t0 + j dt) + h[j]`` ([m, m/s]).
    """
    from gear_dyn.solvers.gauss import _edges, tableau
    from gear_dyn.solvers.linear_maps import kink_times

    c, a, b = tableau(GAUSS_STAGES)
    s = c.size
    grid = t0 + dt * np.arange(n_steps + 1, dtype=np.float64)
    edges = _edges(model, grid)  # the grid with the switching instants inserted
    cuts = kink_times(model, float(grid[0]), float(grid[-1]))  # and the kinks
    if cuts.size:
        tol = 1e-12 * max(abs(float(grid[-1])), 1.0 / model.mesh_frequency)
        i = np.clip(np.searchsorted(edges, cuts), 1, edges.size - 1)
        near = np.minimum(np.abs(cuts - edges[i - 1]), np.abs(edges[i] - cuts))
        edges = np.sort(np.concatenate([edges, cuts[near > tol]]))
    owner_piece = np.clip(np.searchsorted(grid, edges[:-1], side="right") - 1, 0, n_steps - 1)
    # every piece in `substeps` equal parts: start, length and step
    frac = np.arange(substeps) / substeps
    ta = (edges[:-1, None] + np.diff(edges)[:, None] * frac[None, :]).ravel()
    hh = np.repeat(np.diff(edges) / substeps, substeps)
    owner = np.repeat(owner_piece, substeps)
    kt, force = coefficients(model, (ta[:, None] + hh[:, None] * c[None, :]).ravel())
    parts = _collocation_maps(model, hh, kt.reshape(-1, s), force.reshape(-1, s), a, b)
    total = kernel.compose(parts, owner, n_steps)  # each step's parts in order
    return total[:, :2, :2].copy(), total[:, :2, 2].copy()


def _collocation_maps(model: Any, h: FloatArray, kt: FloatArray, force: FloatArray,
                      a: FloatArray, b: FloatArray) -> FloatArray:
    """Augmented 3x3 maps of one Gauss-Legendre step of lengths ``h`` (s), with the stiffness
    ``kt`` (N/m) and force (N) at the ``s`` nodes of each step: ``(m, s)`` arrays.

    With ``x' = v`` the stage positions ``X = x0 + h a V`` are eliminated: the stage velocities
    solve ``(I + h (c/m) a + h^2 a diag(k/m) a) V = v0 - h a (k/m) x0 + h a (F/m)``, one
    batched ``s x s`` solve with three right-hand sides (the maps of x0, v0 and the constant).
    """
    kk, ff = kt / model.mass, force / model.mass
    zeta = model.damping / model.mass
    s = a.shape[0]
    h1 = h[:, None, None]
    lhs = np.eye(s) + h1 * zeta * a + h1 * h1 * (a[None, :, :] * kk[:, None, :]) @ a
    rhs = np.empty((h.size, s, 3))
    rhs[:, :, 0] = -h[:, None] * (kk @ a.T)
    rhs[:, :, 1] = 1.0
    rhs[:, :, 2] = h[:, None] * (ff @ a.T)
    vel = np.linalg.solve(lhs, rhs)  # stage velocities as maps of [x0, v0, 1]
    pos = h1 * (a @ vel)
    pos[:, :, 0] += 1.0
    acc = -kk[:, :, None] * pos - zeta * vel
    acc[:, :, 2] += ff
    out = np.zeros((h.size, 3, 3))
    out[:, 0, :] = h[:, None] * np.einsum("l,klj->kj", b, vel)
    out[:, 1, :] = h[:, None] * np.einsum("l,klj->kj", b, acc)
    out[:, 0, 0] += 1.0
    out[:, 1, 1] += 1.0
    out[:, 2, 2] = 1.0
    return out


def fill_periodic(f: FloatArray, h: FloatArray, y0: FloatArray, n_samples: int, s_per: int,
                  products: tuple[FloatArray, FloatArray] | None = None) -> FloatArray:
    """States on a uniform grid of ``n_samples`` points (``s_per`` per mesh period) from
    ``y0`` and the step maps ``(f[j], h[j])`` of one period (or of all the steps where the span
    is shorter): the period map and the partial products are composed once, then each period
    start follows from the previous one and every sample is one matrix product from its period
    start, in the compiled kernel (:func:`gear_dyn.solvers.kernel.fill_periodic`; no truncation
    error, rounding only). ``products``: :func:`step_products` of the maps, if already
    computed. From the first non-finite state on, the samples are NaN (the callers check)."""
    q, r = step_products(f, h) if products is None else products
    return kernel.fill_periodic(q, r, np.asarray(y0, dtype=float), n_samples, s_per)[0]


def step_products(f: FloatArray, h: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Partial products of the step maps ``(f[j], h[j])``: ``y_j = q[j] y_0 + r[j]``,
    j = 0..len(f); ``(q[-1], r[-1])`` is the map over all the steps (over one mesh period: the
    one-period map, ``q[-1]`` the monodromy matrix). In the compiled kernel
    (:func:`gear_dyn.solvers.kernel.products`)."""
    return kernel.products(f, h)


def propagate_periodic(
    model: Model, t_grid: FloatArray, settings: SolverSettings | None = None,
    y0: FloatArray | None = None
) -> tuple[FloatArray, dict[str, Any]]:
    """States of a linear periodic model on a commensurate uniform grid by recurring step maps.

    A linear model whose coefficients have the mesh period ``T`` (``model.mesh_periodic and
    model.is_linear``: the single-DOF mesh model without backlash) and a grid with ``S`` samples
    per period: the step from ``t_i`` to ``t_{i+1}`` is the affine map ``(F_j, h_j)`` with
    ``j = i mod S``, the same in every period. The ``S`` maps are built once in the compiled
    kernel (``_step_maps``: Magnus substeps tied to ``settings.rtol``), composed into the
    one-period map and its partial products, and the whole span is then filled by matrix
    products (:func:`gear_dyn.solvers.periodic.fill_periodic`): one period of stepping
    instead of all of them. Falls back to LSODA (restarted) where it does not apply
    (:func:`periodic_map_applies`).

    The statistics carry the maps, ``step_maps`` = ``(F, h)``, where they cover a whole mesh
    period from the grid start (the period map, whose eigenvalues are the Floquet multipliers,
    is their product), and ``nfev``, the coefficient evaluations of the maps (two per Magnus
    substep: the work unit of a right-hand-side evaluation). The run's stated error
    (:func:`gear_dyn.analysis.accuracy.estimate_error`) does not rest on the substep rule: it
    compares the run with the same fill from :func:`~gear_dyn.solvers.periodic.gauss_step_maps`, an independent method.

    Raises
    ------
    SolverError
        Non-finite step maps or states.
    """
    t_grid = np.asarray(t_grid, dtype=float)
    settings = settings if settings is not None else SolverSettings()
    if not periodic_map_applies(model, t_grid):
        y, st = integrate_ode(model, t_grid, replace(settings, method="LSODA"), y0)
        return y, {**st, "method": "LSODA"}
    y = np.array(model.initial_state() if y0 is None else y0, dtype=float)
    dt = float(t_grid[1] - t_grid[0])
    s_per = int(round(1.0 / (model.mesh_frequency * dt)))
    s_used = min(s_per, t_grid.size - 1)
    f, h, nfev = _step_maps(model, float(t_grid[0]), dt, s_used, settings.rtol)
    out = fill_periodic(f, h, y, t_grid.size, s_per)
    if not np.all(np.isfinite(out)):
        raise SolverError("periodic-map propagation produced non-finite states: the response "
                          "diverges (parametric instability?)")
    stats: dict[str, Any] = {"nfev": int(nfev), "njev": 0, "nlu": 0, "n_segments": s_used,
                             "method": "periodic"}
    if s_used == s_per:
        stats["step_maps"] = (f, h)
    return out, stats
