"""Tolerance study: Monte-Carlo over random manufacturing deviations, exact over the hunting
period, by superposition.

The model is the linear single-DOF mesh equation with piecewise-constant stiffness (``iso6336``,
``rectangular``, constant): ``m x'' + c (x' - e') + k(p) (x - e) = W``. With ``u = x - e`` it
reads ``m u'' + c u' + k(p) u = W - m e''``: the response is linear in the transmission error.
A sample's e(p) is a sum of harmonics of the mesh phase p (cycles) at mesh orders ``q``: the
pinion's shaft orders ``k / z1`` (k = 1..z1/2), the gear's ``k / z2`` and the mesh harmonics
(profile form, and a ``[transmission_error]`` of the scene), each
``Re(C e^{2 pi i q p})`` with a complex amplitude ``C`` (:mod:`gear_dyn.modification.deviations`).

Per speed, the periodic response to each unit harmonic is computed once, exactly: the mesh
period is cut into cells of constant stiffness (at its switches and at the output samples);
in a cell the particular solution of ``u'' + gamma u' + kappa u = Omega^2 e^{i Omega t}`` is
``U e^{i Omega t}``, ``U = Omega^2 / (kappa - Omega^2 + i gamma Omega)``, and the rest follows
the cell's closed-form 2x2 exponential (the solvers' cell maps,
:func:`gear_dyn.solvers.linear_maps.harmonic_orbits`). The response to order q is
quasi-periodic, ``Y(t + T) = e^{2 pi i q} Y(t)`` (T the mesh period): its state at the period
start solves ``(e^{2 pi i q} I - M) Y0 = r`` with ``M`` the monodromy matrix and
``r`` the response over one period from rest. The static load's response (q = 0) is the
sweep's orbit. Every sample is then a linear combination of these responses (one matrix
product per speed for all samples), with no time integration per sample.

Over the hunting period: the pinion's part repeats every z1 mesh cycles, the gear's every z2,
so the force in mesh cycle n at phase s is ``A(n mod z1, s) + B(n mod z2, s)`` (A holds the
load, the mesh harmonics and the pinion's part). Over ``lcm(z1, z2)`` cycles every pair
``(i, j)`` with ``i = j (mod gcd(z1, z2))`` occurs exactly once, so the peak is
``max over s and residues r of (max_{i = r} A + max_{j = r} B)`` and the mean square is formed
from the per-residue means: exact over the hunting period at ``(z1 + z2)`` mesh cycles' cost
instead of ``lcm(z1, z2)``.

Figures per sample and speed: peak mesh force (N), K_dyn = peak force / peak quasi-static force
of the same model without deviations, the reference of ``gear-dyn run`` and of a sweep of the
scene without them (the deviation forcing ``-m e''`` scales with f_m^2: at the quasi-static
speed ``f_m = f_n / 64`` an order q of amplitude C adds about ``(q / 64)^2 k |C|`` to the
force), RMS DTE (m, the
standard deviation of x over the hunting period), and the least mesh force (N; negative: the
teeth would separate, which a linear model does not represent). Over the samples: median,
5 % and 95 % quantiles, mean, and their Monte-Carlo standard errors (docs/tolerance.md).
"""

from __future__ import annotations

import concurrent.futures as cf
import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.dynamic_factor import quasi_static_model_of, quasi_static_reference
from gear_dyn.analysis.executor import (
    SpeedBlock,
    check_speeds,
    check_workers,
    run_blocks,
    speed_blocks,
    task_map,
)
from gear_dyn.analysis.stability import floquet_stable
from gear_dyn.errors import InputError, check_range
from gear_dyn.excitation import HarmonicSignal
from gear_dyn.models.base import MeshModel, Model
from gear_dyn.modification.deviations import PairDeviations
from gear_dyn.solvers import SolverSettings
from gear_dyn.solvers.linear_maps import harmonic_orbits

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]
ModelFactory = Callable[[float], Model]

