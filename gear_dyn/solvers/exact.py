"""Exact propagation of linear models with piecewise-constant coefficients (method ``exact``).

On each piece ``[ta, tb]`` the model is ``y' = A y + g`` with constant ``A`` and ``g``, so

    [y(ta + s); 1] = expm(M s) [y(ta); 1],   M = [[A, g], [0, 0]]

(no inverse of ``A``: a singular ``A``, a rigid-body mode, is covered). No truncation error, only
rounding. Pieces with the same ``M`` share one (balanced) eigendecomposition, vectorised over
all their ``s``; an ill-conditioned one falls back to :func:`scipy.linalg.expm` on the distinct
``s`` only (docs/solvers.md).

On a uniform grid commensurate with the mesh period of a mesh-periodic model the exponentials
are taken over one period only: the grid's step maps (each step cut at its switching instants),
which recur every period, are applied by the compiled kernel
(:func:`gear_dyn.solvers.kernel.fill_periodic`). Elsewhere every sample is propagated from its
piece start, whose state the kernel chains from piece to piece
(:func:`gear_dyn.solvers.kernel.chain`).

:class:`StepPropagator` is the same route one step at a time on plain floats, with the
exponentials of the recurring step durations cached: the stepwise session's ``exact`` mode
(:class:`gear_dyn.solvers.session.Session`, which the FMU advances by communication steps).
"""

from __future__ import annotations

import functools
import math
import operator
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError, SolverError
from gear_dyn.models.base import Model
from gear_dyn.solvers import kernel

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: largest condition number of the eigenvector matrix accepted for the eigen route; beyond it the
#: rounding error cond * eps could exceed ~1e-12 and the batched Pade expm is used instead
MAX_EIGEN_CONDITION = 1e3


def _augmented(a: FloatArray, g: FloatArray) -> FloatArray:
    n = a.shape[0]
    m = np.zeros((n + 1, n + 1))
    m[:n, :n] = a
    m[:n, n] = g
    return m


def _unique_tol(x: FloatArray, tol: float) -> tuple[FloatArray, NDArray[np.intp]]:
    """Distinct values of ``x`` up to ``tol`` (values closer than tol merge) and the index map."""
    order = np.argsort(x, kind="stable")
    xs = x[order]
    new = np.empty(xs.size, dtype=bool)
    if xs.size:
        new[0] = True
        new[1:] = np.diff(xs) > tol
    group = np.cumsum(new) - 1
    inv = np.empty(x.size, dtype=np.intp)
    inv[order] = group
    return xs[new], inv


@functools.lru_cache(maxsize=256)
def _eigen(key: bytes, n: int, max_condition: float
           ) -> tuple[ComplexArray, ComplexArray, ComplexArray] | None:
    """The balanced eigendecomposition ``M = (D V) diag(lam) (V^-1 D^-1)`` of the n x n matrix
    whose bytes are ``key``: ``(lam, D V, V^-1 D^-1)``, or None where it is not finite or the
    eigenvector matrix's condition number is not below ``max_condition``. Cached: the runs of
    a sweep or a continuation share their few piece matrices (the stiffness levels do not
    change with speed)."""
    # on use: a backlash sweep imports this module but never scipy.linalg (~0.13 s)
    from scipy.linalg import matrix_balance

    m = np.frombuffer(key, dtype=np.float64).reshape(n, n)
    try:
        # balance first: the states of a gear model differ by orders of magnitude (m vs m/s)
        b, (d, _) = matrix_balance(m, permute=False, separate=True)
        lam, v = np.linalg.eig(b)
        vi = np.linalg.inv(v)
    except (ValueError, np.linalg.LinAlgError):  # non-finite M: expm gives NaN, caught later
        return None
    cond = float(np.linalg.norm(v, 2) * np.linalg.norm(vi, 2))
    if not (np.isfinite(cond) and cond < max_condition):
        return None
    left, right = v * d[:, None], vi / d[None, :]  # D V, V^-1 D^-1
    for a in (lam, left, right):
        a.setflags(write=False)
    return lam, left, right


