"""Speed sweeps: dynamic factor, DTE, stability and spectra over a range of pinion speeds.

A sweep evaluates a scene at many speeds. Two methods:

- ``steady`` (default): the periodic steady state directly (:mod:`gear_dyn.stability`). Linear
  models: the monodromy matrix and one linear solve per speed; a Floquet multiplier outside the
  unit circle flags parametric instability (no blow-up is integrated). Backlash: continuation
  from the previous speed's orbit and shooting; where the orbit is lost (a jump, or a response
  that is not period-1) the sweep integrates a settling transient from the previous state, as a
  slow physical sweep would, and shoots again.
- ``transient``: what ``gear-dyn run`` does, at every speed: integrate the scene's number of
  mesh periods and measure the last ``steady_periods`` (linear models still get their Floquet
  check first). With backlash each speed starts from the previous speed's end state.

Speed-dependent parts are rebuilt exactly as :func:`gear_dyn.scene.run_scene` builds them: the
mesh frequency ``f_m = z1 w / 2 pi``; stiffness, mass, load and damping coefficient do not depend
on speed. Models with backlash are swept up and down (the two curves differ where the response
has coexisting orbits: the jumps of Kahraman & Singh 1990).

Parallel runs: speeds are cut into blocks and the blocks run on any
:class:`concurrent.futures.Executor`: by default a process pool over the local cores; a Dask
``distributed.Client(...).get_executor()`` runs the same sweep on a cluster. Linear sweeps run
all blocks at once; continuation sweeps run their blocks in order, one chain per direction (the
up and down chains run side by side). Every speed is computed by the same code whatever the
executor, so the results are identical.
"""

from __future__ import annotations

import concurrent.futures as cf
import json
import math
import multiprocessing
import os
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from functools import lru_cache
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from .errors import InputError, check_range
from .geometry import mesh_frequency
from .models.base import Model
from .models.sdof import SDOFModel
from .solve import SolverSettings, integrate, time_grid

FloatArray = NDArray[np.float64]
RPM = 2 * math.pi / 60

METHODS = ("steady", "transient")
#: periods of settling transient between shooting attempts after an orbit is lost
SETTLE_CHUNK = 25
DIRECTIONS = ("auto", "up", "down", "both")


@dataclass(frozen=True)
class SweepOptions:
    """How each speed of a sweep is evaluated.

    Parameters
    ----------
    method : {"steady", "transient"}
        Periodic steady state directly, or transient integration as ``gear-dyn run``.
    window_periods : int
        Mesh periods in the spectrum window (1..64); 4 resolves subharmonics down to f_m / 4.
    harmonics : int
        Mesh harmonics kept in the spectra (1..64).
    settle_periods : int
        Steady method with backlash: periods of settling transient where shooting from the
        previous orbit fails (10..100000).
    max_newton : int
        Shooting iterations per attempt (2..100).
    """

    method: str = "steady"
    window_periods: int = 4
    harmonics: int = 5
    settle_periods: int = 100
    max_newton: int = 12

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise InputError(f"sweep method = {self.method!r}: valid choices are "
                             f"{', '.join(METHODS)}")
        check_range("window_periods", self.window_periods, "", low=1, high=64)
        check_range("harmonics", self.harmonics, "", low=1, high=64)
        check_range("settle_periods", self.settle_periods, "", low=10, high=100_000)
        check_range("max_newton", self.max_newton, "", low=2, high=100)


class Point(NamedTuple):
    """One speed of a sweep (SI units)."""

    speed: float
    mesh_frequency: float
    dynamic_factor: float
    rms_dte: float
    ptp_dte: float
    mean_dte: float
    spectral_radius: float
    stable: bool
    periodic: bool
    status: str
    separation: float
    backside: float
    iterations: int
    spectrum: FloatArray
    state: FloatArray
    orbit_periods: int = 0


