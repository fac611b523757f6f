"""Sweep options and results: per-speed points stacked into curves."""

from __future__ import annotations

import importlib
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.dynamic_factor import (
    DYNAMIC_FACTOR_DEFINITION,
    STIFFNESS_JUMP_DEFINITION,
)
from gear_dyn.analysis.newton import NewtonSettings
from gear_dyn.analysis.stability import OrbitShape, PeriodicSolution, floquet_stable
from gear_dyn.analysis.sweep.jump import RPM, Jump
from gear_dyn.errors import InputError, check_range
from gear_dyn.solvers import SolverSettings

FloatArray = NDArray[np.float64]

METHODS = ("steady", "transient")
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
    newton : NewtonSettings
        Shooting at each speed: ``max_iter`` iterations per attempt (2..100; default 12) to
        the closing error ``tolerance`` (default None: 100 ``rtol`` of the solver settings).
    lyapunov_periods : int
        Steady method, where no orbit of 1..16 mesh periods is found after settling: mesh
        periods of the largest Lyapunov exponent that tells quasi-periodic from chaotic motion
        (20..1e6; :func:`gear_dyn.analysis.motion.classify_samples`).

    Raises
    ------
    InputError
        An unknown method or a field outside its range.

    See Also
    --------
    :func:`~gear_dyn.scene.sweep.sweep_scene` : Sweeps a scene with these options.
    :class:`~gear_dyn.analysis.motion.diagram.DiagramOptions` : The same for a bifurcation diagram.

    Examples
    --------
    >>> SweepOptions(window_periods=8).harmonics
    5
    >>> SweepOptions(method="implicit")
    Traceback (most recent call last):
    ...
    gear_dyn.errors.InputError: sweep method = 'implicit': valid choices are steady, transient
    """

    method: str = "steady"
    window_periods: int = 4
    harmonics: int = 5
    settle_periods: int = 100
    newton: NewtonSettings = NewtonSettings(max_iter=12)
    lyapunov_periods: int = 200

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise InputError(f"sweep method = {self.method!r}: valid choices are "
                             f"{', '.join(METHODS)}")
        check_range("window_periods", self.window_periods, "", low=1, high=64)
        check_range("harmonics", self.harmonics, "", low=1, high=64)
        check_range("settle_periods", self.settle_periods, "", low=10, high=100_000)
        check_range("newton.max_iter", self.newton.max_iter, "", low=2, high=100)
        check_range("lyapunov_periods", self.lyapunov_periods, "", low=20, high=1_000_000)


class Window(NamedTuple):
    """What a sweep row measures over the last window of a run instead of on an orbit (the
    transient method; speeds where no orbit of 1..16 mesh periods is found; a linear model's
    parametric instability).

    Attributes
    ----------
    state : ndarray
        State at the end of the run, SI (NaN where unstable).
    periodic : bool
        The response repeats after one mesh period (to 1e3 ``rtol`` of the state scale).
    spectral_radius : float
        Largest Floquet multiplier modulus of a linear model (NaN otherwise).
    shape : OrbitShape or None
        Contact pattern, contact shares and DTE measures over the window (None where it is not
        finite or not run).
    """

    state: FloatArray
    periodic: bool
    spectral_radius: float
    shape: OrbitShape | None


class Point(NamedTuple):
    """One speed of a sweep (SI units): the row's own figures beside the orbit they measure.

    The orbit part (state, mesh periods, multipliers and stability, contact shares and DTE
    measures) is read from ``orbit`` (:class:`~gear_dyn.analysis.stability.PeriodicSolution`,
    its ``shape`` from the sweep's samples) or, where the row has no orbit, from ``window``;
    the properties of the :class:`SweepCurve` column names read it from there.

    Attributes
    ----------
    speed : float
        Pinion speed in rad/s.
    mesh_frequency : float
        Hz.
    peak_force_ratio : float
        F_max / W (-).
    status : str
        As ``SweepCurve.status``.
    iterations : int
        Newton iterations spent at this speed (every shooting attempt).
    spectrum : ndarray
        DTE amplitudes (m) at the orders of ``SweepResult.orders``.
    orbit : PeriodicSolution or None
        The steady orbit (for a linear model also the unstable one; its multipliers decide
        the row's stability), None for window rows.
    least_period : int
        Mesh periods after which the orbit's samples repeat (a divisor of
        ``orbit.periods``); 0 where the row shows no orbit.
    window : Window or None
        The run's window where the row has no orbit.
    motion : str
        The classified motion (``period-4``, ``chaotic, lambda = ...``), or "".
    lyapunov, lyapunov_error : float
        Largest Lyapunov exponent and its standard error in 1/s (NaN where not computed).
    """

    speed: float
    mesh_frequency: float
    peak_force_ratio: float
    status: str
    iterations: int
    spectrum: FloatArray
    orbit: PeriodicSolution | None = None
    least_period: int = 0
    window: Window | None = None
    motion: str = ""
    lyapunov: float = math.nan
    lyapunov_error: float = math.nan

    @property
    def shape(self) -> OrbitShape | None:
        """Contact pattern and shares and DTE measures of the orbit or the window."""
        if self.window is not None:
            return self.window.shape
        return None if self.orbit is None else self.orbit.shape

    @property
    def rms_dte(self) -> float:
        """DTE standard deviation in m (NaN without a shape)."""
        return math.nan if self.shape is None else self.shape.dte_rms

    @property
    def ptp_dte(self) -> float:
        """Peak-to-peak DTE in m."""
        return math.nan if self.shape is None else self.shape.dte_ptp

    @property
    def mean_dte(self) -> float:
        """Mean DTE in m."""
        return math.nan if self.shape is None else self.shape.dte_mean

    @property
    def separation(self) -> float:
        """Share of the time with the teeth apart (a linear model: a negative mesh force)."""
        return math.nan if self.shape is None else self.shape.separation

    @property
    def backside(self) -> float:
        """Share of the time on the back flank."""
        return math.nan if self.shape is None else self.shape.back

    @property
    def spectral_radius(self) -> float:
        """Largest multiplier modulus of the map over ``least_period`` mesh periods (of the
        orbit's own map where it shows none; the window's linear system)."""
        if self.window is not None:
            return self.window.spectral_radius
        if self.orbit is None:
            return math.nan
        return self.orbit.spectral_radius_over(self.least_period or self.orbit.periods)

    @property
    def stable(self) -> bool:
        """The orbit's verdict (:attr:`~gear_dyn.analysis.stability.PeriodicSolution.stable`;
        a window: its linear system's, :func:`~gear_dyn.analysis.stability.floquet_stable`)."""
        if self.window is not None:
            return floquet_stable(self.window.spectral_radius)
        return self.orbit is not None and self.orbit.stable

    @property
    def periodic(self) -> bool:
        """The response repeats every mesh period."""
        return self.window.periodic if self.window is not None else self.least_period == 1

    @property
    def state(self) -> FloatArray:
        """State on the orbit at t = 0 (window: at the end of the run); NaN where unstable."""
        if self.window is not None:
            return self.window.state
        if self.orbit is None:
            return np.zeros(0)
        return self.orbit.y0 if self.least_period else np.full_like(self.orbit.y0, math.nan)

    @property
    def orbit_periods(self) -> int:
        """Mesh periods of the steady orbit (0: none shown)."""
        return self.least_period


#: the per-speed columns of a :class:`SweepCurve`, each a :class:`Point` field or property of
#: that name
POINT_COLUMNS = ("speed", "mesh_frequency", "peak_force_ratio", "rms_dte", "ptp_dte", "mean_dte",
                 "spectral_radius", "stable", "periodic", "status", "separation", "backside",
                 "iterations", "spectrum", "state", "orbit_periods", "motion", "lyapunov",
                 "lyapunov_error")


#: the curve arrays a peak can be taken of (:meth:`SweepCurve.peak`), with their SI unit
PEAK_QUANTITIES: dict[str, str] = {"dynamic_factor": "", "peak_force_ratio": "",
                                   "rms_dte": "m", "ptp_dte": "m"}


class Peak(NamedTuple):
    """The largest value of one sweep quantity and where it lies.

    A named tuple: ``value, speed, direction = sweep.peak()`` unpacks as before, and the fields
    read by name (``sweep.peak().speed_rpm``).

    Attributes
    ----------
    value : float
        The peak value in the quantity's unit (K_dyn and F_max / W are ratios, DTE in m);
        NaN where no speed has a finite value.
    speed : float
        Pinion speed of the peak in rad/s (NaN with no finite value).
    direction : str
        The sweep direction (``up`` or ``down``) whose curve holds it ("" with no finite
        value).
    """

    value: float
    speed: float
    direction: str

    @property
    def speed_rpm(self) -> float:
        """Pinion speed of the peak in rpm."""
        return self.speed / RPM

    def row(self, quantity: str) -> dict[str, Any]:
        """The peak as a dict with unit-named keys, e.g. ``{"quantity": "rms_dte",
        "value": ..., "unit": "m", "speed_rpm": ..., "speed_rad_s": ..., "direction": "up"}``."""
        return {"quantity": quantity, "value": self.value,
                "unit": PEAK_QUANTITIES.get(quantity, ""), "speed_rpm": self.speed_rpm,
                "speed_rad_s": self.speed, "direction": self.direction}


NO_PEAK = Peak(math.nan, math.nan, "")


def _check_quantity(quantity: str) -> None:
    if quantity not in PEAK_QUANTITIES:
        raise InputError(f"peak quantity = {quantity!r}: valid choices are "
                         f"{', '.join(PEAK_QUANTITIES)}")


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
    dynamic_factor : ndarray
        K_dyn = F_max / F_qs,max: the peak dynamic mesh force over the peak quasi-static mesh
        force of the same model (one quasi-static run per sweep,
        ``SweepResult.quasi_static``), like ``gear-dyn run``'s; tends to 1 at low speed,
        like ISO 6336-1 K_v. NaN without a quasi-static reference.
    peak_force_ratio : ndarray
        F_max / W: the peak dynamic mesh force over the static load W = T1 / r_b1, the dynamic
        factor times the stiffness-jump factor (:attr:`SweepResult.stiffness_jump_factor`).
    rms_dte, ptp_dte, mean_dte : ndarray
        DTE RMS (mean removed), peak-to-peak and mean in m. NaN (as the factors) where the
        linear model is parametrically unstable.
    spectral_radius : ndarray
        Largest Floquet multiplier modulus of the steady orbit (NaN where not computed).
    stable, periodic : ndarray of bool
        Floquet-stable; response repeats every mesh period.
    status : tuple of str
        ``periodic``, ``settled`` (shooting from the previous orbit failed, the orbit was found
        again after a settling transient: where the response jumps), ``period-n`` (n = 2..16:
        a stable orbit over n mesh periods, subharmonic response, confirmed by shooting over n
        periods), ``aperiodic`` (no orbit of 1..16 periods: quasi-periodic or chaotic, see
        ``motion``; measured over a settled window), ``unstable`` (parametric instability),
        ``transient`` (transient method).
    separation, backside : ndarray
        Share of the mesh period with the teeth apart (inside the backlash; for a linear model,
        a negative mesh force) and in back-side contact.
    iterations : ndarray of int
        Shooting iterations.
    spectrum : ndarray (n_speeds, n_orders)
        DTE amplitude (m) at the orders of ``SweepResult.orders``.
    state : ndarray (n_speeds, n_states)
        State on the periodic orbit at t = 0 (steady method) or at the end of the run
        (transient, aperiodic), SI; NaN where unstable.
    orbit_periods : ndarray of int
        Mesh periods of the steady orbit: 1, n = 2..16 (period-n, subharmonic f_m/n response)
        or 0 (not found: aperiodic, transient method, unstable).
    motion : tuple of str
        Steady method with backlash: what the motion is (``period-1``, ``period-4``,
        ``quasi-periodic, lambda = ...``, ``chaotic, lambda = 2054 +- 98 1/s``, ``not settled,
        ...``; :mod:`gear_dyn.analysis.motion`); "" where not classified.
    lyapunov, lyapunov_error : ndarray
        Largest Lyapunov exponent and its standard error in 1/s where no orbit was found
        (NaN elsewhere).
    jumps : tuple of Jump
        Where the response jumps between neighbouring speeds, found from the orbits
        (:func:`gear_dyn.analysis.sweep.orbit_jumps.find_jumps`;
        :func:`~gear_dyn.analysis.sweep.driver.sweep` fills it in).
    """

    direction: str
    speed: FloatArray
    mesh_frequency: FloatArray
    dynamic_factor: FloatArray
    peak_force_ratio: FloatArray
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
    motion: tuple[str, ...] = ()
    lyapunov: FloatArray = field(default_factory=lambda: np.zeros(0))
    lyapunov_error: FloatArray = field(default_factory=lambda: np.zeros(0))
    jumps: tuple[Jump, ...] = ()

    def peak(self, quantity: str = "dynamic_factor") -> Peak:
        """The largest finite value of ``quantity`` on this curve
        (:class:`~gear_dyn.analysis.sweep.types.Peak`; speed in rad/s,
        ``.speed_rpm`` in rpm).

        Parameters
        ----------
        quantity : {"dynamic_factor", "peak_force_ratio", "rms_dte", "ptp_dte"}
            K_dyn, F_max / W (ratios) or the RMS / peak-to-peak DTE (m).

        Raises
        ------
        InputError
            An unknown quantity.
        """
        _check_quantity(quantity)
        y = np.asarray(getattr(self, quantity), dtype=float)
        finite = np.isfinite(y)
        if not finite.any():
            return Peak(math.nan, math.nan, self.direction) if y.size else NO_PEAK
        i = int(np.argmax(np.where(finite, y, -np.inf)))
        return Peak(float(y[i]), float(self.speed[i]), self.direction)

    @classmethod
    def from_points(cls, direction: str, points: Sequence[Point],
                    stiffness_jump_factor: float = math.nan) -> SweepCurve:
        """Stack per-speed points; ``stiffness_jump_factor`` (F_qs,max / W of the quasi-static
        reference; NaN: none) turns their peak force ratios into dynamic factors."""
        kinds = {"stable": bool, "periodic": bool, "iterations": int, "orbit_periods": int}
        cols: dict[str, Any] = {}
        for name in POINT_COLUMNS:
            values = [getattr(p, name) for p in points]
            cols[name] = (tuple(values) if name in ("status", "motion")
                          else np.array(values, dtype=kinds.get(name, float)))
        return cls(direction=direction,
                   dynamic_factor=cols["peak_force_ratio"] / stiffness_jump_factor, **cols)


#: the module that draws a SweepResult; looked up by name at call time (never imported on load,
#: as :class:`gear_dyn.solvers.result.ResultPlots` does for runs)
PLOTS_MODULE = "gear_dyn.plots.sweep"


class SweepPlots:
    """``sweep.plot``: the sweep's figures as methods, each taking ``ax=None`` and returning the
    matplotlib Figure. Thin forwards to :mod:`gear_dyn.plots.sweep`, imported on the first call.

    Examples
    --------
    >>> fig = sweep.plot.response()                                   # doctest: +SKIP
    >>> fig = Figure(); sweep.plot.response(ax=fig.subplots(3, 1))    # doctest: +SKIP
    """

    def __init__(self, result: SweepResult) -> None:
        self._result = result

    def response(self, ax: Any = None, **kwargs: Any) -> Any:
        """Dynamic factor, RMS and peak-to-peak DTE against speed
        (:func:`gear_dyn.plots.sweep.plot_sweep_response`: ``ax`` is None or its 3 Axes, one
        per panel; ``kwargs`` as there, e.g. ``iso_kv``)."""
        plots = importlib.import_module(PLOTS_MODULE)
        return plots.plot_sweep_response(self._result, ax=ax, **kwargs)

    def waterfall(self, ax: Any = None, **kwargs: Any) -> Any:
        """DTE spectra against speed (:func:`gear_dyn.plots.sweep.plot_waterfall`: ``ax`` is
        None or the Axes it documents; ``kwargs`` as there, e.g. ``direction``)."""
        plots = importlib.import_module(PLOTS_MODULE)
        return plots.plot_waterfall(self._result, ax=ax, **kwargs)


@dataclass(frozen=True, eq=False, repr=False)
class SweepResult:
    """A speed sweep.

    Made by :func:`~gear_dyn.scene.sweep.sweep_scene`; each parameter is kept as the attribute of
    that name.

    Parameters
    ----------
    scene_name : str
        The scene's name.
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
        Where it ran: ``serial`` (the calling process), ``process pool, N workers``
        (``workers=N``) or the class name of the executor given (``ClientExecutor`` for Dask).
    quasi_static : dict or None
        The quasi-static reference of the dynamic factor, one run for the whole sweep (the
        quasi-static peak force does not depend on speed):
        :func:`gear_dyn.analysis.dynamic_factor.quasi_static_reference` (``peak_force_ratio``
        F_qs,max / W, ``speed_ratio``, ``estimated_error`` ...); None where the model states no
        natural frequency (the dynamic factors are then NaN).
    warnings : tuple of str
        What the caller should know about the inputs, one sentence each (e.g. a backlash scene
        with no excitation that can open the gap at light load); printed by the CLI.

    Attributes
    ----------
    stiffness_jump_factor : float
        F_qs,max / W, the quasi-static force overshoot at the jumps of k(t).
    plot : SweepPlots
        The figures: ``sweep.plot.response(ax=None)``, ``sweep.plot.waterfall(ax=None)``.

    See Also
    --------
    :func:`~gear_dyn.scene.sweep.sweep_scene` : Makes it.
    :class:`~gear_dyn.analysis.compare.Comparison` : Sweeps of several designs compared.

    Examples
    --------
    >>> import gear_dyn as gd
    >>> sweep = gd.sweep_scene(gd.load_scene("helicopter_tail"), "3000 rpm:3600 rpm:3")
    >>> [c.direction for c in sweep.curves], sweep.executor
    (['up'], 'serial')
    >>> round(sweep.stiffness_jump_factor, 3)  # F_qs,max / W
    1.75
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
    quasi_static: dict[str, Any] | None = None
    warnings: tuple[str, ...] = ()

    @property
    def stiffness_jump_factor(self) -> float:
        """F_qs,max / W: the peak quasi-static mesh force over W, the force overshoot at the
        jumps of k(t) present at any speed (1 for a smooth k(t)); NaN without a reference.
        The peak force ratio of every speed is the dynamic factor times this."""
        qs = self.quasi_static
        return math.nan if qs is None else float(qs["peak_force_ratio"])

    @property
    def plot(self) -> SweepPlots:
        """The sweep's figures: ``sweep.plot.response(ax=None)``, ``sweep.plot.waterfall(ax=None)``
        (each returns the Figure; :class:`.SweepPlots`)."""
        return SweepPlots(self)

    def to_dict(self) -> dict[str, Any]:
        """The sweep's summary, what sweep.json holds before the scene's figures are added
        (:func:`gear_dyn.analysis.sweep.types.summarize_sweep`).

        Returns
        -------
        dict
            JSON-ready (plain numbers, lists, strings); SI units in the key names, speeds in
            rpm (``speed_range_rpm``, ``curves[direction]["max_dynamic_factor_speed_rpm"]``).

        See Also
        --------
        :meth:`~gear_dyn.analysis.sweep.types.SweepResult.rows` : One row per speed.

        Examples
        --------
        >>> import gear_dyn as gd
        >>> sweep = gd.sweep_scene(gd.load_scene("helicopter_tail"), "3000 rpm:3600 rpm:3")
        >>> [round(s) for s in sweep.to_dict()["speed_range_rpm"]]
        [3000, 3600]
        """
        return summarize_sweep(self)

    def rows(self) -> list[dict[str, float]]:
        """One row per (direction, speed), the rows of sweep.csv
        (:func:`gear_dyn.analysis.sweep.types.sweep_columns`: ``direction_down`` 0 = up,
        1 = down; ``dynamic_factor`` is K_dyn, ``peak_force_ratio`` F_max / W).

        Returns
        -------
        list of dict
            Plain floats; SI units (and rpm) in the key names.

        See Also
        --------
        :meth:`~gear_dyn.analysis.sweep.types.SweepResult.to_csv` : Writes them.

        Examples
        --------
        >>> import gear_dyn as gd
        >>> sweep = gd.sweep_scene(gd.load_scene("helicopter_tail"), "3000 rpm:3600 rpm:3")
        >>> [round(row["speed_rpm"]) for row in sweep.rows()]
        [3000, 3300, 3600]
        """
        from gear_dyn.io import column_rows

        return column_rows(sweep_columns(self))

    def to_csv(self, path: str | Path, extra: Mapping[str, Any] | None = None) -> Path:
        """Write :meth:`rows` as CSV (sweep.csv) atomically, the columns of ``extra`` (one
        value per row, e.g. the CLI's ``iso_6336_kv``) after them.

        Parameters
        ----------
        path : str or Path
            The file to write (replaced if it exists).
        extra : mapping of str to array or None
            More columns, each as long as :meth:`rows`.

        Returns
        -------
        Path
            The file written.

        See Also
        --------
        :meth:`~gear_dyn.analysis.sweep.types.SweepResult.to_dict` : The same for JSON.

        Examples
        --------
        >>> import tempfile
        >>> from pathlib import Path
        >>> import gear_dyn as gd
        >>> sweep = gd.sweep_scene(gd.load_scene("helicopter_tail"), "3000 rpm:3600 rpm:3")
        >>> with tempfile.TemporaryDirectory() as folder:
        ...     lines = sweep.to_csv(Path(folder) / "sweep.csv").read_text().splitlines()
        >>> len(lines)  # the header and one line per speed
        4
        """
        from gear_dyn.io import write_csv

        return write_csv(path, {**sweep_columns(self), **(extra or {})})

    def peak(self, quantity: str = "dynamic_factor") -> Peak:
        """The largest value of ``quantity`` over all curves: a
        :class:`~gear_dyn.analysis.sweep.types.Peak` (value, pinion
        speed in rad/s, direction; ``.speed_rpm`` in rpm), which unpacks as the 3-tuple
        ``value, speed, direction`` it used to be. NaN where no speed has a finite value; of
        two equal peaks the first curve's (``up``).

        Parameters
        ----------
        quantity : {"dynamic_factor", "peak_force_ratio", "rms_dte", "ptp_dte"}
            K_dyn (default), the peak force over the static load F_max / W, or the RMS or
            peak-to-peak DTE in m.

        Raises
        ------
        InputError
            An unknown quantity.

        Returns
        -------
        Peak
            ``value`` (of the quantity's unit), ``speed`` in rad/s, ``direction``.

        See Also
        --------
        :meth:`~gear_dyn.analysis.sweep.types.SweepResult.curve`
            One direction's values at every speed.

        Examples
        --------
        >>> import gear_dyn as gd
        >>> sweep = gd.sweep_scene(gd.load_scene("helicopter_tail"), "3000 rpm:3600 rpm:3")
        >>> value, speed, direction = sweep.peak()
        >>> round(value, 3), direction
        (1.195, 'up')
        >>> round(sweep.peak("peak_force_ratio").speed_rpm)
        3600
        """
        _check_quantity(quantity)
        best = NO_PEAK
        for c in self.curves:
            p = c.peak(quantity)
            if math.isfinite(p.value) and not best.value >= p.value:
                best = p
        return best

    def __repr__(self) -> str:
        speeds = np.concatenate([c.speed for c in self.curves]) / RPM
        dirs = "/".join(c.direction for c in self.curves)
        value, speed, direction = self.peak()
        peak = (f"max dynamic factor {value:.4f} at {speed / RPM:.0f} rpm ({direction})"
                if math.isfinite(value) else "no finite dynamic factor")
        if math.isfinite(self.stiffness_jump_factor):
            peak += f", stiffness-jump factor {self.stiffness_jump_factor:.4f}"
        return (f"SweepResult({self.scene_name!r}: {len(self.curves[0].speed)} speeds "
                f"{speeds.min():.0f}-{speeds.max():.0f} rpm, {dirs}, {self.options.method}\n"
                f"  {peak}; f_n = {self.natural_frequency:.1f} Hz; {self.run_time_s:.3g} s)")

    def curve(self, direction: str) -> SweepCurve:
        """The curve of ``direction`` (``up`` or ``down``).

        Parameters
        ----------
        direction : {"up", "down"}
            The sweep direction.

        Returns
        -------
        SweepCurve
            Speeds (rad/s), dynamic factors, peak force ratios, DTE figures (m), spectra.

        Raises
        ------
        InputError
            No such direction in this sweep.

        See Also
        --------
        :meth:`~gear_dyn.analysis.sweep.types.SweepResult.peak` : The largest value over all curves.

        Examples
        --------
        >>> import gear_dyn as gd
        >>> sweep = gd.sweep_scene(gd.load_scene("helicopter_tail"), "3000 rpm:3600 rpm:3")
        >>> sweep.curve("up").speed.round(2)  # rad/s
        array([314.16, 345.58, 376.99])
        """
        for c in self.curves:
            if c.direction == direction:
                return c
        raise InputError(f"sweep direction {direction!r} not in this result; available: "
                         f"{', '.join(c.direction for c in self.curves)}")


# ------------------------------------------------------------------ tables and summaries
# sweep.csv, spectra.csv and sweep.json of a sweep (SweepResult.rows, to_dict): CSV columns,
# ranges, jumps, hysteresis. The dynamic factor and the figures beside it are those of a run
# (gear_dyn.analysis.dynamic_factor); the jumps are found from the orbits when the sweep runs
# (gear_dyn.analysis.sweep.orbit_jumps) and only listed here.

def sweep_columns(result: SweepResult) -> dict[str, Any]:
    """CSV columns: one row per (direction, speed); direction coded 0 = up, 1 = down;
    ``dynamic_factor`` is K_dyn, ``peak_force_ratio`` F_max / W."""
    fn = result.natural_frequency
    parts = []
    for c in result.curves:
        n = c.speed.size
        nan = np.full(n, np.nan)  # a curve stacked without Lyapunov exponents (made by hand)
        parts.append({
            "direction_down": np.full(n, float(c.direction == "down")), "speed_rpm": c.speed / RPM,
            "speed_rad_s": c.speed, "mesh_frequency_hz": c.mesh_frequency,
            "frequency_ratio": c.mesh_frequency / fn, "dynamic_factor": c.dynamic_factor,
            "peak_force_ratio": c.peak_force_ratio, "rms_dte_m": c.rms_dte,
            "ptp_dte_m": c.ptp_dte, "mean_dte_m": c.mean_dte,
            "max_floquet_modulus": c.spectral_radius, "stable": c.stable,
            "periodic": c.periodic, "orbit_periods": c.orbit_periods,
            "separation_share": c.separation, "backside_share": c.backside,
            "newton_iterations": c.iterations,
            "lyapunov_1_s": c.lyapunov if c.lyapunov.size == n else nan,
            "lyapunov_error_1_s": c.lyapunov_error if c.lyapunov_error.size == n else nan})
    return {k: np.concatenate([np.asarray(p[k], dtype=float) for p in parts]) for k in parts[0]}


def spectra_columns(result: SweepResult) -> dict[str, Any]:
    """spectra.csv columns: one row per (direction, speed), as :func:`sweep_columns`: direction
    coded 0 = up, 1 = down, the speed in rpm and the DTE amplitude (m) of each mesh order."""
    curves = result.curves
    cols = {"direction_down": np.concatenate([np.full(c.speed.size, float(c.direction == "down"))
                                              for c in curves]),
            "speed_rpm": np.concatenate([c.speed / RPM for c in curves])}
    for j, o in enumerate(result.orders):
        cols[f"dte_amp_m_order_{o:g}"] = np.concatenate([c.spectrum[:, j] for c in curves])
    return cols


def speed_ranges(speed: FloatArray, mask: NDArray[np.bool_]) -> list[list[float]]:
    """Contiguous ranges of the speeds ``speed`` (rad/s) where ``mask`` holds: [first, last]
    in rpm, sorted."""
    order = np.argsort(speed)
    s = speed[order] / RPM
    edges = np.diff(np.concatenate([[0], mask[order].astype(int), [0]]))  # +1 start, -1 past end
    return [[float(s[i]), float(s[j - 1])]
            for i, j in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1), strict=True)]