class _Exponential:
    """``expm(M s)`` for one constant matrix ``M`` and many ``s``, exact up to rounding."""

    def __init__(self, m: FloatArray, tol: float) -> None:
        self.m = m
        self.tol = tol
        self.n_expm = 0
        found = _eigen(m.tobytes(), m.shape[0], MAX_EIGEN_CONDITION)
        self.eigen = found is not None
        if found is not None:
            self.lam, self.left, self.right = found

    def __call__(self, s: FloatArray) -> FloatArray:
        """Stack of ``expm(M s_k)``, shape (len(s), n, n)."""
        s = np.asarray(s, dtype=float)
        if self.eigen:  # on the distinct s only (a uniform grid's steps repeat, bit for bit)
            su, inv = np.unique(s, return_inverse=True)
            ex = np.exp(self.lam[None, :] * su[:, None])
            return ((self.left[None, :, :] * ex[:, None, :]) @ self.right).real[inv]
        from scipy.linalg import expm

        su, inv = _unique_tol(s, self.tol)
        self.n_expm += su.size
        return expm(self.m[None, :, :] * su[:, None, None])[inv]

    def apply(self, s: FloatArray, z: FloatArray) -> FloatArray:
        """Rows ``expm(M s_k) z_k``, shape (len(s), n); O(len(s) n^2), no matrix stacks."""
        s = np.asarray(s, dtype=float)
        if self.eigen:
            w = (z @ self.right.T) * np.exp(self.lam[None, :] * s[:, None])
            return np.ascontiguousarray((w @ self.left.T).real)
        return np.einsum("kij,kj->ki", self(s), z)


class StepPropagator:
    """``z -> expm(M s) z`` for one constant matrix ``M``, on plain Python floats: the exact
    route one step at a time (the stepwise session of :mod:`gear_dyn.solvers.session`).

    A co-simulation master steps with a fixed communication step, and the stiffness is
    periodic: the piece durations ``s`` repeat (up to rounding of the times). Their matrices
    ``expm(M s)`` are computed once (``_Exponential``) for ``s``
    rounded to a grid of width ``q`` (a power of two with ``rho q <= 1e-6``, ``rho`` the
    spectral radius of ``M``), and the remainder ``d = s - s_grid`` (``|d| <= q / 2``) is
    applied through ``expm(M d) = I + M d + (M d)^2 / 2 + O((rho d)^3)``: the neglected term
    is below 1e-19 (times the eigenvector condition, < 1e3), far below rounding. Without a
    usable eigendecomposition every call takes the exact propagator as before.
    """

    MAX_CACHED = 4096

    def __init__(self, m: FloatArray, tol: float) -> None:
        self.ex = _Exponential(m, tol)
        n = m.shape[0]
        self.rows = [tuple(r) for r in m[:-1].tolist()]  # M z (the last row of M is zero)
        self.sq = [tuple(r[:-1]) for r in m[:-1, :].tolist()]  # M w for w with w[-1] = 0
        self.n = n
        rho = float(np.max(np.abs(self.ex.lam))) if self.ex.eigen else 0.0
        self.q = 2.0 ** math.floor(math.log2(1e-6 / rho)) if rho > 0 else 0.0
        self.cache: dict[int, list[tuple[float, ...]]] = {}

    def apply(self, s: float, z: list[float]) -> list[float]:
        """``expm(M s) z`` (``z`` augmented: its last entry is 1)."""
        q = self.q
        if not q:
            return self.ex.apply(np.array([s]), np.array(z)[None, :])[0].tolist()
        k = round(s / q)
        phi = self.cache.get(k)
        if phi is None:
            if len(self.cache) >= self.MAX_CACHED:
                self.cache.clear()
            phi = self.cache[k] = [tuple(r) for r in self.ex(np.array([k * q]))[0][:-1].tolist()]
        d = s - k * q
        if self.n == 3:  # two states (the single-DOF model): the same sums, unrolled
            x, v = z[0], z[1]
            if d:
                (a0, a1, a2), (b0, b1, b2) = self.rows
                w0, w1 = a0 * x + a1 * v + a2, b0 * x + b1 * v + b2  # M z
                h2 = 0.5 * d * d
                x, v = (x + d * w0 + h2 * (a0 * w0 + a1 * w1),
                        v + d * w1 + h2 * (b0 * w0 + b1 * w1))
            (p0, p1, p2), (r0, r1, r2) = phi
            return [p0 * x + p1 * v + p2, r0 * x + r1 * v + r2, 1.0]
        if d:
            w = [sum(map(operator.mul, r, z)) for r in self.rows]  # M z
            w2 = [sum(map(operator.mul, r, w)) for r in self.sq]  # M^2 z
            h2 = 0.5 * d * d
            z = [zi + d * wi + h2 * vi for zi, wi, vi in zip(z[:-1], w, w2, strict=True)] + [1.0]
        return [sum(map(operator.mul, r, z)) for r in phi] + [1.0]