@dataclass(frozen=True, eq=False)
class SweepCurve:
    """One sweep direction: arrays over the speeds in sweep order.

    Attributes
    ----------
    direction : str
        ``up`` (increasing speed) or ``down``.
    speed : ndarray
        Pinion speed in rad/s.
    mesh_frequency : ndarray
        Hz.
    dynamic_factor, rms_dte, ptp_dte, mean_dte : ndarray
        Peak mesh force / W; DTE RMS (mean removed), peak-to-peak and mean in m. NaN where the
        linear model is parametrically unstable.
    spectral_radius : ndarray
        Largest Floquet multiplier modulus of the steady orbit (NaN where not computed).
    stable, periodic : ndarray of bool
        Floquet-stable; response repeats every mesh period.
    status : tuple of str
        ``periodic``, ``settled`` (shooting from the previous orbit failed, the orbit was found
        again after a settling transient: where the response jumps), ``period-2`` (a stable
        orbit over two mesh periods: subharmonic response), ``aperiodic`` (no period-1 or -2
        orbit: measured over a settled window), ``unstable`` (parametric instability),
        ``transient`` (transient method).
    separation, backside : ndarray
        Share of the mesh period with the teeth apart (inside the backlash; for a linear model,
        a negative mesh force) and in back-side contact.
    iterations : ndarray of int
        Shooting iterations.
    spectrum : ndarray (n_speeds, n_orders)
        DTE amplitude (m) at the orders of :attr:`SweepResult.orders`.
    state : ndarray (n_speeds, n_states)
        State on the periodic orbit at t = 0 (steady method) or at the end of the run
        (transient, aperiodic), SI; NaN where unstable.
    orbit_periods : ndarray of int
        Mesh periods of the steady orbit: 1, 2 (period-2, subharmonic f_m/2 response) or 0
        (not found: aperiodic, transient method, unstable).
    """

    direction: str
    speed: FloatArray
    mesh_frequency: FloatArray
    dynamic_factor: FloatArray
    rms_dte: FloatArray
    ptp_dte: FloatArray
    mean_dte: FloatArray
    spectral_radius: FloatArray
    stable: NDArray[np.bool_]
    periodic: NDArray[np.bool_]
    status: tuple[str, ...]
    separation: FloatArray
    backside: FloatArray
    iterations: NDArray[np.int_]
    spectrum: FloatArray
    state: FloatArray
    orbit_periods: NDArray[np.int_]

    @classmethod
    def from_points(cls, direction: str, points: Sequence[Point]) -> SweepCurve:
        """Stack per-speed points."""
        def arr(name: str, dtype: Any = float) -> Any:
            return np.array([getattr(p, name) for p in points], dtype=dtype)

        return cls(
            direction=direction, speed=arr("speed"), mesh_frequency=arr("mesh_frequency"),
            dynamic_factor=arr("dynamic_factor"), rms_dte=arr("rms_dte"), ptp_dte=arr("ptp_dte"),
            mean_dte=arr("mean_dte"), spectral_radius=arr("spectral_radius"),
            stable=arr("stable", bool), periodic=arr("periodic", bool),
            status=tuple(p.status for p in points), separation=arr("separation"),
            backside=arr("backside"), iterations=arr("iterations", int),
            spectrum=np.array([p.spectrum for p in points], dtype=float),
            state=np.array([p.state for p in points], dtype=float),
            orbit_periods=arr("orbit_periods", int),
        )


@dataclass(frozen=True, eq=False)
class SweepResult:
    """A speed sweep.

    Attributes
    ----------
    scene_name : str
    curves : tuple of SweepCurve
        One per direction (``up`` first).
    orders : ndarray
        Spectrum frequencies in multiples of the mesh frequency (k / window_periods).
    natural_frequency : float
        f_n = sqrt(k_m / m_e) / 2 pi in Hz (NaN for models without it).
    static_load : float
        W in N.
    nonlinear : bool
        The model has backlash.
    options : SweepOptions
    settings : SolverSettings
    run_time_s : float
        Wall time of the whole sweep.
    executor : str
        Name of the executor class that ran it.
    """

    scene_name: str
    curves: tuple[SweepCurve, ...]
    orders: FloatArray
    natural_frequency: float
    static_load: float
    nonlinear: bool
    options: SweepOptions
    settings: SolverSettings
    run_time_s: float
    executor: str

    def curve(self, direction: str) -> SweepCurve:
        """The curve of ``direction`` (``up`` or ``down``)."""
        for c in self.curves:
            if c.direction == direction:
                return c
        raise InputError(f"sweep direction {direction!r} not in this result; available: "
                         f"{', '.join(c.direction for c in self.curves)}")


