"""One speed of a sweep: the periodic steady state (or a transient) and its metrics."""

from __future__ import annotations

import math
from dataclasses import replace
from typing import cast

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.motion.classify import Motion, classify_motion
from gear_dyn.analysis.motion.period import MAX_PERIOD
from gear_dyn.analysis.stability import (
    OrbitShape,
    PeriodicSolution,
    contact_states,
    floquet_multipliers,
    floquet_stable,
    flow_on_grid,
    periodic_steady_state,
    shoot,
)
from gear_dyn.analysis.sweep.types import Point, SweepOptions, Window
from gear_dyn.models.base import MeshModel, Model
from gear_dyn.solvers import (
    DEFAULT_ODE_METHOD,
    SolverSettings,
    integrate,
    resolve_auto,
    time_grid,
)

FloatArray = NDArray[np.float64]

#: periods of settling transient between shooting attempts after an orbit is lost
SETTLE_CHUNK = 25
#: stroboscopic samples classified where no orbit of one or two mesh periods is found
CLASSIFY_SAMPLES = 64


def orbit_status(periods: int, continuing: bool = False) -> str:
    """Status of a steady orbit of ``periods`` mesh periods: ``periodic`` (``settled`` where
    found again after a settling transient), ``period-n`` for n >= 2."""
    if periods == 1:
        return "settled" if continuing else "periodic"
    return f"period-{periods}"


def _order_spectrum(dte: FloatArray, opts: SweepOptions) -> FloatArray:
    """Amplitudes at orders k / window, k = 1..window*harmonics, of ``window`` periods (of each
    row of ``dte``)."""
    x = dte - dte.mean(axis=-1, keepdims=True)
    spec = np.fft.rfft(x) * 2.0 / x.shape[-1]
    return np.abs(spec[..., 1: opts.window_periods * opts.harmonics + 1])


def _measures(model: Model, t: FloatArray, y: FloatArray,
              out: dict[str, FloatArray] | None = None) -> tuple[float, OrbitShape | None]:
    """F_max / W and the shape (contact shares, DTE measures) of samples over whole periods,
    the end excluded; NaN and None where the response is not finite."""
    out = model.outputs(t, y) if out is None else out
    dte, force = out["dte"], out["mesh_force"]
    if not (np.all(np.isfinite(dte)) and np.all(np.isfinite(force))):
        return math.nan, None
    load = model.static_load
    df = float(np.max(force) / load) if load > 0 else math.nan
    return df, OrbitShape.of_samples(contact_states(model, t, y, force), dte)


def _nan_point(model: Model, speed: float, status: str, opts: SweepOptions,
               orbit: PeriodicSolution | None = None, rho: float = math.nan) -> Point:
    """A row of NaN figures: a linear model's unstable ``orbit`` (its multipliers), else a
    window with spectral radius ``rho`` and no samples."""
    nan = math.nan
    spec = np.full(opts.window_periods * opts.harmonics, nan)
    window = None if orbit is not None else Window(np.full(len(model.state_labels), nan),
                                                   False, rho, None)
    return Point(speed, model.mesh_frequency, nan, status, 0, spec, orbit, 0, window)


def _flow(model: Model, t: FloatArray, settings: SolverSettings, y0: FloatArray) -> FloatArray:
    """States on ``t`` from ``y0`` by :func:`gear_dyn.solvers.integrate`, except where ``auto``
    would give a mesh model to a general ODE solver, or with ``DOP853`` pinned: there DOP853 with
    the stiffness fixed per piece (:func:`gear_dyn.analysis.stability.flow_on_grid`; docs/sweep.md,
    "Which integrator")."""
    if (model.mesh_periodic and model.linear_segments(0.0, float(t[-1])) is None
            and (settings.method == "DOP853"
                 or (settings.method == "auto" and resolve_auto(model) == DEFAULT_ODE_METHOD))):
        return flow_on_grid(cast(MeshModel, model), y0, t, settings.rtol, settings.atol)
    y, _ = integrate(model, t, settings, y0)
    return y