def periodic_response(curve: SweepCurve) -> NDArray[np.bool_]:
    """Per speed, whether the response is a periodic orbit.

    Steady method: an orbit was found (of one or two mesh periods: status ``periodic``,
    ``settled`` or ``period-2``); not where the status is ``aperiodic`` (no orbit found after
    settling) or ``unstable``. Transient method (status ``transient``): the measured window
    repeats after one mesh period (``SweepCurve.periodic``).
    """
    transient = np.array([s == "transient" for s in curve.status], dtype=bool)
    return np.where(transient, curve.periodic, curve.orbit_periods > 0)


def _not_periodic(curve: SweepCurve) -> NDArray[np.bool_]:
    """Speeds with a bounded response that is not a periodic orbit (parametrically unstable
    speeds of a linear model, NaN, are reported as unstable instead)."""
    unstable = np.array([s == "unstable" for s in curve.status], dtype=bool)
    return ~periodic_response(curve) & ~unstable


def aperiodic_ranges(result: SweepResult) -> list[list[float]]:
    """Speed ranges (rpm) where the response of at least one direction is not periodic.

    Up and down are not compared there: a difference between a periodic orbit and a response
    that is not periodic (or between two such responses) is no hysteresis finding.
    """
    mask = np.zeros(result.curves[0].speed.size, dtype=bool)
    for c in result.curves:
        m = _not_periodic(c)
        mask |= m if c.direction == "up" else m[::-1]
    return speed_ranges(np.sort(result.curves[0].speed), mask)  # the mask is in up order