# ------------------------------------------------------------------ per-speed evaluation
def model_at_speed(model: Model, pair: Any, speed: float, scene: Any = None) -> Model:
    """The scene's model at pinion speed ``speed`` (rad/s), as ``run_scene`` would build it.

    For the single-DOF model only the mesh frequency depends on speed (``z1 w / 2 pi``, the
    same expression as :func:`gear_dyn.models.sdof.sdof_from_pair`); other models are rebuilt
    from ``scene`` with the new speed.
    """
    check_range("speed", speed, "rad/s", low=0.0, high=1e5, low_open=True)
    if isinstance(model, SDOFModel):
        return replace(model, mesh_frequency=mesh_frequency(pair, speed))
    if scene is None:
        raise InputError(f"model_at_speed: a {type(model).__name__} needs its scene to rebuild")
    from .scene import build_model

    tables = {**scene.tables, "operating": {**scene.tables["operating"], "speed": speed}}
    return build_model(replace(scene, tables=tables))


def _contact(model: Model, t: FloatArray, y: FloatArray, force: FloatArray
             ) -> tuple[float, float]:
    """Shares of samples with the teeth apart and in back-side contact."""
    if isinstance(model, SDOFModel) and model.backlash is not None:
        u = y[0]
        if model.transmission_error is not None:
            u = u - model.transmission_error.value(model.phase(t))
        b = model.backlash
        return float(np.mean(np.abs(u) <= b)), float(np.mean(u < -b))
    return float(np.mean(force < 0)), 0.0


def _order_spectrum(dte: FloatArray, window: int, spp: int, harmonics: int) -> FloatArray:
    """Amplitudes at orders k / window, k = 1..window*harmonics, of ``window`` periods."""
    x = dte - dte.mean()
    spec = np.fft.rfft(x) * 2.0 / x.size
    return np.abs(spec[1: window * harmonics + 1])


def _metrics(model: Model, t: FloatArray, y: FloatArray, load: float
             ) -> tuple[float, float, float, float, float, float]:
    out = model.outputs(t, y)
    dte, force = out["dte"], out["mesh_force"]
    if not (np.all(np.isfinite(dte)) and np.all(np.isfinite(force))):
        nan = math.nan
        return nan, nan, nan, nan, nan, nan
    df = float(np.max(force) / load) if load > 0 else math.nan
    sep, back = _contact(model, t, y, force)
    return (df, float(np.std(dte)), float(np.ptp(dte)), float(np.mean(dte)), sep, back)


def _nan_point(model: Model, speed: float, rho: float, status: str, n_orders: int) -> Point:
    nan = math.nan
    return Point(speed, model.mesh_frequency, nan, nan, nan, nan, rho, False, False, status, nan,
                 nan, 0, np.full(n_orders, nan), np.full(len(model.state_labels), nan))


def _flow(model: Model, t: FloatArray, settings: SolverSettings, y0: FloatArray) -> FloatArray:
    """States on ``t`` from ``y0``: the exact propagator for linear piecewise-constant models,
    else DOP853 with the stiffness fixed per piece (:func:`gear_dyn.stability.flow_on_grid`)."""
    from .stability import flow_on_grid

    if (isinstance(model, SDOFModel) and model.linear_segments(0.0, float(t[-1])) is None
            and settings.method in ("auto", "DOP853")):
        return flow_on_grid(model, y0, t, settings.rtol, settings.atol)
    y, _ = integrate(model, t, settings, y0)
    return y