#: the figures of a tolerance study: name -> (unit, what)
METRICS = {
    "peak_force": ("N", "peak dynamic mesh force over the hunting period"),
    "k_dyn": ("", "K_dyn = peak force / peak quasi-static force of the model without "
                  "deviations (Tamminana, Kahraman & Vijayakar 2007)"),
    "rms_dte": ("m", "RMS of the dynamic transmission error about its mean, over the hunting "
                     "period"),
    "min_force": ("N", "least mesh force over the hunting period (< 0: the teeth separate)"),
}
#: quantiles of the band
BAND = (0.05, 0.5, 0.95)
#: speeds per task
BLOCK = 10
#: samples combined at once (bounds the memory of a task, not its result)
CHUNK = 256


@dataclass(frozen=True)
class Coefficients:
    """Complex amplitudes ``a - i b`` of every sample's harmonics (m), rows = samples.

    Attributes
    ----------
    pinion : ndarray (N, z1 // 2)
        Pinion shaft orders 1..z1/2.
    gear : ndarray (N, z2 // 2)
        Gear shaft orders 1..z2/2.
    mesh : ndarray (N, H)
        Mesh harmonics 1..H.
    """

    pinion: ComplexArray
    gear: ComplexArray
    mesh: ComplexArray

    @classmethod
    def of(cls, samples: Sequence[PairDeviations], base: HarmonicSignal | None = None
           ) -> Coefficients:
        """The amplitudes of ``samples``, plus the mesh harmonics ``base`` (the model's own
        transmission error, the same in every sample)."""
        rows: list[list[ComplexArray]] = [[], [], []]
        h = max(1, 0 if base is None else base.cos.size)
        for dev in samples:
            for part, sig in zip(rows, dev.signals(), strict=True):
                c = sig.cos - 1j * sig.sin
                if sig.period == 1:
                    c = np.pad(c, (0, h - c.size))
                    if base is not None:
                        c = c + np.pad(base.cos - 1j * base.sin, (0, h - base.cos.size))
                part.append(c)
        return cls(*(np.array(r, dtype=complex) for r in rows))

    def without_deviations(self, base: HarmonicSignal | None) -> Coefficients:
        """One sample of the same shape with no deviations (``base`` only)."""
        mesh = np.zeros((1, self.mesh.shape[1]), dtype=complex)
        if base is not None:
            mesh[0, :base.cos.size] = base.cos - 1j * base.sin
        return Coefficients(np.zeros((1, self.pinion.shape[1]), dtype=complex),
                            np.zeros((1, self.gear.shape[1]), dtype=complex), mesh)

    @property
    def n(self) -> int:
        """Number of samples."""
        return int(self.pinion.shape[0])