def hysteresis_ranges(result: SweepResult, rel: float = 0.05) -> list[list[float]]:
    """Speed ranges (rpm) of hysteresis: both the up and the down sweep found a periodic orbit
    there and the two differ by more than ``rel`` in RMS DTE (coexisting orbits).

    Speeds where either direction's response is not periodic are left out
    (:func:`aperiodic_ranges`).
    """
    if len(result.curves) < 2:
        return []
    up, down = result.curve("up"), result.curve("down")
    d = down.rms_dte[::-1]
    ref = np.maximum(np.abs(up.rms_dte), np.abs(d))
    with np.errstate(invalid="ignore"):
        differ = np.abs(up.rms_dte - d) > rel * ref
    both = periodic_response(up) & periodic_response(down)[::-1]
    return speed_ranges(up.speed, differ & np.isfinite(ref) & both)


def jumps(curve: SweepCurve) -> list[dict[str, Any]]:
    """The curve's jumps between neighbouring speeds, as found from its orbits
    (:func:`gear_dyn.analysis.sweep.orbit_jumps.find_jumps`), one dict each (:meth:`Jump.row
    <gear_dyn.analysis.sweep.jump.Jump.row>`: the fields of
    :class:`~gear_dyn.analysis.sweep.jump.Jump`, speeds in rpm)."""
    return [j.row() for j in curve.jumps]