def _orbit_point(model: Model, speed: float, y0: FloatArray, settings: SolverSettings,
                 opts: SweepOptions, rho: float, stable: bool, status: str, iterations: int,
                 orbit_periods: int = 1) -> Point:
    """Metrics of a periodic orbit of ``orbit_periods`` mesh periods starting at ``y0``: the
    orbit sampled once, repeated over the spectrum window."""
    spp = settings.samples_per_period
    fm = model.mesh_frequency
    n = orbit_periods * spp
    t = np.arange(n + 1) / (fm * spp)
    y = _flow(model, t, settings, y0)
    if orbit_periods > 1:
        # a period-1 orbit is a fixed point of the two-period map too: call it what it is
        scale = np.maximum(np.asarray(model.state_scale, dtype=float), np.abs(y[:, 0]))
        if np.max(np.abs(y[:, spp] - y[:, 0]) / scale) <= 1e3 * settings.rtol:
            orbit_periods, n = 1, spp
            t, y = t[: spp + 1], y[:, : spp + 1]
            rho = math.sqrt(rho)  # multipliers of the two-period map are squares
            status = "periodic" if status == "period-2" else status
    t, y = t[:-1], y[:, :-1]
    df, rms, ptp, mean, sep, back = _metrics(model, t, y, model.static_load)
    dte = model.outputs(t, y)["dte"]
    reps = -(-opts.window_periods // orbit_periods)
    dte_win = np.tile(dte, reps)[: opts.window_periods * spp]
    spec = _order_spectrum(dte_win, opts.window_periods, spp, opts.harmonics)
    return Point(speed, fm, df, rms, ptp, mean, rho, stable, orbit_periods == 1, status, sep,
                 back, iterations, spec, np.array(y0, dtype=float), orbit_periods)


def _window_point(model: Model, speed: float, t: FloatArray, y: FloatArray, n_window: int,
                  settings: SolverSettings, opts: SweepOptions, rho: float, status: str,
                  iterations: int) -> Point:
    """Metrics over the last ``n_window`` samples of a run (whole periods)."""
    spp = settings.samples_per_period
    tw, yw = t[-n_window:], y[:, -n_window:]
    df, rms, ptp, mean, sep, back = _metrics(model, tw, yw, model.static_load)
    dte = model.outputs(t, y)["dte"]
    nspec = opts.window_periods * spp
    spec = _order_spectrum(dte[-nspec - 1:-1], opts.window_periods, spp, opts.harmonics)
    scale = np.asarray(model.state_scale, dtype=float)
    closing = np.abs(y[:, -1] - y[:, -1 - spp]) / np.maximum(scale, np.abs(y[:, -1]))
    periodic = bool(np.max(closing) <= 1e3 * settings.rtol)
    return Point(speed, model.mesh_frequency, df, rms, ptp, mean, rho, math.isfinite(rho) and
                 rho <= 1.0, periodic, status, sep, back, iterations, spec, y[:, -1].copy())


def _steady_point(model: Model, speed: float, settings: SolverSettings, opts: SweepOptions,
                  y_guess: FloatArray | None, n_prev: int = 1
                  ) -> tuple[Point, FloatArray | None]:
    from .stability import UNIT_CIRCLE_TOL, periodic_steady_state, shoot

    assert isinstance(model, SDOFModel)
    n_orders = opts.window_periods * opts.harmonics
    rtol = settings.rtol
    if model.backlash is None:
        sol = periodic_steady_state(model, rtol=rtol)
        if not sol.stable:
            return _nan_point(model, speed, sol.spectral_radius, "unstable", n_orders), None
        return _orbit_point(model, speed, sol.y0, settings, opts, sol.spectral_radius, True,
                            "periodic", 0), sol.y0
    guess = model.initial_state() if y_guess is None else np.asarray(y_guess, dtype=float)
    first = n_prev if n_prev in (1, 2) else 1
    sol = shoot(model, guess, rtol, opts.max_newton, periods=first)
    iters = sol.iterations
    if sol.converged and sol.stable:
        return _orbit_point(model, speed, sol.y0, settings, opts, sol.spectral_radius, True,
                            "periodic" if first == 1 else "period-2", iters, first), sol.y0
    # the orbit followed so far is gone (or Newton left it): settle as a slow sweep would, in
    # chunks of SETTLE_CHUNK periods, shooting for a period-1, then a period-2 orbit after each.
    # The settling run only has to reach the attractor's basin, so it runs at rtol >= 1e-6;
    # shooting (or the measured window) restores the full accuracy.
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
            sol = shoot(model, y_end, rtol, opts.max_newton, periods=per)
            iters += sol.iterations
            if sol.converged and sol.spectral_radius <= 1.0 + UNIT_CIRCLE_TOL:
                if per == 2:
                    status = "period-2"
                else:
                    status = "settled" if y_guess is not None else "periodic"
                return _orbit_point(model, speed, sol.y0, settings, opts, sol.spectral_radius,
                                    True, status, iters, per), sol.y0
    # no period-1 or -2 orbit: measure a window of whole periods at full accuracy
    n_win = opts.window_periods * spp
    tw = np.arange(n_win + spp + 1) / (fm * spp)
    yw = _flow(model, tw, settings, y_end)
    return _window_point(model, speed, tw, yw, n_win, settings, opts, math.nan, "aperiodic",
                         iters), yw[:, -1]


def _transient_point(model: Model, speed: float, settings: SolverSettings,
                     opts: SweepOptions, periods: int, steady_periods: int,
                     y_guess: FloatArray | None) -> tuple[Point, FloatArray | None]:
    from .stability import UNIT_CIRCLE_TOL, floquet_multipliers

    n_orders = opts.window_periods * opts.harmonics
    rho = math.nan
    if isinstance(model, SDOFModel) and model.backlash is None:
        rho = float(np.max(np.abs(floquet_multipliers(model, settings.rtol))))
        if rho > 1.0 + UNIT_CIRCLE_TOL:
            return _nan_point(model, speed, rho, "unstable", n_orders), None
        y_guess = None  # linear: every speed from the static state, as run_scene
    spp = settings.samples_per_period
    t = time_grid(model.mesh_frequency, periods / model.mesh_frequency, spp)
    y, _ = integrate(model, t, settings, y_guess)
    # whole periods: the window of run_scene repeats phase 0 at both ends; one is enough
    n_win = steady_periods * spp
    return _window_point(model, speed, t, y, min(n_win, t.size), settings, opts, rho,
                         "transient", 0), y[:, -1]


@lru_cache(maxsize=4)
def _base(source: str, tables_json: str, overrides_json: str) -> tuple[Any, Any, Any]:
    """(scene, plan, pair) rebuilt from JSON (cached per worker process)."""
    from .scene import build_pair, build_plan, load_feature_sections
    from .scene.loader import Scene

    load_feature_sections()
    scene = Scene(source=source, tables=json.loads(tables_json))
    plan = build_plan(scene, **json.loads(overrides_json))
    return scene, plan, build_pair(scene)


@dataclass(frozen=True)
class _Task:
    source: str
    tables_json: str
    overrides_json: str
    options: SweepOptions
    speeds: tuple[float, ...]
    y_start: FloatArray | None
    continuation: bool
    orbit_periods: int = 1


def run_block(task: _Task) -> tuple[list[Point], FloatArray | None]:
    """Evaluate a block of speeds in order (the worker function; picklable).

    Returns the points and the last state (the start of the next block of a continuation; the
    last point's ``orbit_periods`` goes with it).
    """
    scene, plan, pair = _base(task.source, task.tables_json, task.overrides_json)
    f0 = plan.model.mesh_frequency
    periods = round(plan.t_end * f0)
    steady = round((plan.t_end - plan.steady_start) * f0)
    y = task.y_start
    n_prev = task.orbit_periods
    points = []
    for s in task.speeds:
        model = model_at_speed(plan.model, pair, s, scene)
        if task.options.method == "steady":
            p, y_next = _steady_point(model, s, plan.settings, task.options, y, n_prev)
            n_prev = p.orbit_periods or n_prev
        else:
            p, y_next = _transient_point(model, s, plan.settings, task.options, periods,
                                         steady, y)
        points.append(p)
        if task.continuation and y_next is not None:
            y = y_next
    return points, y


# ------------------------------------------------------------------ the driver
def parse_speed_range(text: str) -> FloatArray:
    """Speeds from ``START:STOP:N`` (units allowed; plain numbers are rpm), in rad/s.

    >>> parse_speed_range("600:1200:3") * 60 / (2 * math.pi)
    array([ 600.,  900., 1200.])

    Raises
    ------
    InputError
        Not three parts, a bad number or unit (Hz is refused: pint would read it as rad/s),
        N < 2, or speeds out of range.
    """
    from .scene.fields import Field

    parts = text.split(":")
    if len(parts) != 3:
        raise InputError(f"--speeds {text!r}: expected START:STOP:N, e.g. '500 rpm:6000 rpm:200'")
    fld = Field("speed", "rad/s", low=0.0, high=1e5, low_open=True)
    ends = []
    for label, part in zip(("START", "STOP"), parts[:2], strict=True):
        part = part.strip()
        if "hz" in part.lower():
            # pint reads 1 Hz as 1 rad/s (radians are dimensionless): 2 pi off for a shaft
            raise InputError(f"--speeds {label} = {part!r}: Hz is ambiguous for a shaft speed "
                             "(it would be read as rad/s); write e.g. '600 rpm' or '10 turn/s'")
        try:
            v = float(part) * RPM
        except ValueError:
            v = fld.parse(part, f"--speeds {label}")
        else:
            v = fld.parse(v, f"--speeds {label} ({part} rpm)")
        ends.append(v)
    try:
        n = int(parts[2])
    except ValueError:
        raise InputError(f"--speeds N = {parts[2]!r}: expected a whole number >= 2") from None
    check_range("--speeds N", n, "", low=2, high=1_000_000)
    return np.linspace(ends[0], ends[1], n)


def _default_executor(workers: int | None) -> cf.Executor:
    ctx = None
    if sys.version_info >= (3, 12) and "forkserver" in multiprocessing.get_all_start_methods():
        ctx = multiprocessing.get_context("forkserver")
    return cf.ProcessPoolExecutor(max_workers=workers or os.cpu_count() or 1, mp_context=ctx)


class _Inline(cf.Executor):
    """Runs each task at once in this process (``workers=1``)."""

    def submit(self, fn: Any, /, *args: Any, **kwargs: Any) -> cf.Future[Any]:
        fut: cf.Future[Any] = cf.Future()
        try:
            fut.set_result(fn(*args, **kwargs))
        except BaseException as exc:  # handed to the caller through the future
            fut.set_exception(exc)
        return fut


def sweep(
    scene: Any,
    speeds: Sequence[float] | FloatArray,
    *,
    options: SweepOptions | None = None,
    direction: str = "auto",
    executor: cf.Executor | None = None,
    workers: int | None = None,
    block: int = 8,
    progress: Callable[[int, int], None] | None = None,
    **overrides: Any,
) -> SweepResult:
    """Sweep a scene over pinion speeds.

    Parameters
    ----------
    scene : Scene
        A loaded scene (:func:`gear_dyn.scene.load_scene`).
    speeds : sequence of float
        Pinion speeds in rad/s (> 0); sorted, duplicates removed.
    options : SweepOptions or None
        Method and spectrum settings (default: steady state).
    direction : {"auto", "up", "down", "both"}
        ``auto``: up and down for models with backlash, up only for linear ones.
    executor : concurrent.futures.Executor or None
        Where blocks run (e.g. ``distributed.Client(...).get_executor()``); it is not shut
        down. None: a process pool over ``workers`` local cores, shut down at the end.
    workers : int or None
        Local processes when ``executor`` is None (default: all cores; 1 runs in-process).
    block : int
        Speeds per task (1..10000).
    progress : callable or None
        ``progress(done, total)`` after each finished block.
    **overrides
        ``[solver]`` values (rtol, method, samples_per_period, periods, steady_periods).

    Returns
    -------
    SweepResult

    Raises
    ------
    InputError
        Bad speeds, options or direction; the steady method on a model it does not cover.
    SolverError
        An integration failed.
    """
    from .scene import build_plan, load_feature_sections

    opts = options or SweepOptions()
    if direction not in DIRECTIONS:
        raise InputError(f"direction = {direction!r}: valid choices are {', '.join(DIRECTIONS)}")
    check_range("block", block, "", low=1, high=10_000)
    if workers is not None:
        check_range("workers", workers, "", low=1, high=4096)
    sp = np.unique(np.asarray(speeds, dtype=float))
    if sp.size < 1:
        raise InputError("sweep: no speeds given")
    for s in (sp[0], sp[-1]):
        check_range("speed", s, "rad/s", low=0.0, high=1e5, low_open=True)
    load_feature_sections()
    ov = {k: v for k, v in overrides.items() if v is not None}
    plan = build_plan(scene, **ov)
    model = plan.model
    nonlinear = not (isinstance(model, SDOFModel) and model.backlash is None)
    if opts.method == "steady" and not isinstance(model, SDOFModel):
        raise InputError(f"sweep method 'steady' covers the single-DOF model; this scene's model "
                         f"is {type(model).__name__}: use method 'transient'")
    if direction == "auto":
        dirs = ("up", "down") if nonlinear else ("up",)
    elif direction == "both":
        dirs = ("up", "down")
    else:
        dirs = (direction,)
    base = dict(source=scene.source, tables_json=json.dumps(scene.tables, sort_keys=True),
                overrides_json=json.dumps(ov, sort_keys=True), options=opts)
    chains: dict[str, list[tuple[float, ...]]] = {}
    for d in dirs:
        order = sp if d == "up" else sp[::-1]
        chains[d] = [tuple(float(v) for v in order[i:i + block])
                     for i in range(0, order.size, block)]
    total = sp.size * len(dirs)
    own = executor is None
    ex: cf.Executor = executor if executor is not None else (
        _Inline() if workers == 1 else _default_executor(workers))
    start = time.perf_counter()
    results: dict[str, list[list[Point]]] = {d: [[] for _ in chains[d]] for d in dirs}
    done = 0
    pending: dict[cf.Future[Any], tuple[str, int]] = {}
    try:

        def submit(d: str, i: int, y0: FloatArray | None, n_per: int = 1) -> None:
            task = _Task(speeds=chains[d][i], y_start=y0, continuation=nonlinear,
                         orbit_periods=n_per, **base)
            pending[ex.submit(run_block, task)] = (d, i)

        for d in dirs:
            if nonlinear:
                submit(d, 0, None)
            else:
                for i in range(len(chains[d])):
                    submit(d, i, None)
        while pending:
            finished, _ = cf.wait(list(pending), return_when=cf.FIRST_COMPLETED)
            for fut in finished:
                d, i = pending.pop(fut)
                points, y_end = fut.result()
                results[d][i] = points
                done += len(points)
                if progress is not None:
                    progress(done, total)
                if nonlinear and i + 1 < len(chains[d]):
                    submit(d, i + 1, y_end, points[-1].orbit_periods or 1)
    finally:
        for fut in pending:  # after a failure or an interrupt: drop the queued blocks
            fut.cancel()
        if own:
            ex.shutdown(wait=True, cancel_futures=True)
    run_time = time.perf_counter() - start
    curves = tuple(
        SweepCurve.from_points(d, [p for blk in results[d] for p in blk]) for d in dirs
    )
    orders = np.arange(1, opts.window_periods * opts.harmonics + 1) / opts.window_periods
    fn = float(getattr(model, "natural_frequency", math.nan))
    return SweepResult(
        scene_name=scene.name, curves=curves, orders=orders, natural_frequency=fn,
        static_load=float(model.static_load), nonlinear=nonlinear, options=opts,
        settings=plan.settings, run_time_s=run_time, executor=type(ex).__name__,
    )


# ------------------------------------------------------------------ tables and summaries
def sweep_columns(result: SweepResult) -> dict[str, Any]:
    """CSV columns: one row per (direction, speed); direction coded 0 = up, 1 = down."""
    cols: dict[str, list[float]] = {k: [] for k in (
        "direction_down", "speed_rpm", "speed_rad_s", "mesh_frequency_hz", "frequency_ratio",
        "dynamic_factor", "rms_dte_m", "ptp_dte_m", "mean_dte_m", "max_floquet_modulus",
        "stable", "periodic", "orbit_periods", "separation_share", "backside_share",
        "newton_iterations")}
    fn = result.natural_frequency
    for c in result.curves:
        n = c.speed.size
        cols["direction_down"] += [float(c.direction == "down")] * n
        cols["speed_rpm"] += list(c.speed / RPM)
        cols["speed_rad_s"] += list(c.speed)
        cols["mesh_frequency_hz"] += list(c.mesh_frequency)
        cols["frequency_ratio"] += list(c.mesh_frequency / fn)
        cols["dynamic_factor"] += list(c.dynamic_factor)
        cols["rms_dte_m"] += list(c.rms_dte)
        cols["ptp_dte_m"] += list(c.ptp_dte)
        cols["mean_dte_m"] += list(c.mean_dte)
        cols["max_floquet_modulus"] += list(c.spectral_radius)
        cols["stable"] += list(c.stable.astype(float))
        cols["periodic"] += list(c.periodic.astype(float))
        cols["orbit_periods"] += list(c.orbit_periods.astype(float))
        cols["separation_share"] += list(c.separation)
        cols["backside_share"] += list(c.backside)
        cols["newton_iterations"] += list(c.iterations.astype(float))
    return {k: np.asarray(v, dtype=float) for k, v in cols.items()}


def _ranges(speed: FloatArray, mask: NDArray[np.bool_]) -> list[list[float]]:
    """Contiguous speed ranges (rpm, sorted) where ``mask`` holds."""
    order = np.argsort(speed)
    s, m = speed[order] / RPM, mask[order]
    out: list[list[float]] = []
    i = 0
    while i < s.size:
        if m[i]:
            j = i
            while j + 1 < s.size and m[j + 1]:
                j += 1
            out.append([float(s[i]), float(s[j])])
            i = j + 1
        else:
            i += 1
    return out


def hysteresis_ranges(result: SweepResult, rel: float = 0.05) -> list[list[float]]:
    """Speed ranges (rpm) where the up and down sweeps differ by more than ``rel`` in RMS DTE."""
    if len(result.curves) < 2:
        return []
    up, down = result.curve("up"), result.curve("down")
    d = down.rms_dte[::-1]
    ref = np.maximum(np.abs(up.rms_dte), np.abs(d))
    with np.errstate(invalid="ignore"):
        differ = np.abs(up.rms_dte - d) > rel * ref
    return _ranges(up.speed, differ & np.isfinite(ref))


def jumps(curve: SweepCurve, rel: float = 0.3) -> list[dict[str, float]]:
    """Adjacent speeds whose RMS DTE changes by more than ``rel`` of the larger value."""
    r = curve.rms_dte
    out = []
    for i in range(r.size - 1):
        a, b = r[i], r[i + 1]
        if np.isfinite(a) and np.isfinite(b) and abs(b - a) > rel * max(abs(a), abs(b)):
            out.append({"from_rpm": float(curve.speed[i] / RPM),
                        "to_rpm": float(curve.speed[i + 1] / RPM),
                        "rms_dte_before_m": float(a), "rms_dte_after_m": float(b)})
    return out


def summarize_sweep(result: SweepResult) -> dict[str, Any]:
    """Summary of a sweep for sweep.json (SI units in the key names, speeds in rpm)."""
    out: dict[str, Any] = {
        "scene": result.scene_name,
        "method": result.options.method,
        "nonlinear": result.nonlinear,
        "natural_frequency_hz": result.natural_frequency,
        "resonance_speed_rpm": _resonance_rpm(result),
        "static_load_n": result.static_load,
        "n_speeds": int(result.curves[0].speed.size),
        "speed_range_rpm": [float(np.min(result.curves[0].speed) / RPM),
                            float(np.max(result.curves[0].speed) / RPM)],
        "run_time_s": result.run_time_s,
        "executor": result.executor,
        "solver": {"method": result.settings.method, "rtol": result.settings.rtol,
                   "samples_per_period": result.settings.samples_per_period},
        "options": {"window_periods": result.options.window_periods,
                    "harmonics": result.options.harmonics,
                    "settle_periods": result.options.settle_periods},
        "curves": {},
        "hysteresis_ranges_rpm": hysteresis_ranges(result),
    }
    for c in result.curves:
        finite = np.isfinite(c.dynamic_factor)
        info: dict[str, Any] = {
            "unstable_ranges_rpm": _ranges(c.speed, np.array([s == "unstable"
                                                               for s in c.status])),
            "separation_ranges_rpm": _ranges(c.speed, np.nan_to_num(c.separation) > 0),
            "backside_ranges_rpm": _ranges(c.speed, np.nan_to_num(c.backside) > 0),
            "aperiodic_ranges_rpm": _ranges(c.speed, np.array([s == "aperiodic"
                                                                for s in c.status])),
            "period2_ranges_rpm": _ranges(c.speed, c.orbit_periods == 2),
            "jumps": jumps(c),
        }
        if np.any(finite):
            i = int(np.nanargmax(np.where(finite, c.dynamic_factor, -np.inf)))
            info["max_dynamic_factor"] = float(c.dynamic_factor[i])
            info["max_dynamic_factor_speed_rpm"] = float(c.speed[i] / RPM)
            j = int(np.nanargmax(np.where(finite, c.rms_dte, -np.inf)))
            info["max_rms_dte_m"] = float(c.rms_dte[j])
            info["max_rms_dte_speed_rpm"] = float(c.speed[j] / RPM)
        out["curves"][c.direction] = info
    return out


def _resonance_rpm(result: SweepResult) -> float:
    """Speed (rpm) at which f_m equals f_n, from the sweep's own speed-to-f_m ratio."""
    c = result.curves[0]
    return float(result.natural_frequency / (c.mesh_frequency[0] / c.speed[0]) / RPM)


__all__ = [
    "METHODS", "Point", "SweepCurve", "SweepOptions", "SweepResult", "hysteresis_ranges",
    "jumps", "model_at_speed", "parse_speed_range", "run_block", "summarize_sweep", "sweep",
    "sweep_columns",
]