def _orbit_point(model: Model, speed: float, orbit: PeriodicSolution, settings: SolverSettings,
                 opts: SweepOptions, status: str, iterations: int) -> Point:
    """The row of a periodic orbit: the orbit sampled once (its least period), repeated over
    the spectrum window; the samples give the orbit its ``shape``."""
    spp = settings.samples_per_period
    fm = model.mesh_frequency
    least = orbit.periods
    n = least * spp
    t = np.arange(n + 1) / (fm * spp)
    y = _flow(model, t, settings, orbit.y0)
    if least > 1:
        # a period-d orbit (d dividing n) is a fixed point of the n-period map too: call it
        # what it is
        scale = np.maximum(np.asarray(model.state_scale, dtype=float), np.abs(y[:, 0]))
        for d in range(1, least):
            if (least % d == 0
                    and np.max(np.abs(y[:, d * spp] - y[:, 0]) / scale) <= 1e3 * settings.rtol):
                if status.startswith("period-"):
                    status = orbit_status(d)
                least, n = d, d * spp
                t, y = t[: n + 1], y[:, : n + 1]
                break
    t, y = t[:-1], y[:, :-1]  # whole periods, the end excluded
    out = model.outputs(t, y)
    df, shape = _measures(model, t, y, out)
    reps = -(-opts.window_periods // least)
    dte_win = np.tile(out["dte"], reps)[: opts.window_periods * spp]
    spec = _order_spectrum(dte_win, opts)
    return Point(speed, fm, df, status, iterations, spec, replace(orbit, shape=shape), least,
                 motion=f"period-{least}")


def _window_point(model: Model, speed: float, t: FloatArray, y: FloatArray, n_window: int,
                  settings: SolverSettings, opts: SweepOptions, rho: float, status: str,
                  iterations: int, motion: Motion | None = None) -> Point:
    """The row of the last ``n_window`` samples of a run (whole periods)."""
    spp = settings.samples_per_period
    df, shape = _measures(model, t[-n_window:], y[:, -n_window:])
    dte = model.outputs(t, y)["dte"]
    nspec = opts.window_periods * spp
    spec = _order_spectrum(dte[-nspec - 1:-1], opts)
    scale = np.asarray(model.state_scale, dtype=float)
    closing = np.abs(y[:, -1] - y[:, -1 - spp]) / np.maximum(scale, np.abs(y[:, -1]))
    periodic = bool(np.max(closing) <= 1e3 * settings.rtol)
    est = None if motion is None else motion.lyapunov
    return Point(speed, model.mesh_frequency, df, status, iterations, spec,
                 window=Window(y[:, -1].copy(), periodic, rho, shape),
                 motion="" if motion is None else motion.label,
                 lyapunov=math.nan if est is None else est.value,
                 lyapunov_error=math.nan if est is None else est.error)


def steady_point(model: Model, speed: float, settings: SolverSettings, opts: SweepOptions,
                 y_guess: FloatArray | None, n_prev: int = 1
                 ) -> tuple[Point, FloatArray | None]:
    """The steady method at one speed: the periodic orbit (linear: directly; backlash: shooting
    from ``y_guess``, settling where the orbit is lost). Returns the point and the state to
    continue from."""
    if not model.mesh_periodic:
        raise ValueError("steady_point needs a mesh-periodic model")  # checked by sweep()
    mesh = model
    assert isinstance(mesh, MeshModel)
    if mesh.backlash is None:  # linear: the orbit from the one-period map, NaN where unstable
        sol = periodic_steady_state(mesh, rtol=settings.rtol)
        if not sol.stable:
            return _nan_point(mesh, speed, "unstable", opts, orbit=sol), None
        return _orbit_point(mesh, speed, sol, settings, opts, "periodic", 0), sol.y0
    guess = mesh.initial_state() if y_guess is None else np.asarray(y_guess, dtype=float)
    first = n_prev if 1 <= n_prev <= MAX_PERIOD else 1
    sol = shoot(mesh, guess, settings.rtol, opts.newton.max_iter, periods=first,
                tol=opts.newton.tolerance)
    if sol.converged and sol.stable:
        return _orbit_point(mesh, speed, sol, settings, opts, orbit_status(first),
                            sol.iterations), sol.y0
    return _settle_and_shoot(mesh, speed, settings, opts, guess, sol.iterations,
                             continuing=y_guess is not None)


def _settle_and_shoot(model: MeshModel, speed: float, settings: SolverSettings,
                      opts: SweepOptions, guess: FloatArray, iters: int, continuing: bool
                      ) -> tuple[Point, FloatArray | None]:
    """The orbit followed so far is gone (or Newton left it): settle as a slow sweep would, in
    chunks of SETTLE_CHUNK periods at rtol >= 1e-6 (it only has to reach the basin), shooting
    for a period-1, then a period-2 orbit after each; else classify the motion
    (:func:`gear_dyn.analysis.motion.classify_motion`). docs/sweep.md, "How the steady state is
    found", gives the statuses."""
    spp = settings.samples_per_period
    fm = model.mesh_frequency
    loose = replace(settings, rtol=max(settings.rtol, 1e-6), atol=None)
    y_end = guess
    settled = 0
    while settled < opts.settle_periods:
        n = min(SETTLE_CHUNK, opts.settle_periods - settled)
        y_end = _flow(model, np.arange(n * spp + 1) / (fm * spp), loose, y_end)[:, -1]
        settled += n
        for per in (1, 2):
            sol = shoot(model, y_end, settings.rtol, opts.newton.max_iter, periods=per,
                        tol=opts.newton.tolerance)
            iters += sol.iterations
            if sol.stable:
                return _orbit_point(model, speed, sol, settings, opts,
                                    orbit_status(per, continuing), iters), sol.y0
    motion = classify_motion(model, y_end, 0, CLASSIFY_SAMPLES, settings.rtol,
                             opts.lyapunov_periods, max(10, opts.lyapunov_periods // 10),
                             opts.newton)
    iters += motion.shooting_iterations
    if motion.orbit is not None:
        return _orbit_point(model, speed, motion.orbit, settings, opts,
                            orbit_status(motion.period, continuing), iters), motion.state
    n_win = opts.window_periods * spp
    tw = np.arange(n_win + spp + 1) / (fm * spp)
    yw = _flow(model, tw, settings, motion.state)
    return _window_point(model, speed, tw, yw, n_win, settings, opts, math.nan, "aperiodic",
                         iters, motion), yw[:, -1]


def transient_point(model: Model, speed: float, settings: SolverSettings,
                     opts: SweepOptions, periods: int, steady_periods: int,
                     y_guess: FloatArray | None) -> tuple[Point, FloatArray | None]:
    """The transient method at one speed: a run as ``gear-dyn run`` and its last window."""
    rho = math.nan
    if model.mesh_periodic and model.is_linear:
        assert isinstance(model, MeshModel)
        rho = float(np.max(np.abs(floquet_multipliers(model, settings.rtol))))
        if not floquet_stable(rho):
            return _nan_point(model, speed, "unstable", opts, rho=rho), None
        y_guess = None  # linear: every speed from the static state, as run_scene
    spp = settings.samples_per_period
    t = time_grid(model.mesh_frequency, periods / model.mesh_frequency, spp)
    y, _ = integrate(model, t, settings, y_guess)
    # whole periods: the window of run_scene repeats phase 0 at both ends; one is enough
    n_win = steady_periods * spp
    return _window_point(model, speed, t, y, min(n_win, t.size), settings, opts, rho,
                         "transient", 0), y[:, -1]
