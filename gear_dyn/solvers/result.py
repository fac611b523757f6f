"""The result of a simulation: time series, derived outputs, solver statistics.

``Result.plot`` is the one deliberate upward reference of the solver layer (docs/architecture.md):
like pandas' ``DataFrame.plot``, the accessor looks up the plotting module by name when a plot
method is called (``importlib.import_module("gear_dyn.plots.run")``), so importing this module
loads no matplotlib and no plots module, and the layers contract (``lint-imports``, which follows
import statements) stays as it is: the figures remain functions of the plots layer.
``Result.to_dict`` and ``Result.to_csv`` look up :mod:`gear_dyn.analysis.report` (the run
summary and the CSV head's definitions) by name in the same way.
"""

from __future__ import annotations

import importlib
import math
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError
from gear_dyn.solvers.settings import SolverSettings

FloatArray = NDArray[np.float64]

#: the module that draws a Result; looked up by name at call time (never imported on load)
PLOTS_MODULE = "gear_dyn.plots.run"
#: the module that summarises a Result (summary.json, the CSV head); looked up the same way
REPORT_MODULE = "gear_dyn.analysis.report"


class ResultPlots:
    """``result.plot``: the run's figures as methods, each taking ``ax=None`` and returning the
    matplotlib Figure (for notebooks; annotated ``Any`` so that this module never names
    matplotlib, which the FMU's slim copy of the solvers checks). Thin forwards to
    :mod:`gear_dyn.plots.run`, which is imported on the first call (see the module docstring).

    Examples
    --------
    >>> fig = result.plot.spectrum(scale="linear")          # doctest: +SKIP
    >>> fig, ax = plt.subplots(); result.plot.spectrum(ax=ax)  # doctest: +SKIP
    """

    def __init__(self, result: Result) -> None:
        self._result = result

    @staticmethod
    def _plots() -> Any:
        return importlib.import_module(PLOTS_MODULE)

    def time(self, periods: float | None = 10.0, ax: Any = None) -> Any:
        """DTE and mesh force against time (:func:`gear_dyn.plots.run.plot_time_history`).

        ``ax``: None (new figure) or ``rows x cols`` Axes: rows DTE[, elastic part], force;
        cols whole run[, zoom on the last ``periods`` mesh periods; ``periods=None``: no zoom].
        """
        return self._plots().plot_time_history(self._result, periods=periods, ax=ax)

    def spectrum(self, name: str = "dte", harmonics: int | None = None, ax: Any = None,
                 scale: str = "log", floor: float | None = None) -> Any:
        """Amplitude spectrum over the steady window, f_n, mesh harmonics, shaft frequencies and
        sidebands marked, the stated error drawn as a noise floor
        (:func:`gear_dyn.plots.run.plot_spectrum`; ``ax``: None, one Axes, or two for the
        sideband zoom)."""
        return self._plots().plot_spectrum(self._result, name=name, harmonics=harmonics, ax=ax,
                                           scale=scale, floor=floor)


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
        return asdict(self)