def _orders(z1: int, z2: int, h: int) -> tuple[FloatArray, FloatArray, FloatArray]:
    return np.arange(1, z1 // 2 + 1) / z1, np.arange(1, z2 // 2 + 1) / z2, np.arange(1.0, h + 1)


@dataclass(frozen=True)
class UnitResponses:
    """Periodic responses of a linear model over one mesh period, at ``spp`` samples.

    Attributes
    ----------
    force_w, dte_w : ndarray (spp,)
        Mesh force (N) and DTE x (m) under the static load alone (the mesh-periodic orbit).
    force_q, dte_q : ndarray (Q, spp), complex
        Responses to the unit transmission error ``e = e^{2 pi i q p}`` at each order q:
        ``Re(C force_q)`` is the force of ``e = Re(C e^{2 pi i q p})`` in the first mesh
        period; in period n it is ``Re(C e^{2 pi i q n} force_q)``.
    start_w : ndarray (2,)
        State [x, v] (m, m/s) of the load's orbit at t = 0.
    start_q : ndarray (2, Q), complex
        State [x, v] of each unit response at t = 0 (``x = u + e``).
    rho : float
        Spectral radius of the monodromy matrix (> 1: unstable, no periodic response).
    """

    force_w: FloatArray
    dte_w: FloatArray
    force_q: ComplexArray
    dte_q: ComplexArray
    start_w: FloatArray
    start_q: ComplexArray
    rho: float


def unit_responses(model: MeshModel, orders: FloatArray, spp: int) -> UnitResponses:
    """Periodic responses of ``model`` (linear, piecewise-constant stiffness, no transmission
    error) to the static load and to a unit transmission error at each of ``orders`` (mesh
    orders), over one mesh period at ``spp`` samples (phases ``j / spp`` after ``phase0``).

    Raises
    ------
    InputError
        The model is not linear with piecewise-constant stiffness, or has a transmission error.
    """
    orbit = harmonic_orbits(model, orders, spp)
    if orbit is None:
        raise InputError("tolerance study: the model must be the linear single-DOF model with "
                         "piecewise-constant stiffness (stiffness method iso6336 or rectangular), "
                         "no backlash")
    y0, ys, z0, zs, rho = orbit
    fm = model.mesh_frequency
    om = 2 * math.pi * np.asarray(orders, dtype=float) * fm
    t = np.arange(spp) / (spp * fm)
    k_s = np.asarray(model.stiffness(model.phase(t)), dtype=float)
    c_m = model.damping
    shift = np.exp(2j * math.pi * np.asarray(orders, dtype=float) * model.phase0)[:, None]
    e_s = np.exp(1j * om[:, None] * t[None, :])
    force_q = (k_s[None, :] * zs[0] + c_m * zs[1]) * shift
    dte_q = (zs[0] + e_s) * shift
    start_q = (z0 + np.stack([np.ones(om.size), 1j * om])) * shift[:, 0]
    return UnitResponses(k_s * ys[0] + c_m * ys[1], ys[0].copy(), force_q, dte_q, y0.copy(),
                         start_q, rho)


def _combine(amp: ComplexArray, resp: ComplexArray, z: int) -> FloatArray:
    """``Re(sum_k amp[m, k] resp[k, s] e^{2 pi i k n / z})`` for n = 0..z-1: (N, z, spp)."""
    n_s = resp.shape[-1]
    if amp.shape[1] == 0:
        return np.zeros((amp.shape[0], z, n_s))
    k = np.arange(1, amp.shape[1] + 1)
    lam = np.exp(2j * math.pi * np.outer(k, np.arange(z)) / z)  # (K, z)
    basis = (lam[:, :, None] * resp[:, None, :]).reshape(k.size, -1)
    out = amp.real @ basis.real - amp.imag @ basis.imag
    return out.reshape(amp.shape[0], z, n_s)


def _residues(a: FloatArray, g: int) -> FloatArray:
    """(N, z, spp) -> (N, z/g, g, spp): axis 2 the residue ``i mod g``."""
    n, z, s = a.shape
    return a.reshape(n, z // g, g, s)


def sample_figures(model: MeshModel, coef: Coefficients, z1: int, z2: int, spp: int
                   ) -> dict[str, FloatArray]:
    """Per-sample figures of ``model`` (at its speed) over the hunting period: ``peak_force``,
    ``min_force`` (N), ``rms_dte``, ``mean_dte`` (m), each (N,); ``rho`` (spectral radius)."""
    o1, o2, om = _orders(z1, z2, coef.mesh.shape[1])
    orders = np.concatenate([o1, o2, om])
    r = unit_responses(model, orders, spp)
    f_w, x_w, f_q, x_q = r.force_w, r.dte_w, r.force_q, r.dte_q
    n1, n2 = o1.size, o2.size
    g = math.gcd(z1, z2)
    out: dict[str, FloatArray] = {"rho": np.full(coef.n, r.rho)}
    if not floquet_stable(r.rho):  # no periodic response: the parametric instability of k(t)
        for name in ("peak_force", "min_force", "rms_dte", "mean_dte"):
            out[name] = np.full(coef.n, np.nan)
        return out
    for name in ("peak_force", "min_force", "rms_dte", "mean_dte"):
        out[name] = np.empty(coef.n)
    for lo in range(0, coef.n, CHUNK):  # memory: CHUNK x (z1 + z2) x spp per array
        rows = slice(lo, min(lo + CHUNK, coef.n))
        c1, c2, cm = coef.pinion[rows], coef.gear[rows], coef.mesh[rows]
        for what, w, q in (("force", f_w, f_q), ("dte", x_w, x_q)):
            mesh = cm.real @ q[n1 + n2:].real - cm.imag @ q[n1 + n2:].imag  # (n, spp)
            a = _combine(c1, q[:n1], z1) + (w[None, :] + mesh)[:, None, :]
            b = _combine(c2, q[n1:n1 + n2], z2)
            ar, br = _residues(a, g), _residues(b, g)
            if what == "force":
                out["peak_force"][rows] = np.max(ar.max(axis=1) + br.max(axis=1), axis=(1, 2))
                out["min_force"][rows] = np.min(ar.min(axis=1) + br.min(axis=1), axis=(1, 2))
            else:
                am, bm = ar.mean(axis=1), br.mean(axis=1)
                mean = np.mean(am + bm, axis=(1, 2))
                sq = np.mean((ar**2).mean(axis=1) + (br**2).mean(axis=1) + 2 * am * bm,
                             axis=(1, 2))
                out["mean_dte"][rows] = mean
                out["rms_dte"][rows] = np.sqrt(np.maximum(sq - mean**2, 0.0))
    return out


@dataclass(frozen=True)
class _Job:
    """What the study does at each speed (the job of its :class:`.executor.SpeedBlock`)."""

    factory: ModelFactory
    coef: Coefficients
    z1: int
    z2: int
    spp: int


def _run_task(task: SpeedBlock[_Job]) -> tuple[list[dict[str, FloatArray]], None]:
    """One block of speeds, every sample (the worker function; picklable)."""
    job, out = task.job, []
    for s in task.speeds:
        model = cast(MeshModel, _bare(job.factory(s)))
        out.append(sample_figures(model, job.coef, job.z1, job.z2, job.spp))
    return out, None


def _bare(model: Model) -> Model:
    """``model`` without its transmission error (its mesh harmonics go into the samples)."""
    if getattr(model, "transmission_error", None) is None:
        return model
    return cast(Model, replace(cast(Any, model), transmission_error=None))


def quantile_stderr(x: FloatArray, q: float) -> FloatArray:
    """Monte-Carlo standard error of the ``q`` quantile of the samples ``x`` (axis 0),
    distribution-free: half the distance between the order statistics at ranks
    ``N q -+ sqrt(N q (1 - q))`` (one standard deviation of the binomial count below the
    quantile: the distribution-free confidence interval of a quantile, David & Nagaraja
    2003); NaN for fewer than two samples."""
    n = x.shape[0]
    if n < 2:  # one sample states no spread
        return np.full(x.shape[1:], np.nan)
    xs = np.sort(x, axis=0)
    half = math.sqrt(n * q * (1 - q))
    lo = int(np.clip(math.floor(n * q - half), 0, n - 1))
    hi = int(np.clip(math.ceil(n * q + half), 0, n - 1))
    return cast(FloatArray, 0.5 * (xs[hi] - xs[lo]))


@dataclass(frozen=True)
class ToleranceResult:
    """A tolerance study: every sample's figures at every speed, and their distribution.

    Attributes
    ----------
    speeds : ndarray (S,)
        Pinion speeds in rad/s.
    mesh_frequency : ndarray (S,)
        f_m in Hz.
    values : dict
        ``peak_force`` (N), ``k_dyn``, ``rms_dte`` (m), ``min_force`` (N): arrays (N, S).
    seeds : list
        The seed of every sample (as given to
        :func:`~gear_dyn.modification.deviations.sample_deviations`).
    static_load : float
        W in N.
    quasi_static_peak_ratio : float
        F_qs,max / W of the model without deviations (K_dyn's reference).
    baseline : dict
        The same figures without deviations, arrays (S,).
    natural_frequency : float
        f_n in Hz.
    hunting_period : int
        lcm(z1, z2) mesh cycles, the period every figure covers.
    executor : str
        Where the blocks ran.
    run_time_s : float
        Wall time in s.
    """

    speeds: FloatArray
    mesh_frequency: FloatArray
    values: dict[str, FloatArray]
    seeds: list[Any]
    static_load: float
    quasi_static_peak_ratio: float
    baseline: dict[str, FloatArray]
    natural_frequency: float
    hunting_period: int
    executor: str = "serial"
    run_time_s: float = math.nan
    name: str = ""
    notes: tuple[str, ...] = field(default=())

    @property
    def n_samples(self) -> int:
        """Number of Monte-Carlo samples N."""
        return int(self.values["peak_force"].shape[0])

    def stats(self, metric: str) -> dict[str, FloatArray]:
        """Distribution of ``metric`` over the samples at every speed: ``p05``, ``median``,
        ``p95``, ``mean``, ``std`` and the standard errors ``*_stderr`` (arrays (S,)).

        Raises
        ------
        InputError
            Unknown metric.
        """
        if metric not in self.values:
            raise InputError(f"metric = {metric!r}: valid choices are {', '.join(self.values)}")
        x = self.values[metric]
        n = x.shape[0]
        out: dict[str, FloatArray] = {}
        for q, name in zip(BAND, ("p05", "median", "p95"), strict=True):
            out[name] = np.quantile(x, q, axis=0)
            out[f"{name}_stderr"] = quantile_stderr(x, q)
        out["mean"] = x.mean(axis=0)
        out["std"] = x.std(axis=0, ddof=1) if n > 1 else np.full(x.shape[1], np.nan)
        out["mean_stderr"] = out["std"] / math.sqrt(n)
        return out

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary, what tolerance.json holds before the CLI adds ISO K_v:
        definitions, the band of every figure against speed, with the Monte-Carlo standard
        errors (SI units in the names; speeds also in rpm).

        Returns
        -------
        dict
            Plain numbers, lists and strings.

        See Also
        --------
        :meth:`~gear_dyn.analysis.tolerance.ToleranceResult.rows` : One row per speed.
        """
        rpm = self.speeds * 60 / (2 * math.pi)
        out: dict[str, Any] = {
            "scene": self.name, "n_samples": self.n_samples, "n_speeds": int(self.speeds.size),
            "speed_rad_per_s": self.speeds.tolist(), "speed_rpm": rpm.tolist(),
            "mesh_frequency_hz": self.mesh_frequency.tolist(),
            "natural_frequency_hz": self.natural_frequency,
            "static_load_n": self.static_load,
            "quasi_static_peak_ratio": self.quasi_static_peak_ratio,
            "hunting_period_mesh_cycles": self.hunting_period,
            "seeds": self.seeds, "executor": self.executor, "run_time_s": self.run_time_s,
            "method": "exact periodic response over the hunting period by superposition of "
                      "unit-harmonic responses (linear model, piecewise-constant stiffness)",
            "standard_error": "mean: std / sqrt(N); quantiles: half the spread of the order "
                              "statistics at N q -+ sqrt(N q (1 - q))",
            "notes": list(self.notes), "metrics": {},
        }
        for name, (unit, what) in METRICS.items():
            st = self.stats(name)
            out["metrics"][name] = {"unit": unit, "definition": what,
                                    "baseline_no_deviations": self.baseline[name].tolist(),
                                    **{k: v.tolist() for k, v in st.items()}}
        return out

    def columns(self) -> dict[str, FloatArray]:
        """The table as columns (one value per speed): the band and standard errors of every
        figure, SI units in the names. For ``io.write_csv``."""
        cols: dict[str, FloatArray] = {"speed_rpm": self.speeds * 60 / (2 * math.pi),
                                       "speed_rad_per_s": self.speeds,
                                       "mesh_frequency_hz": self.mesh_frequency}
        for name, (unit, _what) in METRICS.items():
            suffix = f"_{unit.lower()}" if unit else ""
            st = self.stats(name)
            for k in ("p05", "median", "p95", "mean", "mean_stderr", "median_stderr"):
                cols[f"{name}_{k}{suffix}"] = st[k]
            cols[f"{name}_baseline{suffix}"] = self.baseline[name]
        return cols

    def rows(self) -> list[dict[str, float]]:
        """One row per speed, the rows of tolerance.csv: the band and standard errors of
        every figure (:meth:`columns` as dicts of plain floats).

        Returns
        -------
        list of dict
            SI units (and rpm) in the key names.

        See Also
        --------
        :meth:`~gear_dyn.analysis.tolerance.ToleranceResult.to_csv` : Writes them.
        """
        from gear_dyn.io import column_rows

        return column_rows(self.columns())

    def to_csv(self, path: str | Path, extra: Mapping[str, Any] | None = None) -> Path:
        """Write :meth:`rows` as CSV (tolerance.csv) atomically, the columns of ``extra`` (one
        value per speed, e.g. the CLI's ``iso_6336_kv``) after them.

        Parameters
        ----------
        path : str or Path
            The file to write (replaced if it exists).
        extra : mapping of str to array or None
            More columns, one value per speed each.

        Returns
        -------
        Path
            The file written.
        """
        from gear_dyn.io import write_csv

        return write_csv(path, {**self.columns(), **(extra or {})})

    def plot(self, ax: Any = None) -> Any:
        """The band figure (:func:`gear_dyn.plots.tolerance.plot_tolerance`); returns the
        Figure."""
        import importlib

        return importlib.import_module("gear_dyn.plots.tolerance").plot_tolerance(self, ax=ax)


def tolerance_study(
    factory: ModelFactory,
    speeds: Sequence[float] | FloatArray,
    samples: Sequence[PairDeviations],
    *,
    seeds: Sequence[Any] | None = None,
    settings: SolverSettings | None = None,
    samples_per_period: int | None = None,
    workers: int | None = None,
    executor: cf.Executor | None = None,
    name: str = "",
) -> ToleranceResult:
    """Monte-Carlo tolerance study of a linear single-DOF model over pinion speeds.

    Parameters
    ----------
    factory : callable
        ``factory(speed) -> Model`` (speed in rad/s), the linear single-DOF model with
        piecewise-constant stiffness, without the deviations (its own mesh-harmonic
        transmission error, if any, is added to every sample); picklable for ``workers``
        (e.g. :class:`gear_dyn.scene.sweep.SceneModels`).
    speeds : sequence of float
        Pinion speeds in rad/s (> 0); sorted, duplicates removed.
    samples : sequence of PairDeviations
        The deviations of every sample (N >= 1), e.g. from
        :func:`gear_dyn.modification.deviations.sample_deviations` with their own seeds.
    seeds : sequence or None
        The samples' seeds, recorded in the result.
    settings : SolverSettings or None
        The quasi-static reference's settings (default: the defaults); its
        ``samples_per_period`` is the output sampling unless ``samples_per_period`` is given.
    samples_per_period : int or None
        Output samples per mesh period (4..4096) where the peak is taken.
    workers, executor
        Where the blocks of speeds run (:func:`gear_dyn.analysis.executor.task_map`); the
        numbers do not depend on it.
    name : str
        Name stored in the result.

    Returns
    -------
    ToleranceResult

    Raises
    ------
    InputError
        No samples, samples of another pair, bad speeds or workers, a model the method does not
        cover (backlash, smooth stiffness, not single-DOF).

    Examples
    --------
    >>> import gear_dyn as gd
    >>> from gear_dyn.scene.tolerance import tolerance_scene
    >>> res = tolerance_scene(gd.load_scene("helicopter_tail"), "3000 rpm:3400 rpm:3",
    ...                       samples=8, grade=6)
    >>> res.values["k_dyn"].shape
    (8, 3)
    """
    start = time.perf_counter()
    check_workers(workers, executor)
    if not samples:
        raise InputError("tolerance study: samples: none given (N >= 1)")
    z1, z2 = samples[0].z1, samples[0].z2
    if any((d.z1, d.z2) != (z1, z2) for d in samples):
        raise InputError("tolerance study: samples of different tooth counts")
    sp = check_speeds(speeds, "tolerance study")
    settings = settings or SolverSettings()
    spp = int(samples_per_period or settings.samples_per_period)
    check_range("samples_per_period", spp, "", low=4, high=4096)
    model0 = factory(float(sp[0]))
    if not (model0.is_linear and isinstance(model0, MeshModel)):
        raise InputError("tolerance study: the model must be the linear single-DOF model "
                         f"(no backlash); got {type(model0).__name__}"
                         + (" with backlash" if model0.backlash is not None else ""))
    base_te = getattr(model0, "transmission_error", None)
    if base_te is not None and not (isinstance(base_te, HarmonicSignal) and base_te.period == 1):
        raise InputError("tolerance study: the model's own transmission error must be mesh "
                         "harmonics ([transmission_error]); leave [deviations] to the study")
    coef = Coefficients.of(samples, base_te)
    zero = coef.without_deviations(base_te)
    blocks = speed_blocks(sp, ("up",), BLOCK)
    with task_map(workers, executor) as (run_map, label):
        done = run_blocks(run_map, _run_task, blocks, _Job(factory, coef, z1, z2, spp), None,
                          chained=False)["up"]
        base_done = run_blocks(run_map, _run_task, blocks, _Job(factory, zero, z1, z2, spp),
                               None, chained=False)["up"]
    qs_model = quasi_static_model_of(factory, float(sp[0]), model0)
    if qs_model is None:
        raise InputError("tolerance study: the model states no natural frequency (K_dyn needs "
                         "its quasi-static reference)")
    qs_ratio = float(quasi_static_reference(qs_model, settings)["peak_force_ratio"])
    w = float(model0.static_load)
    f_qs = qs_ratio * w

    def collect(rows: list[dict[str, FloatArray]]) -> dict[str, FloatArray]:
        peak = np.stack([r["peak_force"] for r in rows], axis=1)
        return {"peak_force": peak, "k_dyn": peak / f_qs if f_qs > 0 else peak * np.nan,
                "rms_dte": np.stack([r["rms_dte"] for r in rows], axis=1),
                "min_force": np.stack([r["min_force"] for r in rows], axis=1)}

    values, base = collect(done), {k: v[0] for k, v in collect(base_done).items()}
    notes = []
    if np.any(values["min_force"] < 0):
        notes.append("some samples' mesh force goes negative: the teeth would separate, which "
                     "the linear model does not represent")
    if np.any(~np.isfinite(values["peak_force"])):
        notes.append("NaN at speeds where k(t) is parametrically unstable (no periodic "
                     "response)")
    fn = model0.natural_frequency
    return ToleranceResult(
        speeds=sp, mesh_frequency=z1 * sp / (2 * math.pi), values=values,
        seeds=list(seeds) if seeds is not None else [None] * len(samples), static_load=w,
        quasi_static_peak_ratio=qs_ratio, baseline=base,
        natural_frequency=math.nan if fn is None else float(fn),
        hunting_period=math.lcm(z1, z2), executor=label,
        run_time_s=time.perf_counter() - start, name=name, notes=tuple(notes))


__all__ = ["METRICS", "Coefficients", "ToleranceResult", "UnitResponses", "quantile_stderr",
           "sample_figures", "tolerance_study", "unit_responses"]