def _distinct(pieces: list[tuple[float, float, FloatArray, FloatArray]]
              ) -> tuple[list[FloatArray], NDArray[np.intp], FloatArray, FloatArray]:
    """The distinct augmented matrices of ``pieces``, each piece's index into them, and the
    piece starts and ends (s). Pieces that share their ``A`` and ``g`` objects (as the models
    build them) are compared once."""
    keys: dict[bytes, int] = {}
    seen: dict[tuple[int, int], int] = {}
    mats: list[FloatArray] = []
    n_p = len(pieces)
    piece_id = np.empty(n_p, dtype=np.intp)
    starts = np.empty(n_p)
    ends = np.empty(n_p)
    for j, (ta, tb, a, g) in enumerate(pieces):
        u = seen.get((id(a), id(g)))
        if u is None:
            m = _augmented(np.asarray(a, float), np.asarray(g, float))
            u = keys.setdefault(m.tobytes(), len(mats))
            if u == len(mats):
                mats.append(m)
            seen[(id(a), id(g))] = u
        piece_id[j] = u
        starts[j], ends[j] = ta, tb
    return mats, piece_id, starts, ends


def propagate_pieces(
    pieces: list[tuple[float, float, FloatArray, FloatArray]], t_grid: FloatArray, y0: FloatArray
) -> tuple[FloatArray, dict[str, Any]]:
    """States on ``t_grid`` for ``y' = A y + g`` piecewise constant, exactly.

    Parameters
    ----------
    pieces : list of (ta, tb, A, g)
        Consecutive pieces covering ``[t_grid[0], t_grid[-1]]`` (times in s; ``A`` n x n in 1/s,
        ``g`` length n in state units per s).
    t_grid : ndarray
        Increasing output times in s; the first is the initial time.
    y0 : ndarray
        State at ``t_grid[0]``.

    Returns
    -------
    y : ndarray (n_states, n_t)
    stats : dict
        ``nfev`` = matrix exponentials evaluated by Pade (0 on the eigen route), ``n_segments``,
        ``n_distinct`` (distinct piece matrices), ``eigen`` (all pieces on the eigen route).
    """
    t_grid = np.asarray(t_grid, dtype=float)
    y = np.asarray(y0, dtype=float)
    n = y.size
    n_p = len(pieces)
    # rounding of the instants themselves (two ulps): on the Pade route, time offsets closer
    # than this share one exponential
    tol = 2 * float(np.spacing(max(abs(float(t_grid[0])), abs(float(t_grid[-1])))))
    mats, piece_id, starts, ends = _distinct(pieces)
    exps = [_Exponential(m, tol) for m in mats]
    # which piece each grid point belongs to (a point on a cut belongs to the later piece)
    owner = np.clip(np.searchsorted(starts, t_grid, side="right") - 1, 0, n_p - 1)
    tau = t_grid - starts[owner]
    # end-of-piece propagators: durations recur (same switching pattern every cycle)
    dur = ends - starts
    phi = np.empty((n_p, n + 1, n + 1))
    for u, ex in enumerate(exps):
        sel = piece_id == u
        phi[sel] = ex(dur[sel])
    # states at piece starts: one product per piece (the only sequential part, in the kernel)
    ys = np.ones((n_p, n + 1))
    ys[:, :n] = kernel.chain(phi[:, :n, :n], phi[:, :n, n], y)[:n_p]
    out = np.empty((n, t_grid.size))
    g_id = piece_id[owner]
    for u, ex in enumerate(exps):
        gsel = np.flatnonzero(g_id == u)
        out[:, gsel] = ex.apply(tau[gsel], ys[owner[gsel]])[:, :n].T
    stats = {
        "nfev": int(sum(e.n_expm for e in exps)), "njev": 0, "nlu": 0, "n_segments": n_p,
        "n_distinct": len(mats), "eigen": all(e.eigen for e in exps),
        "piece_maps": (phi[:, :n, :n], phi[:, :n, n], ends),
    }
    return out, stats


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
        ``nfev`` = Pade matrix exponentials evaluated, ``n_segments``, ``n_distinct``, ``eigen``.

    Raises
    ------
    InputError
        The model is not linear with piecewise-constant coefficients.
    SolverError
        Non-finite states (a diverging response).
    """
    del settings
    t_grid = np.asarray(t_grid, dtype=float)
    t0, t1 = float(t_grid[0]), float(t_grid[-1])
    s_per = _samples_per_period(model, t_grid)
    periodic = s_per > 0
    # one period of pieces where the step maps recur, else the whole span
    pieces = model.linear_segments(t0, float(t_grid[min(s_per, t_grid.size - 1)]) if periodic
                                   else t1)
    if pieces is None:
        raise InputError(
            "solver.method = 'exact' needs a linear model with piecewise-constant coefficients "
            "(piecewise-constant stiffness, no backlash, no transmission error); "
            "use DOP853 or LSODA"
        )
    y = np.array(model.initial_state() if y0 is None else y0, dtype=float)
    if periodic:
        out, stats = _propagate_periodic(pieces, t_grid, y, s_per)
        stats["n_segments"] = int(np.size(model.switching_times(t0, t1))) + 1
    else:
        out, stats = propagate_pieces(pieces, t_grid, y)
    if not np.all(np.isfinite(out)):
        raise SolverError("exact propagation produced non-finite states: the response diverges")
    f, h, ends = stats.pop("piece_maps")
    if getattr(model, "mesh_periodic", False):
        # the pieces of the first mesh period, where one of them ends on it: their product is
        # the one-period map (reused by the Floquet check)
        t_per = t0 + 1.0 / model.mesh_frequency
        k = int(np.searchsorted(ends, t_per - 1e-9 * (t_per - t0)))
        if k < ends.size and abs(ends[k] - t_per) <= 1e-9 * (t_per - t0):
            stats["step_maps"] = (f[: k + 1].copy(), h[: k + 1].copy())
    return out, stats


def _samples_per_period(model: Model, t_grid: FloatArray) -> int:
    """``S`` where ``model`` is mesh-periodic and ``t_grid`` is ``t0 + i T / S`` (``T`` the mesh
    period) to rounding, a few ulps of its end time; else 0. Only then do the step maps of the
    first period hold in every later one to rounding: a grid commensurate to 1e-9 only (enough
    for the ``periodic`` method's tolerance) would let the switching instants drift against it
    period after period."""
    if not (getattr(model, "mesh_periodic", False) and model.is_linear) or t_grid.size < 3:
        return 0
    f_m = model.mesh_frequency
    steps = 1.0 / (f_m * float(t_grid[1] - t_grid[0]))
    s_per = int(round(steps)) if np.isfinite(steps) else 0
    if s_per < 1:
        return 0
    t0 = float(t_grid[0])
    ulps = 8 * float(np.spacing(max(abs(t0), abs(float(t_grid[-1])))))
    return s_per if kernel.grid_error(t_grid, t0, 1.0 / (f_m * s_per)) <= ulps else 0


def _propagate_periodic(pieces: list[tuple[float, float, FloatArray, FloatArray]],
                        t_grid: FloatArray, y0: FloatArray, s_per: int
                        ) -> tuple[FloatArray, dict[str, Any]]:
    """:func:`propagate_pieces` on a uniform grid of ``s_per`` samples per mesh period, from
    ``pieces`` covering the first period (or the whole span, where shorter): the exact map of
    each grid step, the product of the exponentials of its parts between switching instants,
    is computed once and the kernel applies the maps of every later period
    (:func:`gear_dyn.solvers.kernel.fill_periodic`)."""
    n = y0.size
    s_used = min(s_per, t_grid.size - 1)
    grid = t_grid[: s_used + 1]
    tol = 2 * float(np.spacing(max(abs(float(t_grid[0])), abs(float(t_grid[-1])))))
    mats, piece_id, starts, ends = _distinct(pieces)
    exps = [_Exponential(m, tol) for m in mats]
    # the steps cut at the switching instants: each part's step and piece
    edges = np.unique(np.concatenate([grid, starts[1:]]))
    left, dur = edges[:-1], np.diff(edges)
    owner = np.clip(np.searchsorted(grid, left, side="right") - 1, 0, s_used - 1)
    mid = piece_id[np.clip(np.searchsorted(starts, left, side="right") - 1, 0, starts.size - 1)]
    parts = np.empty((left.size, n + 1, n + 1))
    phi = np.empty((starts.size, n + 1, n + 1))  # the pieces' own maps (the Floquet check's)
    for u, ex in enumerate(exps):
        sel = mid == u
        parts[sel] = ex(dur[sel])
        psel = piece_id == u
        phi[psel] = ex((ends - starts)[psel])
    total = kernel.compose(parts, owner, s_used)
    q, r = kernel.products(total[:, :n, :n], total[:, :n, n])
    out, _finite = kernel.fill_periodic(q, r, y0, t_grid.size, s_per)
    stats = {
        "nfev": int(sum(e.n_expm for e in exps)), "njev": 0, "nlu": 0,
        "n_distinct": len(mats), "eigen": all(e.eigen for e in exps),
        "piece_maps": (phi[:, :n, :n], phi[:, :n, n], ends),
    }
    return out, stats


def exact_applies(model: Model) -> bool:
    """True when ``model`` is linear with piecewise-constant coefficients (method exact works)."""
    return model.linear_segments(0.0, 1.0 / model.mesh_frequency) is not None