#: f_m / f_n of the resonances marked: super-harmonic (f_n/3, f_n/2), main, parametric
RESONANCES: tuple[tuple[float, str], ...] = ((1 / 3, "f_n/3"), (0.5, "f_n/2"), (1.0, "f_n"),
                                             (2.0, "2f_n"))


def rpm_per_ratio(result: SweepResult) -> float:
    """Pinion speed (rpm) per unit of f_m / f_n."""
    c = result.curves[0]
    return float(result.natural_frequency / (c.mesh_frequency[0] / (c.speed[0] / RPM)))


def resonance_notes(result: SweepResult) -> list[str]:
    """Where the marked resonances lie outside the swept range, one sentence each
    (``f_m = f_n at 7420 rpm, above the range``); empty where f_n is unknown."""
    if not np.isfinite(result.natural_frequency):
        return []
    rpm = np.concatenate([c.speed for c in result.curves]) / RPM
    lo, hi = float(np.min(rpm)), float(np.max(rpm))
    out = []
    for ratio, label in RESONANCES:
        s = ratio * rpm_per_ratio(result)
        if s < lo or s > hi:
            out.append(f"f_m = {label} at {s:.0f} rpm, {'above' if s > hi else 'below'} "
                       "the range")
    return out


def sweep_peaks(result: SweepResult) -> list[tuple[str, float, float]]:
    """(direction, largest dynamic factor K_dyn, its speed in rpm) of each curve with finite
    values."""
    out = []
    for c in result.curves:
        df = np.where(np.isfinite(c.dynamic_factor), c.dynamic_factor, -np.inf)
        if np.any(np.isfinite(c.dynamic_factor)):
            i = int(np.argmax(df))
            out.append((c.direction, float(df[i]), float(c.speed[i] / RPM)))
    return out


