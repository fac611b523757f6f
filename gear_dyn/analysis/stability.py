"""Periodic steady state, monodromy matrix and Floquet multipliers of the mesh models.

Linear models: the affine one-period map ``y(T) = Phi y(0) + q``, its fixed point and the
eigenvalues of ``Phi``; models with backlash: shooting, Newton's method on ``P(y0) - y0 = 0``
(:func:`gear_dyn.solvers.sensitivity.integrate_with_sensitivity` gives
``Phi = dP/dy0``). docs/sweep.md, "How the steady
state is found", gives the routes; docs/solvers.md the checks and their tests. Stability charts
are in :mod:`gear_dyn.analysis.chart`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, cast, overload

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError, SolverError, check_range
from gear_dyn.models.base import MeshModel, Model
from gear_dyn.solvers.exact import propagate_pieces
from gear_dyn.solvers.ode import flow
from gear_dyn.solvers.periodic import step_products
from gear_dyn.solvers.sensitivity import integrate_with_sensitivity

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: a multiplier modulus above ``1 + UNIT_CIRCLE_TOL`` counts as unstable. Undamped (conservative)
#: systems have multipliers on the unit circle; rounding and the integrator's tolerance move them
#: off it by far less than this.
UNIT_CIRCLE_TOL = 1e-6


@overload
def floquet_stable(spectral_radius: float) -> bool: ...
@overload
def floquet_stable(spectral_radius: FloatArray) -> NDArray[np.bool_]: ...
def floquet_stable(spectral_radius: float | FloatArray) -> bool | NDArray[np.bool_]:
    """The stability rule of every orbit and every linear system here: all Floquet multipliers
    inside the unit circle, i.e. the spectral radius ``rho = max |mu|`` at most
    ``1 + UNIT_CIRCLE_TOL`` (a conservative system's multipliers on the circle count as
    stable; NaN, no multipliers, is not stable). Vectorised: an array of radii gives an
    array of verdicts.

    Examples
    --------
    >>> floquet_stable(1.0 + 1e-9), floquet_stable(1.01), floquet_stable(float("nan"))
    (True, False, False)
    """
    verdict = np.asarray(spectral_radius, dtype=float) <= 1.0 + UNIT_CIRCLE_TOL
    return bool(verdict) if verdict.ndim == 0 else verdict


#: contact states as the letters of a contact pattern: drive flank, gap (teeth apart), back flank
CONTACT_LETTERS = {1: "D", 0: "G", -1: "B"}


def contact_states(model: Model, t: FloatArray, y: FloatArray,
                   force: FloatArray | None = None) -> NDArray[np.int64]:
    """The contact state at each sample: 1 on the drive flank, 0 with the teeth apart, -1 on the
    back flank. The one rule behind every contact share and pattern here (sweeps, runs,
    continuation).

    With backlash ``b`` (a mesh-periodic model): the flank separation ``u = x - e(t)``, the
    state ``x = y[0]`` less the transmission error, is drive contact where ``u > b``, a gap
    where ``|u| <= b`` and back contact where ``u < -b``. Without backlash the model keeps the
    teeth in contact; a negative mesh force marks where they would part (0), else 1.

    Parameters
    ----------
    model : Model
    t : ndarray (n,)
        Times in s.
    y : ndarray (n_states, n)
        States on ``t``, SI units.
    force : ndarray (n,) or None
        Mesh force on ``t`` in N, used without backlash; None: ``model.outputs``.

    Returns
    -------
    ndarray of int (n,)

    Examples
    --------
    >>> from gear_dyn import SDOFModel, rectangular_stiffness
    >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
    ...               backlash=1e-3)
    >>> contact_states(m, np.zeros(3), np.array([[2e-3, 0.0, -2e-3], [0.0, 0.0, 0.0]]))
    array([ 1,  0, -1])
    """
    if model.mesh_periodic and model.backlash is not None:
        mesh = cast(MeshModel, model)
        u = np.asarray(y[0], dtype=float)
        if mesh.transmission_error is not None:
            u = u - np.asarray(mesh.transmission_error.value(mesh.phase(t)), dtype=float)
        b = float(mesh.backlash or 0.0)
        return np.where(u > b, 1, np.where(u < -b, -1, 0)).astype(np.int64)
    f = model.outputs(t, y)["mesh_force"] if force is None else force
    return np.where(np.asarray(f) < 0, 0, 1).astype(np.int64)


def contact_shares(states: NDArray[np.int64], durations: FloatArray | None = None,
                   span: float | None = None) -> tuple[float, float]:
    """``(separation, back)``: the shares of time with the teeth apart and on the back flank.

    Parameters
    ----------
    states : ndarray of int
        :func:`contact_states`: of samples equally spaced over whole periods, or one per
        spell between contact changes.
    durations : ndarray or None
        Durations of the spells in s; None: the samples count equally.
    span : float or None
        Time the spells cover in s (default: the sum of ``durations``).

    Examples
    --------
    >>> contact_shares(np.array([1, 0, 0, -1]))
    (0.5, 0.25)
    >>> contact_shares(np.array([1, 0, 1]), np.array([0.5, 0.25, 0.25]), span=1.0)
    (0.25, 0.0)
    """
    if durations is None:
        return float(np.mean(states == 0)), float(np.mean(states == -1))
    total = float(np.sum(durations)) if span is None else span
    return (float(np.sum(durations[states == 0]) / total),
            float(np.sum(durations[states == -1]) / total))


def contact_pattern(states: NDArray[np.int64]) -> str:
    """The contact pattern of states in time order, one letter per spell
    (``CONTACT_LETTERS``), e.g. ``DGD``.

    >>> contact_pattern(np.array([1, 1, 0, 0, 1]))
    'DGD'
    """
    keep = np.concatenate([[True], states[1:] != states[:-1]])
    return "".join(CONTACT_LETTERS[int(s)] for s in states[keep])


@dataclass(frozen=True)
class OrbitShape:
    """What an orbit looks like over its n mesh periods (part of :class:`PeriodicSolution`;
    a sweep row's orbit: over its least period, from the sweep's samples; a sweep row without
    an orbit has one of its run's window).

    Attributes
    ----------
    pattern : str
        Contact pattern in time order from t = 0, one letter per spell (``D`` drive flank,
        ``G`` gap, ``B`` back flank), e.g. ``DGD``.
    separation, back : float
        Shares of the n periods with the teeth apart and on the back flank (-).
    dte_rms, dte_ptp, dte_mean : float
        Standard deviation, peak-to-peak and mean of the DTE over the orbit (m).
    """

    pattern: str
    separation: float
    back: float
    dte_rms: float
    dte_ptp: float
    dte_mean: float

    @classmethod
    def of_samples(cls, states: NDArray[np.int64], dte: FloatArray) -> OrbitShape:
        """The shape from samples equally spaced over whole periods (the end excluded): their
        contact states (:func:`contact_states`) and DTE (m)."""
        sep, back = contact_shares(states)
        return cls(contact_pattern(states), sep, back, float(np.std(dte)), float(np.ptp(dte)),
                   float(np.mean(dte)))


@dataclass(frozen=True, eq=False)
class PeriodicSolution:
    """A periodic orbit of a mesh model: the one orbit type of shooting, sweeps, continuation
    (:class:`~gear_dyn.analysis.continuation.branch.OrbitPoint` adds a branch's data to one)
    and motion classification (:class:`~gear_dyn.analysis.motion.classify.Motion` holds one).

    Parameters
    ----------
    y0 : ndarray
        State on the orbit at t = 0 (mesh phase ``model.phase0``), SI units.
    period : float
        Period of the orbit in s: ``periods`` mesh periods, ``periods / f_m``.
    monodromy : ndarray (n, n)
        d y(period) / d y(0) along the orbit.
    multipliers : ndarray of complex
        Floquet multipliers (eigenvalues of the monodromy matrix).
    converged : bool
        The orbit was found (always True for linear models).
    iterations : int
        Newton iterations (0 for linear models: one direct solve).
    how : str
        ``expm`` (exact product), ``magnus`` (Magnus step maps, a sweep's linear block),
        ``variational`` (solve_ivp over one period), ``shooting`` or ``continuation`` (a
        corrector's point).
    residual : float
        Final closing error: relative, ``max_i |P(y0)_i - y0_i| / scale_i``, for shooting
        (0 for linear models); the scaled residual of the shooting equations for
        ``continuation``.
    periods : int
        Mesh periods n of the orbit (period-n).
    shape : OrbitShape or None
        Contact pattern, contact shares and DTE measures over the orbit, where computed.

    Attributes
    ----------
    spectral_radius : float
        Largest multiplier modulus.
    stable : bool
        Converged and :func:`floquet_stable`.
    separation, back : float
        Contact shares of ``shape`` (NaN without one).
    """

    y0: FloatArray
    period: float
    monodromy: FloatArray
    multipliers: ComplexArray
    converged: bool
    iterations: int
    how: str
    residual: float = 0.0
    periods: int = 1
    shape: OrbitShape | None = None

    @property
    def spectral_radius(self) -> float:
        """Largest Floquet multiplier modulus."""
        return float(np.max(np.abs(self.multipliers)))

    def spectral_radius_over(self, periods: int) -> float:
        """Largest multiplier modulus of the map over ``periods`` mesh periods, a divisor of
        ``self.periods`` after which the orbit already repeats (its least period): the
        multipliers of the n-period map are those of the d-period map to the power n / d.

        Raises
        ------
        InputError
            ``periods`` does not divide the orbit's.
        """
        if periods == self.periods:
            return self.spectral_radius
        if periods < 1 or self.periods % periods:
            raise InputError(f"periods = {periods}: must divide the orbit's {self.periods} "
                             "mesh periods")
        return self.spectral_radius ** (periods / self.periods)

    @property
    def separation(self) -> float:
        """Share of the orbit with the teeth apart (NaN where no ``shape`` was computed)."""
        return math.nan if self.shape is None else self.shape.separation

    @property
    def back(self) -> float:
        """Share of the orbit on the back flank (NaN where no ``shape`` was computed)."""
        return math.nan if self.shape is None else self.shape.back

    @property
    def stable(self) -> bool:
        """Converged, with all multipliers inside the unit circle (:func:`floquet_stable`)."""
        return self.converged and floquet_stable(self.spectral_radius)


def _require_sdof(model: Any) -> MeshModel:
    if not (isinstance(model, MeshModel) and model.mesh_periodic):
        raise InputError(
            f"the periodic steady state needs a model periodic in the mesh period (sdof); got "
            f"{type(model).__name__}: use the transient method instead"
        )
    return model


def is_linear_periodic(model: Model) -> bool:
    """Whether ``model`` is linear and mesh-periodic (Floquet multipliers apply)."""
    return bool(model.mesh_periodic and model.is_linear)


#: earlier name of :func:`is_linear_periodic`
is_linear = is_linear_periodic


# ------------------------------------------------------------------ linear one-period map
def one_period_map(model: MeshModel, rtol: float = 1e-10) -> tuple[FloatArray, FloatArray, str]:
    """The affine one-period map ``y(T) = Phi y(0) + q`` of a linear single-DOF model.

    Parameters
    ----------
    model : MeshModel
        Without backlash.
    rtol : float
        Relative tolerance of the variational integration (unused where the stiffness is
        piecewise constant: that path is exact).

    Returns
    -------
    phi : ndarray (2, 2)
        Monodromy matrix (dimensionless / s / 1/s entries for [x, v]).
    q : ndarray (2,)
        Response after one period from rest at zero ([m, m/s]).
    how : str
        ``expm`` or ``variational``.

    Raises
    ------
    InputError
        Not a linear single-DOF model.
    SolverError
        The integration failed.
    """
    model = _require_sdof(model)
    if model.backlash is not None:
        raise InputError("one_period_map: the model has backlash (nonlinear); use shoot()")
    period = 1.0 / model.mesh_frequency
    segments = model.linear_segments(0.0, period)
    if segments is not None:  # the exact propagator's piece maps, composed
        _, stats = propagate_pieces(segments, np.array([0.0, period]),
                                    np.zeros(len(model.state_labels)))
        f, h, _ends = stats["piece_maps"]
        return (*period_map(f, h), "expm")
    # from rest at zero: y(T) = q, and d y(T) / d y(0) = Phi
    q, phi = integrate_with_sensitivity(model, np.zeros(len(model.state_labels)), period, rtol,
                                        route="variational")
    return phi, q, "variational"


def period_map(f: FloatArray, h: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The one-period map ``(Phi, q)`` composed of the step maps ``y_{j+1} = f[j] y_j + h[j]``
    of one mesh period (e.g. ``Result.step_maps`` of a ``periodic`` run)."""
    q, r = step_products(f, h)
    return q[-1], r[-1]


def flow_on_grid(model: MeshModel, y0: FloatArray, t_grid: FloatArray, rtol: float = 1e-8,
                 atol: FloatArray | float | None = None) -> FloatArray:
    """States of a single-DOF model on ``t_grid`` from ``y(t_grid[0]) = y0`` (DOP853).

    The solvers' solve_ivp driver (:func:`gear_dyn.solvers.ode.flow`: cut at the switching
    instants, restarted at contact changes, dense output on the grid), with the stiffness
    evaluated once per piece where it is piecewise constant: several times faster for sweeps.

    Parameters
    ----------
    model : MeshModel
    y0 : ndarray
        Initial state [m, m/s].
    t_grid : ndarray
        Increasing output times in s.
    rtol : float
        Relative tolerance.
    atol : float, ndarray or None
        Absolute tolerance; None: ``rtol * model.state_scale``.

    Returns
    -------
    ndarray (2, n_t)

    Raises
    ------
    SolverError
        Integration failure or non-finite states.
    """
    return flow(_require_sdof(model), y0, t_grid, rtol=rtol, atol=atol)[0]


def floquet_multipliers(model: MeshModel, rtol: float = 1e-10) -> ComplexArray:
    """Floquet multipliers of a linear single-DOF model (eigenvalues of its monodromy matrix).

    A multiplier with modulus > 1 means parametric instability. For a model with backlash use
    :func:`periodic_steady_state` (the multipliers belong to an orbit).

    Raises
    ------
    InputError
        Not a linear single-DOF model.
    """
    phi, _q, _how = one_period_map(model, rtol)
    return np.linalg.eigvals(phi).astype(np.complex128)


# ------------------------------------------------------------------ periodic steady state
def periodic_steady_state(
    model: MeshModel, y_guess: FloatArray | None = None, rtol: float = 1e-10,
    max_iter: int = 15,
) -> PeriodicSolution:
    """The periodic orbit of a single-DOF model, found directly.

    Linear models: one solve ``(I - Phi) y0 = q``. Models with backlash: shooting from
    ``y_guess`` (default: the static deflection).

    Parameters
    ----------
    model : MeshModel
    y_guess : ndarray or None
        Starting state for shooting (e.g. the orbit at the previous speed of a sweep).
    rtol : float
        Relative tolerance of the one-period integration (1e-13..1e-3).
    max_iter : int
        Newton iterations for shooting.

    Returns
    -------
    PeriodicSolution
        For linear models ``converged`` is True even when the orbit is unstable (check
        ``stable``): the orbit exists but the response runs away from it.

    Raises
    ------
    InputError
        Not a single-DOF model, or a bad tolerance.
    SolverError
        A multiplier equal to 1 (no isolated periodic orbit) or an integration failure.
    """
    model = _require_sdof(model)
    check_range("rtol", rtol, "", low=1e-13, high=1e-3)
    period = 1.0 / model.mesh_frequency
    if model.backlash is None:
        phi, q, how = one_period_map(model, rtol)
        n = q.size
        lhs = np.eye(n) - phi
        if np.linalg.cond(lhs) > 1e14:
            raise SolverError("the monodromy matrix has a multiplier at 1: no isolated periodic "
                              "steady state (undamped resonance?)")
        y0 = np.asarray(np.linalg.solve(lhs, q), dtype=np.float64)
        mult = np.linalg.eigvals(phi).astype(np.complex128)
        return PeriodicSolution(y0, period, phi, mult, True, 0, how)
    return shoot(model, model.initial_state() if y_guess is None else y_guess, rtol, max_iter)


def shoot(model: MeshModel, y_guess: FloatArray, rtol: float = 1e-10, max_iter: int = 15,
          periods: int = 1, route: str = "auto", tol: float | None = None) -> PeriodicSolution:
    """Periodic orbit by Newton's method on the one-period map (shooting).

    With ``periods = 2`` the map over two mesh periods: a period-2 (subharmonic) orbit, as
    found inside a parametric instability zone of a pair with backlash.

    Converged when the closing error ``|P(y0) - y0|`` is below ``tol`` (default ``100 rtol``)
    times the larger of the state scale and the state itself, component by component (the map
    is only known to about ``rtol``). Gives up early when from the fourth iteration on the
    error no longer halves (Newton is not converging from this guess).

    Parameters
    ----------
    model : MeshModel
    y_guess : ndarray
        Starting state ([m, m/s]).
    rtol : float
        Relative tolerance of each one-period integration.
    max_iter : int
        Newton iterations (>= 1).
    periods : int
        Mesh periods of the orbit (1..16).
    route : str
        How the one-period map and its Jacobian are computed
        (:func:`~gear_dyn.solvers.sensitivity.integrate_with_sensitivity`):
        ``auto`` (exact where it applies, else variational), ``exact`` or ``variational``.
    tol : float or None
        Relative closing error to stop at; None: ``100 rtol``. Each study's ``max_iter`` and
        ``tol`` are a :class:`gear_dyn.analysis.newton.NewtonSettings` (its table gives the
        defaults).

    Returns
    -------
    PeriodicSolution
        ``converged`` False if Newton did not close the orbit (the last iterate is returned);
        ``period`` is ``periods / f_m``.

    Raises
    ------
    SolverError
        Integration failure.
    """
    model = _require_sdof(model)
    check_range("periods", periods, "", low=1, high=16)
    period = int(periods) / model.mesh_frequency
    scale = np.asarray(model.state_scale, dtype=float)
    y = np.array(y_guess, dtype=float)
    n = y.size
    phi = np.eye(n)
    res = math.inf
    it = 0
    stop = 100 * rtol if tol is None else tol
    for it in range(1, max_iter + 1):
        yt, phi = integrate_with_sensitivity(model, y, period, rtol, route)
        r = yt - y
        ref = np.maximum(scale, np.abs(y))
        res_prev, res = res, float(np.max(np.abs(r) / ref))
        if res <= stop:
            mult = np.linalg.eigvals(phi).astype(np.complex128)
            return PeriodicSolution(y, period, phi, mult, True, it, "shooting", res, int(periods))
        if it >= 4 and res > 0.5 * res_prev:
            break  # no Newton convergence: the guess is outside the orbit's basin of Newton
        try:
            dy = np.linalg.solve(phi - np.eye(n), -r)
        except np.linalg.LinAlgError:
            break
        # limit the step to a few state scales (a far jump leaves Newton's region)
        factor = float(np.min(np.minimum(1.0, 20.0 * ref / np.maximum(np.abs(dy), 1e-300))))
        y = y + factor * dy
        if not np.all(np.isfinite(y)):
            break
    mult = np.linalg.eigvals(phi).astype(np.complex128)
    return PeriodicSolution(y, period, phi, mult, False, it, "shooting", res, int(periods))
