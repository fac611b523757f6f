"""The shooting equations of a period-n orbit with the parameter as an unknown, their Jacobian,
the Newton corrector and the branch tangent (Seydel 2010, ch. 4 and 7; Doedel's AUTO notes).

Unknowns, scaled: ``z = (x / x_s, v / v_s, p / p_ref)``. Equations: ``G(z) = (P(y, p) - y) /
y_s = 0`` (two equations, three unknowns: a curve of solutions, the branch), closed by one more
linear equation ``r . z = rhs``: the pseudo-arclength condition ``t . (z - z_pred) = 0`` (Keller
1977) or, to stop at a given parameter value, ``p = p_end``.

The Jacobian ``[M - I | dP/dp]`` (scaled): ``M`` exact or variational (:mod:`.orbit`). On the
exact route, for a family whose models differ only in the mesh frequency, proportional to the
parameter (a speed family: ``family.mesh_frequency_only``), the parameter column is exact too,
from the same walk as ``M``: ``dP/dp = (dP/df_m) f_m / p`` with ``dP/df_m`` the walk's
mesh-frequency derivative (:meth:`gear_dyn.solvers.contact_exact.Walk.mesh_rate`, the time
scaling ``tau = f_m t`` written as moving stiffness switches and end time), exact to rounding
(:data:`RATE_ROUNDING` per piece, its stated error): the corrector is Newton's method with the
exact Jacobian at every iterate, and every converged point's tangent is exact, at no extra map.
Otherwise the parameter derivative inside the corrector by the secant condition of each Newton step
(a finite difference along the step, whose change from one step to the next is its error estimate).
At a converged point whose secant columns have not settled, on the exact route (a map exact to
rounding) by one more map: the forward difference over ``p + h_f``, ``h_f = FORWARD_STEP_RATIO
fd_step |p|`` (truncation ``h_f |d2P/dp2| / 2``, rounding O(eps / h_f); Dennis and Schnabel 1996,
sec. 5.4), whose disagreement with the corrector's last secant column (first order in the longer
Newton step) plus its rounding is kept as an upper estimate of its error. Where no secant column
was taken, or on the variational route (a map accurate to ``rtol`` only), by the central difference
over ``p +- h``, ``h = fd_step |p|`` (two maps; truncation O(h^2)), whose one-sided differences'
disagreement is kept as an upper estimate of its error.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.continuation.orbit import map_only, period_map
from gear_dyn.analysis.newton import NewtonSettings
from gear_dyn.errors import InputError, SolverError
from gear_dyn.models.base import MeshModel
from gear_dyn.solvers.contact_exact import Walk

FloatArray = NDArray[np.float64]
#: two successive secant parameter columns that agree to this (relative) are taken as the
#: parameter derivative at a converged point, without the central difference
SECANT_AGREEMENT = 1e-4
#: a secant update is made only where the parameter's share of the residual change,
#: ``|col| |dz_p|``, exceeds this times ``1 + max|z|``: the map rounds the scaled residual to
#: about 1e-15 of that, so the column's own rounding error stays below ~1e-5 relative. A
#: Newton step at the rounding level (a corrector run to ``newton.tolerance`` near 1e-14) would
#: otherwise replace a good column by noise (a difference quotient over a step near the
#: function's noise level; Dennis and Schnabel 1996, sec. 5.4).
SECANT_FLOOR = 1e-10
#: the forward difference's step as a fraction of the central difference's ``fd_step |p|``:
#: its truncation error is first order in the step, the central one's second, so the same
#: accuracy needs a shorter step (near ``sqrt(eps)`` relative rather than ``eps**(1/3)``):
#: 1e-8 relative at the default ``fd_step``, about 1e-7 relative error on the packaged
#: backlash scene's resonance (against a Richardson-extrapolated central difference)
FORWARD_STEP_RATIO = 1e-3
#: relative rounding of the scaled map (its residual is rounded to about this times
#: ``1 + max|z|``): the rounding part of a forward difference's error estimate
MAP_ROUNDING = 1e-15
#: stated relative error of the exact parameter column per closed-form piece of its walk:
#: rounding, as the exact flow's own (:func:`gear_dyn.solvers.contact_exact.rounding_bound`,
#: 1000 eps per piece); measured within 2e-8 relative of a central difference, whose own
#: truncation and rounding errors that is (tests/solvers/test_mesh_rate.py)
RATE_ROUNDING = 1000 * float(np.finfo(float).eps)
_EYE2 = np.eye(2)
_EYE2.flags.writeable = False


@dataclass(frozen=True, eq=False)
class Evaluation:
    """The shooting equations at one ``z``.

    Attributes
    ----------
    z : ndarray (3,)
        Scaled unknowns.
    g : ndarray (2,)
        Scaled residual ``(P(y) - y) / y_s``.
    jac : ndarray (2, 3)
        ``dG/dz`` (scaled).
    monodromy : ndarray (2, 2)
        ``M = dP/dy`` (SI).
    dp_error : float
        Upper estimate of the relative error of the parameter derivative (nan where the
        column is a chord taken from another point).
    model : MeshModel
        The model at this parameter value.
    walked : Walk or None
        On the exact route, the walk of the map (:func:`.orbit.period_map`), for the orbit's
        shape; None on the variational route.
    """

    z: FloatArray
    g: FloatArray
    jac: FloatArray
    monodromy: FloatArray
    dp_error: float
    model: MeshModel
    walked: Walk | None = None


class Shooting:
    """The shooting equations of period-``periods`` orbits of ``family`` (see the module).

    Parameters
    ----------
    family : callable
        ``value -> MeshModel`` (SI value of the parameter).
    periods : int
        Mesh periods n of the orbits.
    route : str
        ``exact`` or ``variational``.
    scale : ndarray (2,)
        State scales (m, m/s).
    p_ref : float
        Parameter scale (> 0, SI).
    rtol, fd_step : float
        Variational tolerance; relative step of the parameter difference.
    mesh_frequency_only : bool
        The family's models differ only in the mesh frequency, proportional to the
        parameter (a speed family): on the exact route the parameter column is then the
        walk's exact one (see the module). Default: the family's own
        ``mesh_frequency_only`` attribute (False where it has none).

    Attributes
    ----------
    exact_column : bool
        The parameter column is exact (the exact route and ``mesh_frequency_only``).
    """

    def __init__(self, family: Callable[[float], MeshModel], periods: int, route: str,
                 scale: FloatArray, p_ref: float, rtol: float, fd_step: float,
                 mesh_frequency_only: bool | None = None) -> None:
        self.family, self.periods, self.route = family, int(periods), route
        self.scale = np.asarray(scale, dtype=float)
        self.p_ref, self.rtol, self.fd_step = float(p_ref), float(rtol), float(fd_step)
        if mesh_frequency_only is None:
            mesh_frequency_only = bool(getattr(family, "mesh_frequency_only", False))
        self.mesh_frequency_only = bool(mesh_frequency_only)
        self.exact_column = self.mesh_frequency_only and route == "exact"
        self.n_maps = 0  #: n-period maps computed (cost counter)

    def with_periods(self, periods: int) -> Shooting:
        """The same problem for period-``periods`` orbits."""
        return Shooting(self.family, periods, self.route, self.scale, self.p_ref, self.rtol,
                        self.fd_step, self.mesh_frequency_only)

    def state(self, z: FloatArray) -> FloatArray:
        """SI state of scaled unknowns."""
        return np.asarray(z[:2] * self.scale, dtype=float)

    def param(self, z: FloatArray) -> float:
        """SI parameter value of scaled unknowns."""
        return float(z[2] * self.p_ref)

    def scaled(self, y: FloatArray, p: float) -> FloatArray:
        """Scaled unknowns of an SI state and parameter."""
        return np.array([y[0] / self.scale[0], y[1] / self.scale[1], p / self.p_ref])

    def residual_only(self, z: FloatArray) -> FloatArray:
        """Scaled ``G(z)`` alone (no sensitivity)."""
        y, p = self.state(z), self.param(z)
        self.n_maps += 1
        return (map_only(self.family(p), y, self.periods, self.route, self.rtol) - y) / self.scale

    def evaluate(self, z: FloatArray, dp_col: FloatArray | None = None) -> Evaluation:
        """The residual, Jacobian and monodromy matrix at ``z``.

        ``dp_col``: the scaled parameter column of the Jacobian to use (a chord: e.g. that of
        the step's start point); None computes it here by the central difference. With
        ``exact_column`` the column is the walk's exact one and ``dp_col`` is not used.

        Raises
        ------
        SolverError
            Integration failure (from the map).
        InputError
            The parameter left the family's valid range.
        """
        y, p = self.state(z), self.param(z)
        model = self.family(p)
        yt, mono, walked = period_map(model, y, self.periods, self.route, self.rtol,
                                      self.exact_column)
        self.n_maps += 1
        s = self.scale
        jac = np.empty((2, 3))
        jac[:, :2] = (mono - _EYE2) * s[None, :] / s[:, None]
        dp_err = float("nan")
        if self.exact_column and walked is not None:
            # dP/dp = dP/df_m * df_m/dp, f_m proportional to p
            dp_col = walked.mesh_rate() * (float(model.mesh_frequency) / p) * self.p_ref / s
            dp_err = RATE_ROUNDING * (walked.n_segments + 1)
        elif dp_col is None:
            dp_col, dp_err = self._dp_column(y, p, yt)
        jac[:, 2] = dp_col
        return Evaluation(np.array(z, dtype=float), (yt - y) / s, jac, mono, dp_err, model,
                          walked)

    def _dp_column(self, y: FloatArray, p: float, yt: FloatArray,
                   ref: FloatArray | None = None) -> tuple[FloatArray, float]:
        """Scaled ``dP/dp`` and an upper estimate of its relative error.

        ``ref``: a secant column of the corrector at this point: on the exact route (a map
        exact to rounding) the forward difference (one map), its error bounded by its
        disagreement with that column plus its rounding; None, or the variational route (a
        map accurate to ``rtol``, too coarse for the forward difference's short step): the
        central difference (two maps).
        """
        h = self.fd_step * max(abs(p), 1e-3 * self.p_ref)
        if ref is not None and self.route == "exact":
            h *= FORWARD_STEP_RATIO
            y_plus = map_only(self.family(p + h), y, self.periods, self.route, self.rtol)
            self.n_maps += 1
            col = (y_plus - yt) / h * self.p_ref / self.scale
            # the secant column's error (first order in the corrector's Newton step, or its
            # rounding at SECANT_FLOOR) exceeds the forward difference's: their disagreement
            # bounds the latter's truncation error; plus its rounding
            hs = h / self.p_ref  # the step, scaled
            size = max(float(np.max(np.abs(col))), 1e-300)
            z_size = 1.0 + float(np.max(np.abs(np.append(y / self.scale, p / self.p_ref))))
            err = (float(np.max(np.abs(col - ref))) + 2 * MAP_ROUNDING * z_size / hs) / size
            return col, err
        y_plus = map_only(self.family(p + h), y, self.periods, self.route, self.rtol)
        y_minus = map_only(self.family(p - h), y, self.periods, self.route, self.rtol)
        self.n_maps += 2
        dp = (y_plus - y_minus) / (2 * h)
        fwd, bwd = (y_plus - yt) / h, (yt - y_minus) / h
        dp_err = float(np.max(np.abs(fwd - bwd)) / max(float(np.max(np.abs(dp))), 1e-300))
        return dp * self.p_ref / self.scale, dp_err

    def refresh(self, ev: Evaluation, ref: FloatArray | None = None) -> Evaluation:
        """``ev`` with its parameter column computed at its own point (for the tangent).

        ``ref``: a secant column of the corrector at ``ev`` (the forward difference, one map);
        None: the central difference (two maps).
        """
        if not np.isnan(ev.dp_error):
            return ev
        y, p = self.state(ev.z), self.param(ev.z)
        col, err = self._dp_column(y, p, y + ev.g * self.scale, ref)
        return replace(ev, jac=np.column_stack([ev.jac[:, :2], col]), dp_error=err)

    def _settled_column(self, ev: Evaluation, secants: list[FloatArray],
                        last: FloatArray | None = None) -> Evaluation | None:
        """``ev`` with a parameter column good for the tangent: the last secant column where
        the last two agree to :data:`SECANT_AGREEMENT` (their difference is its error
        estimate), else the forward difference checked against ``last`` (the corrector's last
        secant column), else the central difference (:meth:`refresh`)."""
        if len(secants) >= 2:
            a, b = secants[-1], secants[-2]
            err = float(np.max(np.abs(a - b)) / max(float(np.max(np.abs(a))), 1e-300))
            if err <= SECANT_AGREEMENT:
                return replace(ev, dp_error=err)
        try:
            return self.refresh(ev, last)
        except (SolverError, ValueError):
            return None

    def correct(self, z0: FloatArray, row: FloatArray, rhs: float, newton: NewtonSettings,
                dp_col: FloatArray | None = None, fresh: bool = True
                ) -> tuple[Evaluation, int] | None:
        """Newton's method on ``G(z) = 0``, ``row . z = rhs`` from ``z0``, at most
        ``newton.max_iter`` iterations.

        Converged when the scaled residual of all three equations is below
        ``newton.tolerance`` (``tol``) at an iterate; the returned evaluation is that
        iterate's. (The shooting residual bounds the distance to the orbit by
        ``tol / (1 - |mu|)`` in scaled units, mu the multiplier nearest 1.)
        With ``exact_column`` every iterate has its exact Jacobian (``dp_col`` and
        ``fresh`` are not used). Otherwise, with ``dp_col`` (the parameter column at the
        step's start) the iterations skip the
        difference quotient and correct the column by the secant condition of each step;
        ``fresh`` then makes sure the converged point's column is good for the tangent
        (the last secant column if it agrees with the one before, else the central
        difference).

        Returns
        -------
        (Evaluation, iterations) or None
            None when Newton does not converge in ``max_iter`` iterations, diverges, meets a
            singular system or the map fails (a chattering contact, a parameter out of range).

        Raises
        ------
        InputError
            ``newton.tolerance`` is None (the scaled residual has no map tolerance to follow).
        """
        if newton.tolerance is None:
            raise InputError("newton.tolerance = None: the corrector needs a scaled residual "
                             "to stop at, valid range 1e-14 <= x <= 0.0001")
        tol, max_iter = float(newton.tolerance), newton.max_iter
        if self.exact_column:
            dp_col, fresh = None, False  # the column of every evaluation is exact
        z = np.array(z0, dtype=float)
        step_prev = math.inf
        prev: tuple[Evaluation, FloatArray] | None = None
        secants: list[FloatArray] = []  # the column after each secant update, in order
        last: FloatArray | None = None  # the last of them
        for it in range(1, max_iter + 1):
            try:
                ev = self.evaluate(z, dp_col)
            except (SolverError, ValueError):
                return None
            updated = False
            if dp_col is not None and prev is not None:
                new = _secant_column(prev[0], ev, prev[1])
                if new is not None:
                    dp_col, updated = new, True
                    secants.append(new)
                    last = new
                    ev.jac[:, 2] = dp_col
            g0, g1 = ev.g.tolist()
            f = np.array([g0, g1, float(row @ z) - rhs])
            if max(abs(g0), abs(g1), abs(float(f[2]))) <= tol:
                if not fresh:
                    return ev, it
                settled = self._settled_column(ev, secants if updated else [], last)
                return None if settled is None else (settled, it)
            dz = solve3(np.vstack([ev.jac, row]), -f)
            if dz is None:
                return None
            step = max(map(abs, dz.tolist()))
            if not math.isfinite(step):
                return None
            if it >= 3 and step > 0.5 * step_prev:
                return None  # not contracting: outside Newton's region
            step_prev = step
            prev = (ev, dz)
            z = z + dz
        return None


def _secant_column(ev0: Evaluation, ev1: Evaluation, dz: FloatArray) -> FloatArray | None:
    """The parameter column from the secant condition of the last Newton step (Broyden's
    update restricted to that column; the state columns are exact):
    ``g1 - g0 = A_y dz_y + col dz_p``, ``A_y`` averaged over the two points (second order in
    the step). None when the step hardly moved the parameter, or so little that the
    residual's rounding would dominate the column (:data:`SECANT_FLOOR`)."""
    dzp = float(dz[2])
    if abs(dzp) <= 1e-3 * float(np.max(np.abs(dz))):
        return None
    size = float(np.max(np.abs(ev0.jac[:, 2])))
    if abs(dzp) * size <= SECANT_FLOOR * (1.0 + float(np.max(np.abs(ev0.z)))):
        return None  # the step is at the rounding level of the residual: keep the column
    a_y = 0.5 * (ev0.jac[:, :2] + ev1.jac[:, :2])
    return np.asarray((ev1.g - ev0.g - a_y @ dz[:2]) / dzp, dtype=float)


def solve3(a: FloatArray, b: FloatArray) -> FloatArray | None:
    """``a^-1 b`` for a 3 x 3 ``a``: Gaussian elimination with partial pivoting (Golub & Van
    Loan 2013, sec. 3.4), unrolled on Python floats (the corrector's system, a few times per
    point: a fraction of the time of ``numpy.linalg.solve`` on one so small). None where ``a``
    is singular (a zero pivot) or not finite."""
    r0, r1, r2 = (row + [bi] for row, bi in zip(a.tolist(), b.tolist(), strict=True))
    if abs(r1[0]) > abs(r0[0]):
        r0, r1 = r1, r0
    if abs(r2[0]) > abs(r0[0]):
        r0, r2 = r2, r0
    p = r0[0]
    if p == 0.0 or not math.isfinite(p):
        return None
    f1, f2 = r1[0] / p, r2[0] / p
    r1 = [0.0, r1[1] - f1 * r0[1], r1[2] - f1 * r0[2], r1[3] - f1 * r0[3]]
    r2 = [0.0, r2[1] - f2 * r0[1], r2[2] - f2 * r0[2], r2[3] - f2 * r0[3]]
    if abs(r2[1]) > abs(r1[1]):
        r1, r2 = r2, r1
    p = r1[1]
    if p == 0.0 or not math.isfinite(p):
        return None
    f2 = r2[1] / p
    c22, c23 = r2[2] - f2 * r1[2], r2[3] - f2 * r1[3]
    if c22 == 0.0 or not math.isfinite(c22):
        return None
    x2 = c23 / c22
    x1 = (r1[3] - r1[2] * x2) / r1[1]
    x0 = (r0[3] - r0[1] * x1 - r0[2] * x2) / r0[0]
    return np.array([x0, x1, x2])


def tangent(jac: FloatArray) -> FloatArray:
    """Unit null vector of the 2 x 3 Jacobian ``[M - I | dP/dp]`` (scaled): the branch
    direction (the cross product of its rows; its sign is the caller's choice)."""
    (a0, a1, a2), (b0, b1, b2) = jac.tolist()
    t = np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])
    norm = math.sqrt(float(t @ t))
    if norm == 0.0 or not math.isfinite(norm):
        raise SolverError("the branch tangent is undefined (Jacobian of rank < 2): a "
                          "singular point of the shooting equations")
    return np.asarray(t / norm, dtype=float)