def summarize_sweep(result: SweepResult) -> dict[str, Any]:
    """Summary of a sweep for sweep.json (SI units in the key names, speeds in rpm).

    ``dynamic_factor_definition`` and ``stiffness_jump_definition`` state the figures;
    ``stiffness_jump_factor`` (F_qs,max / W) and ``quasi_static`` (the reference run) are the
    sweep's, once; per curve ``max_dynamic_factor`` (K_dyn) and, at the same speed,
    ``max_peak_force_ratio`` (F_max / W = K_dyn x stiffness-jump factor).
    """
    qs = result.quasi_static
    out: dict[str, Any] = {
        "scene": result.scene_name,
        "method": result.options.method,
        "nonlinear": result.nonlinear,
        "natural_frequency_hz": result.natural_frequency,
        "resonance_speed_rpm": rpm_per_ratio(result),  # f_m = f_n
        "resonances_outside_range": resonance_notes(result),
        "static_load_n": result.static_load,
        "dynamic_factor_definition": DYNAMIC_FACTOR_DEFINITION,
        "stiffness_jump_factor": result.stiffness_jump_factor if qs is not None else None,
        "stiffness_jump_definition": STIFFNESS_JUMP_DEFINITION,
        # the reference run's figures (its time is part of the sweep's run_time_s)
        "quasi_static": ({k: v for k, v in qs.items() if k != "run_time_s"}
                         if qs is not None else None),
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
        # both directions periodic and different / either direction not periodic
        "hysteresis_ranges_rpm": hysteresis_ranges(result),
        "aperiodic_ranges_rpm": aperiodic_ranges(result),
        "warnings": list(result.warnings),
    }
    for c in result.curves:
        finite = np.isfinite(c.peak_force_ratio)  # K_dyn is NaN too without a reference
        info: dict[str, Any] = {
            "unstable_ranges_rpm": speed_ranges(c.speed, np.array([s == "unstable"
                                                               for s in c.status])),
            "separation_ranges_rpm": speed_ranges(c.speed, np.nan_to_num(c.separation) > 0),
            "backside_ranges_rpm": speed_ranges(c.speed, np.nan_to_num(c.backside) > 0),
            "aperiodic_ranges_rpm": speed_ranges(c.speed, _not_periodic(c)),
            "period2_ranges_rpm": speed_ranges(c.speed, c.orbit_periods == 2),
            "jumps": jumps(c),
            # what the motion is where it is not period-1 (gear_dyn.analysis.motion)
            "motion": [{"speed_rpm": float(c.speed[i] / RPM), "label": label}
                       for i, label in enumerate(c.motion) if label not in ("", "period-1")],
        }
        if np.any(finite):
            # K_dyn is F_max / W over one constant: both peak at the same speed
            i = int(np.nanargmax(np.where(finite, c.peak_force_ratio, -np.inf)))
            info["max_dynamic_factor"] = float(c.dynamic_factor[i])
            info["max_dynamic_factor_speed_rpm"] = float(c.speed[i] / RPM)
            info["max_peak_force_ratio"] = float(c.peak_force_ratio[i])
            # share of the period with the teeth out of contact at that speed (0: in contact)
            info["max_dynamic_factor_separation_share"] = float(np.nan_to_num(c.separation[i]))
            j = int(np.nanargmax(np.where(finite, c.rms_dte, -np.inf)))
            info["max_rms_dte_m"] = float(c.rms_dte[j])
            info["max_rms_dte_speed_rpm"] = float(c.speed[j] / RPM)
        out["curves"][c.direction] = info
    return out