@dataclass(frozen=True, eq=False)
class Result:
    """A simulation: time series, derived outputs, solver statistics and provenance.

    Made by :func:`~gear_dyn.analysis.study.simulate` and :func:`~gear_dyn.scene.run_scene`;
    each parameter is kept as the attribute of that name.

    Parameters
    ----------
    t : ndarray
        Uniform output times in s.
    y : ndarray
        States, shape (n_states, n_times).
    state_labels : tuple of str
        Names of the state components (``x`` in m, ``v`` in m/s for the single-DOF model).
    outputs : dict of ndarray
        Derived series from ``model.outputs`` (e.g. ``dte`` in m, ``mesh_force`` in N).
    steady_start : float
        Start of the steady-state window in s (the transient is before it).
    mesh_frequency : float
        Mesh frequency f_m in Hz.
    static_load : float
        W in N.
    stats : SolverStats
        What the integration cost: method, tolerances, counts, wall time in s.
    settings : SolverSettings
        The settings asked for.
    scene : object or None
        The scene that produced the run (if any).
    extra : dict
        Checks and model facts for the summary (JSON-ready); after
        :func:`~gear_dyn.analysis.study.simulate`: ``extra["estimated_error"]["max_rel"]`` (the
        run's estimated max DTE error over the static deflection W/k_m), ``extra["floquet"]``
        and, for explicit Runge-Kutta methods, ``extra["stiffness_check"]``.
    step_maps : tuple of ndarray or None
        Where the solver computed them (methods ``periodic``: the grid steps; ``exact``: its
        pieces, where one ends on the period): the affine maps ``(F, h)``,
        ``y(t_{j+1}) = F[j] y(t_j) + h[j]``, of consecutive intervals covering the first mesh
        period; their product is the one-period (monodromy) map, reused by the Floquet check.
        Else None.

    Attributes
    ----------
    dynamic_factor : float
        K_dyn = F_max / F_qs,max.
    peak_force_ratio : float
        F_max / W over the steady window.
    mean_dte, rms_dte, ptp_dte : float
        Mean, RMS (mean removed) and peak-to-peak DTE over the steady window in m.
    steady : ndarray of bool
        Mask of the steady-state window.
    plot : ResultPlots
        The figures: ``result.plot.time(ax=None)``, ``result.plot.spectrum(ax=None)``.

    See Also
    --------
    :func:`~gear_dyn.analysis.study.simulate` : Makes it from a model.
    :func:`~gear_dyn.scene.run_scene` : Makes it from a scene.
    :func:`~gear_dyn.analysis.report.summarize` : The run's summary.

    Examples
    --------
    >>> from gear_dyn import SDOFModel, rectangular_stiffness, simulate
    >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
    >>> res = simulate(m, 0.2)  # 100 mesh periods at 500 Hz
    >>> res.state_labels, sorted(res.outputs)
    (('x', 'v'), ['dte', 'mesh_force', 'stiffness'])
    >>> res.t.shape, res.y.shape  # 64 samples per mesh period
    ((6401,), (2, 6401))
    >>> res.extra["estimated_error"]["max_rel"] < 1e-6  # error over W / k_m
    True
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
    step_maps: tuple[FloatArray, FloatArray] | None = field(default=None, repr=False)

    @property
    def plot(self) -> ResultPlots:
        """The run's figures: ``result.plot.time(ax=None)``, ``result.plot.spectrum(ax=None)``
        (each returns the Figure; :class:`.ResultPlots`)."""
        return ResultPlots(self)

    def to_dict(self) -> dict[str, Any]:
        """The run summary, what summary.json holds
        (:func:`gear_dyn.analysis.report.summarize`, looked up by name as ``plot`` is).

        Returns
        -------
        dict
            JSON-ready: kinematics, stiffness, dynamic factor, DTE figures, solver cost; SI
            units in the key names (``rms_dte_m``, ``mesh_frequency_hz`` ...).

        See Also
        --------
        :meth:`~gear_dyn.solvers.result.Result.rows` : The time series, one row per sample.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, rectangular_stiffness, simulate
        >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
        >>> simulate(m, 0.2).to_dict()["mesh_frequency_hz"]
        500.0
        """
        summary: dict[str, Any] = importlib.import_module(REPORT_MODULE).summarize(self)
        return summary

    def columns(self) -> dict[str, FloatArray]:
        """The time series as columns: ``t_s``, the states, then the outputs (an output named
        as a state is given once, as the state); SI units. For ``io.write_csv``.

        Returns
        -------
        dict of ndarray
            Columns of equal length over ``t``.

        See Also
        --------
        :meth:`~gear_dyn.solvers.result.Result.rows` : The same as one dict per sample.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, rectangular_stiffness, simulate
        >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
        >>> list(simulate(m, 0.2).columns())
        ['t_s', 'x', 'v', 'dte', 'mesh_force', 'stiffness']
        """
        cols: dict[str, FloatArray] = {"t_s": self.t,
                                       **dict(zip(self.state_labels, self.y, strict=True))}
        for name, arr in self.outputs.items():
            cols.setdefault(name, arr)
        return cols

    def rows(self) -> list[dict[str, float]]:
        """One row per sample, the rows of timeseries.csv (:meth:`columns` as dicts of plain
        floats).

        Returns
        -------
        list of dict
            ``t_s``, states and outputs in SI units.

        See Also
        --------
        :meth:`~gear_dyn.solvers.result.Result.to_csv` : Writes them.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, rectangular_stiffness, simulate
        >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
        >>> rows = simulate(m, 0.2).rows()
        >>> len(rows), list(rows[0])[:3]
        (6401, ['t_s', 'x', 'v'])
        """
        from gear_dyn.io import column_rows

        return column_rows(self.columns())

    def to_csv(self, path: str | Path) -> Path:
        """Write :meth:`rows` as CSV (timeseries.csv) atomically, after ``#`` lines stating the
        units, the DTE and the dynamic factor
        (:func:`gear_dyn.analysis.report.timeseries_comments`).

        Parameters
        ----------
        path : str or Path
            The file to write (replaced if it exists).

        Returns
        -------
        Path
            The file written.

        See Also
        --------
        :meth:`~gear_dyn.solvers.result.Result.to_dict` : The summary, for JSON.

        Examples
        --------
        >>> import tempfile
        >>> from pathlib import Path
        >>> from gear_dyn import SDOFModel, rectangular_stiffness, simulate
        >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
        >>> with tempfile.TemporaryDirectory() as folder:
        ...     lines = simulate(m, 0.2).to_csv(Path(folder) / "t.csv").read_text().splitlines()
        >>> lines[4], len(lines)  # 4 comment lines, the header, 6401 samples
        ('t_s,x,v,dte,mesh_force,stiffness', 6406)
        """
        from gear_dyn.io import write_csv

        head = importlib.import_module(REPORT_MODULE).timeseries_comments(self)
        return write_csv(path, self.columns(), comments=head)

    @property
    def steady(self) -> NDArray[np.bool_]:
        """Boolean mask of the steady-state window."""
        return self.t >= self.steady_start - 1e-12 * max(1.0, abs(self.steady_start))

    def series(self, name: str) -> FloatArray:
        """A state or an output series by name.

        Parameters
        ----------
        name : str
            A state label (``x``, ``v``) or an output (``dte``, ``mesh_force`` ...).

        Returns
        -------
        ndarray
            The series over ``t``, SI units.

        Raises
        ------
        InputError
            No such series in this result.

        See Also
        --------
        :meth:`~gear_dyn.solvers.result.Result.key_figures` : The run's main figures.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, rectangular_stiffness, simulate
        >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
        >>> res = simulate(m, 0.2)  # 100 mesh periods at 500 Hz
        >>> res.series("mesh_force").shape
        (6401,)
        >>> res.series("q")
        Traceback (most recent call last):
        ...
        gear_dyn.errors.InputError: series 'q' not in this result; available: x, v, dte, ...
        """
        if name in self.outputs:
            return self.outputs[name]
        if name in self.state_labels:
            return self.y[self.state_labels.index(name)]
        raise InputError(
            f"series {name!r} not in this result; available: "
            f"{', '.join([*self.state_labels, *self.outputs])}"
        )

    @property
    def peak_force_ratio(self) -> float:
        """Peak dynamic mesh force / W over the steady window, F_max / W (NaN if W = 0)."""
        f = self.outputs["mesh_force"][self.steady]
        return float(np.max(f) / self.static_load) if self.static_load > 0 else math.nan

    @property
    def dynamic_factor(self) -> float:
        """K_dyn = F_max / F_qs,max: the peak dynamic mesh force over the peak quasi-static
        mesh force of the same model (Tamminana, Kahraman & Vijayakar 2007), which tends to 1
        at low speed like ISO 6336-1 K_v: :attr:`peak_force_ratio` over
        ``extra["stiffness_jump_factor"]`` (F_qs,max / W, the stiffness-jump overshoot), which
        :func:`~gear_dyn.analysis.study.simulate` computes
        (:mod:`gear_dyn.analysis.dynamic_factor`). NaN
        without it (a bare run of :func:`gear_dyn.solvers.simulate_bare`)."""
        qs = self.extra.get("stiffness_jump_factor")
        return self.peak_force_ratio / float(qs) if qs else math.nan

    @property
    def mean_dte(self) -> float:
        """Mean dynamic transmission error over the steady window in m."""
        return float(np.mean(self.outputs["dte"][self.steady]))

    @property
    def rms_dte(self) -> float:
        """RMS of the fluctuating DTE (mean removed) over the steady window in m."""
        return float(np.std(self.outputs["dte"][self.steady]))

    @property
    def ptp_dte(self) -> float:
        """Peak-to-peak DTE over the steady window in m."""
        return float(np.ptp(self.outputs["dte"][self.steady]))

    def key_figures(self) -> list[tuple[str, str]]:
        """(name, value with unit) of the figures a notebook shows for this run.

        Returns
        -------
        list of (str, str)
            Method, span, dynamic factor, peak force / W, DTE, estimated error, run time.

        See Also
        --------
        :func:`~gear_dyn.analysis.report.summarize` : Every figure, for JSON.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, rectangular_stiffness, simulate
        >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
        >>> res = simulate(m, 0.2)  # 100 mesh periods at 500 Hz
        >>> res.key_figures()[1]
        ('span', '100 mesh periods at f_m = 500.0 Hz')
        """
        periods = (self.t[-1] - self.t[0]) * self.mesh_frequency
        rows = [("method", f"{self.stats.method} (rtol {self.stats.rtol:g})"),
                ("span", f"{periods:.0f} mesh periods at f_m = {self.mesh_frequency:.1f} Hz")]
        if "dte" in self.outputs and "mesh_force" in self.outputs:
            rows += [("dynamic factor", f"{self.dynamic_factor:.4f}")]
            jump = self.extra.get("stiffness_jump_factor")
            rows.append(("peak force / W", f"{self.peak_force_ratio:.4f}" + (
                f" (stiffness-jump overshoot {jump:.4f} at crawl speed)" if jump else "")))
            iso = self.extra.get("iso_6336_kv")
            if isinstance(iso, dict) and iso.get("k_v") is not None:
                rows.append(("ISO 6336-1 K_v", f"{iso['k_v']:.4f} (N = "
                             f"{iso['resonance_ratio_n']:.3g}, {iso['speed_range']})"))
            rows.append(("RMS / p-p DTE",
                         f"{self.rms_dte * 1e6:.4g} / {self.ptp_dte * 1e6:.4g} um"))
        est = self.extra.get("estimated_error")
        if isinstance(est, dict) and est.get("max_rel") is not None:
            tail = "" if est.get("reproducible", True) else " (trajectory not reproducible)"
            rows.append(("estimated error", f"{est['max_rel']:.2g} of W/k_m{tail}"))
        rows.append(("run time", f"{self.stats.run_time_s:.3g} s"))
        return rows

    def __repr__(self) -> str:
        return "Result(" + ", ".join(f"{k}: {v}" for k, v in self.key_figures()) + ")"

    def _repr_html_(self) -> str:
        from html import escape

        cells = "".join(f"<tr><th style='text-align:left'>{escape(k)}</th><td>{escape(v)}</td>"
                        "</tr>" for k, v in self.key_figures())
        return f"<table><caption>gear_dyn Result</caption>{cells}</table>"


def time_grid(mesh_frequency: float, t_end: float, samples_per_period: int) -> FloatArray:
    """Uniform grid from 0 to ``t_end`` with ``samples_per_period`` points per mesh period."""
    dt = 1.0 / (mesh_frequency * samples_per_period)
    n = int(math.floor(t_end / dt + 1e-9)) + 1
    return np.arange(n, dtype=np.float64) * dt
