"""Integration of a gear_dyn model with scipy's solve_ivp, piece by piece, and the Result.

The solver never steps across an instant where the right-hand side jumps (teeth entering or
leaving contact): the span is cut at ``model.switching_times`` and each piece is integrated by its
own ``solve_ivp`` call, started from the end state of the previous one. Output is on a uniform
time grid (``samples_per_period`` points per mesh period) so spectra can be taken directly.

Failures are never silent: a solver that reports failure or a non-finite state raises
:class:`~gear_dyn.errors.SolverError` carrying scipy's own message and advice.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.integrate import solve_ivp

from .errors import InputError, SolverError, check_range
from .models.base import Model

FloatArray = NDArray[np.float64]

METHODS = ("auto", "RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA", "exact", "periodic")
#: solve_ivp method of ``auto`` when the exact propagator does not apply. LSODA (restarted at
#: each switching instant) was the fastest for every target error on the helicopter tail scene
#: with rectangular and Fourier stiffness, heavy damping, a 1000x stiffer mesh and backlash
#: (docs/solvers.md, ``gear-dyn bench``), and it switches to BDF by itself when stiff.
DEFAULT_ODE_METHOD = "LSODA"
IMPLICIT = ("Radau", "BDF", "LSODA")

#: work limits, so that an absurd input ends in a clear error instead of a hang or a memory blow-up
MAX_SAMPLES = 4_000_000  #: output samples of one run (periods x samples_per_period)
MAX_NATURAL_PERIODS = 50_000  #: natural periods of the mesh mode one ODE run may span
MAX_NFEV = 5_000_000  #: right-hand-side evaluations of one ODE run (checked between pieces)

# Registry of non-solve_ivp methods: name -> function(model, t_grid, settings) -> (y, stats)
_EXTRA_METHODS: dict[str, Callable[..., tuple[FloatArray, dict[str, Any]]]] = {}


def register_method(name: str, func: Callable[..., tuple[FloatArray, dict[str, Any]]]) -> None:
    """Register a non-solve_ivp integration method (e.g. the exact propagator).

    ``func(model, t_grid, settings)`` returns the states on ``t_grid`` (n_states x n_t) and a
    dict of statistics (at least ``nfev``).
    """
    _EXTRA_METHODS[name] = func


@dataclass(frozen=True)
class SolverSettings:
    """Integration settings.

    Parameters
    ----------
    method : str
        ``auto`` (default: the exact propagator where it applies; else, for a linear
        single-DOF model on the usual uniform grid, ``periodic``; else LSODA), or one of
        RK45, RK23, DOP853, Radau, BDF, LSODA (solve_ivp), ``exact`` (piecewise-exact
        propagator, linear models with piecewise-constant coefficients only) or ``periodic``
        (linear mesh-periodic models: one period of step maps integrated, then reused; see
        :func:`gear_dyn.exact.propagate_periodic`).
    rtol : float
        Relative tolerance, 1e-13..1e-2.
    atol : float or None
        Absolute tolerance in units of the states; None means ``rtol * model.state_scale``
        (the static deflection and its velocity scale), i.e. a purely relative criterion.
    samples_per_period : int
        Output points per mesh period, 4..4096.
    max_step : float
        Largest step in s (inf: unlimited).
    estimate_error : bool
        Attach an error estimate to the result (``extra["estimated_error"]``, see
        :mod:`gear_dyn.accuracy`); for solve_ivp methods it costs a second, tighter run over a
        short window. Default True.
    """

    method: str = "auto"
    rtol: float = 1e-8
    atol: float | None = None
    samples_per_period: int = 64
    max_step: float = math.inf
    estimate_error: bool = True

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise InputError(
                f"solver.method = {self.method!r}: valid choices are {', '.join(METHODS)}"
            )
        check_range("solver.rtol", self.rtol, "", low=1e-13, high=1e-2)
        if self.atol is not None:
            check_range("solver.atol", self.atol, "", low=0.0, low_open=True)
        if isinstance(self.samples_per_period, bool) or int(self.samples_per_period) != (
            self.samples_per_period
        ):
            raise InputError(
                f"solver.samples_per_period = {self.samples_per_period!r}: expected an integer"
            )
        check_range("solver.samples_per_period", self.samples_per_period, "", low=4, high=4096)
        if not (isinstance(self.max_step, int | float) and self.max_step > 0):
            raise InputError(f"solver.max_step = {self.max_step!r} s: valid range > 0 s")


@dataclass(frozen=True)
class SolverStats:
    """What the integration cost: method, tolerances, counts and wall time."""

    method: str
    rtol: float
    atol: list[float]
    nfev: int
    njev: int
    nlu: int
    n_segments: int
    run_time_s: float

    def as_dict(self) -> dict[str, Any]:
        """Plain dict for JSON."""
        return {
            "method": self.method,
            "rtol": self.rtol,
            "atol": self.atol,
            "nfev": self.nfev,
            "njev": self.njev,
            "nlu": self.nlu,
            "n_segments": self.n_segments,
            "run_time_s": self.run_time_s,
        }


@dataclass(frozen=True, eq=False)
class Result:
    """A simulation: time series, derived outputs, solver statistics and provenance.

    Attributes
    ----------
    t : ndarray
        Uniform output times in s.
    y : ndarray
        States, shape (n_states, n_times).
    state_labels : tuple of str
    outputs : dict of ndarray
        Derived series from ``model.outputs`` (e.g. ``dte`` in m, ``mesh_force`` in N).
    steady_start : float
        Start of the steady-state window in s (the transient is before it).
    mesh_frequency : float
        Hz.
    static_load : float
        W in N.
    stats : SolverStats
    settings : SolverSettings
    scene : object or None
        The scene that produced the run (if any).
    """

    t: FloatArray
    y: FloatArray
    state_labels: tuple[str, ...]
    outputs: dict[str, FloatArray]
    steady_start: float
    mesh_frequency: float
    static_load: float
    stats: SolverStats
    settings: SolverSettings
    scene: Any = None
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def steady(self) -> NDArray[np.bool_]:
        """Boolean mask of the steady-state window."""
        return self.t >= self.steady_start - 1e-12 * max(1.0, abs(self.steady_start))

    def series(self, name: str) -> FloatArray:
        """A state or an output series by name."""
        if name in self.outputs:
            return self.outputs[name]
        if name in self.state_labels:
            return self.y[self.state_labels.index(name)]
        raise InputError(
            f"series {name!r} not in this result; available: "
            f"{', '.join([*self.state_labels, *self.outputs])}"
        )

    @property
    def dynamic_factor(self) -> float:
        """Peak dynamic mesh force / W over the steady window (NaN if W = 0)."""
        f = self.outputs["mesh_force"][self.steady]
        return float(np.max(f) / self.static_load) if self.static_load > 0 else math.nan

    @property
    def mean_dte(self) -> float:
        """Mean dynamic transmission error over the steady window in m."""
        return float(np.mean(self.outputs["dte"][self.steady]))

    @property
    def rms_dte(self) -> float:
        """RMS of the fluctuating DTE (mean removed) over the steady window in m."""
        x = self.outputs["dte"][self.steady]
        return float(np.sqrt(np.mean((x - x.mean()) ** 2)))

    @property
    def ptp_dte(self) -> float:
        """Peak-to-peak DTE over the steady window in m."""
        return float(np.ptp(self.outputs["dte"][self.steady]))


def time_grid(mesh_frequency: float, t_end: float, samples_per_period: int) -> FloatArray:
    """Uniform grid from 0 to ``t_end`` with ``samples_per_period`` points per mesh period."""
    dt = 1.0 / (mesh_frequency * samples_per_period)
    n = int(math.floor(t_end / dt + 1e-9)) + 1
    return np.arange(n, dtype=np.float64) * dt


def _atol(model: Model, settings: SolverSettings) -> FloatArray:
    if settings.atol is not None:
        return np.full(len(model.state_labels), settings.atol)
    return settings.rtol * np.asarray(model.state_scale, dtype=float)


def pieces(
    t_grid: FloatArray, cuts: FloatArray
) -> Iterator[tuple[float, float, int, int, FloatArray]]:
    """The pieces ``[ta, tb]`` between consecutive ``cuts`` with the output points they own.

    Yields ``(ta, tb, i0, i1, t_eval)``: grid points ``t_grid[i0:i1]`` lie in ``(ta, tb]`` (the
    first piece also owns ``ta``), and ``t_eval`` is those points with ``tb`` appended when it is
    not a grid point, so the end state of every piece is always returned.
    """
    idx = np.searchsorted(t_grid, cuts, side="right")  # grid points up to each cut
    for k in range(cuts.size - 1):
        ta, tb = float(cuts[k]), float(cuts[k + 1])
        if tb <= ta:
            continue
        i0, i1 = int(idx[k]), int(idx[k + 1])
        te = t_grid[i0:i1]
        t_eval = np.concatenate([te, [tb]]) if te.size == 0 or te[-1] < tb else te
        yield ta, tb, i0, i1, t_eval


def resolve_auto(model: Model) -> str:
    """The method ``auto`` picks: ``exact`` for linear piecewise-constant models, else LSODA.

    (:func:`integrate` further replaces LSODA by ``periodic`` for a linear single-DOF model on
    a grid commensurate with the mesh period; that choice needs the grid.)
    """
    seg = getattr(model, "linear_segments", None)
    if "exact" in _EXTRA_METHODS and seg is not None:
        t1 = 1.0 / model.mesh_frequency
        if seg(0.0, t1) is not None:
            return "exact"
    return DEFAULT_ODE_METHOD


def integrate(
    model: Model, t_grid: FloatArray, settings: SolverSettings, y0: FloatArray | None = None
) -> tuple[FloatArray, dict[str, Any]]:
    """States on ``t_grid`` (which starts at the initial time), segment by segment.

    Returns
    -------
    y : ndarray (n_states, n_t)
    stats : dict with nfev, njev, nlu, n_segments

    Raises
    ------
    SolverError
        solve_ivp failure or non-finite states, with scipy's message.
    """
    if settings.method == "auto":
        method = resolve_auto(model)
        if method != "exact" and "periodic" in _EXTRA_METHODS:
            from .exact import periodic_map_applies

            if periodic_map_applies(model, np.asarray(t_grid, dtype=float)):
                method = "periodic"  # linear, mesh-periodic: one period of integration
        y, st = integrate(model, t_grid, replace(settings, method=method), y0)
        return y, {**st, "method": st.get("method", method)}
    if settings.method in _EXTRA_METHODS:
        return _EXTRA_METHODS[settings.method](model, t_grid, settings, y0)
    if settings.method == "exact":
        raise InputError(
            "solver.method = 'exact': the exact propagator is not available in this build"
        )
    t0, t1 = float(t_grid[0]), float(t_grid[-1])
    y = np.array(model.initial_state() if y0 is None else y0, dtype=float)
    check_work(model, t0, t1, y)
    cuts = np.concatenate([[t0], model.switching_times(t0, t1), [t1]])
    atol = _atol(model, settings)
    n = len(model.state_labels)
    out = np.empty((n, t_grid.size))
    out[:, 0] = y
    extra: dict[str, Any] = {"jac": model.jac} if settings.method in IMPLICIT else {}
    nfev = njev = nlu = 0
    from .events import contact_event_functions, solve_piece_with_events

    events = contact_event_functions(model)  # contact changes (backlash): restart at each
    n_events = 0
    for ta, tb, i0, i1, t_eval in pieces(t_grid, cuts):
        if events:
            ys, y, est = solve_piece_with_events(
                model.rhs, ta, tb, y, t_eval, events, settings.method, settings.rtol, atol,
                settings.max_step, extra,
            )
            nfev, njev, nlu = nfev + est["nfev"], njev + est["njev"], nlu + est["nlu"]
            _check_nfev(nfev, settings.method, tb)
            n_events += est["n_events"]
            out[:, i0:i1] = ys[:, : i1 - i0]
            continue
        sol = solve_ivp(
            model.rhs, (ta, tb), y, method=settings.method, t_eval=t_eval, rtol=settings.rtol,
            atol=atol, max_step=settings.max_step, **extra,
        )
        nfev += sol.nfev
        _check_nfev(nfev, settings.method, tb)
        njev += sol.njev
        nlu += sol.nlu
        if sol.status != 0:
            raise SolverError(
                f"solve_ivp ({settings.method}) failed at t = {ta:.6g}..{tb:.6g} s: {sol.message}; "
                "try a smaller rtol or an implicit method (Radau, BDF)"
            )
        if not np.all(np.isfinite(sol.y)):
            raise SolverError(
                f"solve_ivp ({settings.method}) produced non-finite states near t = {tb:.6g} s; "
                "the response diverges (parametric instability?) or the tolerances are too loose"
            )
        out[:, i0:i1] = sol.y[:, : i1 - i0]
        y = sol.y[:, -1]
    stats: dict[str, Any] = {"nfev": nfev, "njev": njev, "nlu": nlu,
                             "n_segments": int(cuts.size - 1)}
    if events:
        stats["n_contact_events"] = n_events
    return out, stats


def check_work(model: Model, t0: float, t1: float, y0: FloatArray) -> None:
    """Refuse an ODE run that cannot give a sensible answer in reasonable time.

    Raises
    ------
    InputError
        The initial state is not finite, or the span covers more than
        :data:`MAX_NATURAL_PERIODS` periods of the model's ``natural_frequency`` (an ODE solver
        needs several steps per natural period, so such a run would take hours).
    """
    if not np.all(np.isfinite(y0)):
        labels = ", ".join(f"{n} = {v:.6g}" for n, v in zip(model.state_labels, y0, strict=False))
        raise InputError(
            f"initial state is not finite ({labels}): the inputs are beyond what the model can "
            "represent (check near-zero sizes, stiffnesses or inertias and huge loads)"
        )
    f_n = getattr(model, "natural_frequency", None)
    if f_n is None:
        return
    n_nat = (t1 - t0) * float(f_n)
    if not (math.isfinite(n_nat) and n_nat <= MAX_NATURAL_PERIODS):
        raise InputError(
            f"the run spans {n_nat:.4g} natural periods (natural frequency {float(f_n):.6g} Hz, "
            f"mesh frequency {model.mesh_frequency:.6g} Hz, duration {t1 - t0:.6g} s): valid "
            f"range <= {MAX_NATURAL_PERIODS} for an ODE solver; raise operating.speed, lower "
            "solver.periods, or use method 'exact' where it applies"
        )


def _check_nfev(nfev: int, method: str, t: float) -> None:
    if nfev > MAX_NFEV:
        raise SolverError(
            f"solve_ivp ({method}) gave up at t = {t:.6g} s after {nfev} right-hand-side "
            f"evaluations (limit {MAX_NFEV}): the problem is stiff or the tolerance too tight; "
            "try an implicit method (LSODA, Radau, BDF), a looser rtol, or fewer solver.periods"
        )


def simulate(
    model: Model,
    t_end: float,
    settings: SolverSettings | None = None,
    steady_start: float | None = None,
    scene: Any = None,
) -> Result:
    """Integrate ``model`` from 0 to ``t_end`` and return a :class:`Result`.

    Parameters
    ----------
    model : Model
        Any model offering the face of :mod:`gear_dyn.models.base`.
    t_end : float
        End time in s (> 0, at least two output samples).
    settings : SolverSettings or None
        Method and tolerances; None uses the defaults.
    steady_start : float or None
        Start of the steady-state window in s; None takes the second half of the run.
    scene : object
        Provenance stored in the result.

    Raises
    ------
    InputError
        Bad time span.
    SolverError
        The integration failed or diverged.
    """
    settings = settings or SolverSettings()
    check_range("duration", t_end, "s", low=0.0, low_open=True)
    n_samples = t_end * model.mesh_frequency * settings.samples_per_period
    if n_samples > MAX_SAMPLES:
        raise InputError(
            f"solver.periods x solver.samples_per_period = {n_samples:.4g} output samples "
            f"(duration {t_end:.6g} s at mesh frequency {model.mesh_frequency:.6g} Hz): valid "
            f"range <= {MAX_SAMPLES} samples; simulate fewer periods or fewer samples per period"
        )
    t_grid = time_grid(model.mesh_frequency, t_end, settings.samples_per_period)
    if t_grid.size < 8:
        raise InputError(
            f"duration = {t_end:.6g} s is shorter than a few samples; valid range >= "
            f"{8 / (model.mesh_frequency * settings.samples_per_period):.3g} s"
        )
    if steady_start is None:
        steady_start = 0.5 * t_grid[-1]
    check_range("steady_start", steady_start, "s", low=0.0, high=float(t_grid[-1]))
    start = time.perf_counter()
    y, st = integrate(model, t_grid, settings)
    run_time = time.perf_counter() - start
    outputs = model.outputs(t_grid, y)
    for name, arr in outputs.items():
        if not np.all(np.isfinite(arr)):
            raise SolverError(f"output {name!r} is not finite; the response diverges")
    stats = SolverStats(
        method=str(st.get("method", settings.method)),
        rtol=settings.rtol,
        atol=[float(a) for a in _atol(model, settings)],
        nfev=int(st.get("nfev", 0)),
        njev=int(st.get("njev", 0)),
        nlu=int(st.get("nlu", 0)),
        n_segments=int(st.get("n_segments", 0)),
        run_time_s=run_time,
    )
    counted = ("nfev", "njev", "nlu", "n_segments", "method")
    extra = {k: v for k, v in st.items() if k not in counted}
    if settings.estimate_error:
        from .accuracy import estimate_error

        used = replace(settings, method=str(st.get("method", settings.method)))
        extra["estimated_error"] = estimate_error(model, t_grid, y, used, st)
    from .accuracy import floquet_check

    floquet = floquet_check(model)
    if floquet is not None:
        extra["floquet"] = floquet
    if stats.method in ("RK45", "RK23", "DOP853"):
        from .accuracy import stiffness_check

        extra["stiffness_check"] = stiffness_check(model, stats.method)
    info = getattr(model, "summary_info", None)
    if info is not None:
        extra = {**info(), **extra}
    return Result(
        t=t_grid, y=y, state_labels=tuple(model.state_labels), outputs=outputs,
        steady_start=float(steady_start), mesh_frequency=model.mesh_frequency,
        static_load=model.static_load, stats=stats, settings=settings, scene=scene, extra=extra,
    )


def _register_builtin() -> None:
    from .exact import propagate_exact, propagate_periodic

    register_method("exact", propagate_exact)
    register_method("periodic", propagate_periodic)


_register_builtin()
