"""Work-precision benchmark: error against run time for every solver and tolerance.

Every solve_ivp method (restarted at the switching instants) over a range of ``rtol``, the exact
propagator where it applies, and plain RK45 over the whole span as the hand-written baseline.
Each case records the median run time, the error against :func:`reference_solution` (max and
RMS, relative to the static deflection) and the function evaluations; :func:`recommend` names
the fastest case that meets a target error. The reference is the exact propagator, else DOP853
at rtol 1e-13 whose error is bounded by its difference from a run at rtol 1e-12.
"""

from __future__ import annotations

import math
import statistics
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field, fields, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.accuracy import error_series, relative_errors, rounding_estimate
from gear_dyn.errors import InputError, SolverError
from gear_dyn.models.base import Model
from gear_dyn.solvers import (
    MAX_NFEV,
    SolverSettings,
    exact_applies,
    integrate,
    periodic_map_applies,
    time_grid,
)
from gear_dyn.solvers.ode import solve_once

FloatArray = NDArray[np.float64]

ODE_METHODS: tuple[str, ...] = ("RK45", "DOP853", "Radau", "BDF", "LSODA")
DEFAULT_RTOLS: tuple[float, ...] = (1e-4, 1e-6, 1e-8, 1e-10)


@dataclass(frozen=True)
class Reference:
    """A reference solution on a grid and its own estimated error (relative, max)."""

    t: FloatArray
    y: FloatArray
    kind: str
    own_error: float
    run_time_s: float


@dataclass(frozen=True)
class BenchCase:
    """One benchmarked case: method, mode and tolerance, with its cost and error.

    ``mode`` is ``restart`` (integrated piece by piece between switching instants, as
    ``gear-dyn run`` does), ``once`` (one solve_ivp call over the whole span), ``exact`` or
    ``periodic`` (one period of step maps, reused; linear mesh-periodic models).
    ``status`` is ``ok``, ``failed`` (the solver raised; ``message`` says why) or ``skipped``
    (a looser tolerance of the same method already took longer than the time budget); those
    two keep the defaults, NaN times and errors and zero counts.
    """

    method: str
    mode: str
    rtol: float
    run_time_s: float = math.nan
    run_time_min_s: float = math.nan
    repeats: int = 0
    err_max: float = math.nan
    err_rms: float = math.nan
    nfev: int = 0
    njev: int = 0
    nlu: int = 0
    n_segments: int = 0
    status: str = "ok"
    message: str = ""

    @property
    def label(self) -> str:
        """Short name for plots and tables."""
        if self.mode in ("exact", "periodic"):
            return self.mode
        return self.method if self.mode == "restart" else f"{self.method} (once)"


@dataclass(frozen=True)
class BenchReport:
    """All cases of a benchmark, its reference and what it was run on."""

    name: str
    t_end: float
    n_periods: float
    samples_per_period: int
    reference: Reference
    cases: tuple[BenchCase, ...]
    info: dict[str, Any] = field(default_factory=dict)

    def recommend(self, target: float) -> BenchCase | None:
        """Fastest successful case with ``err_max <= target`` (None if no case meets it)."""
        return recommend(self.cases, target)


def recommend(cases: Sequence[BenchCase], target: float) -> BenchCase | None:
    """Fastest successful case whose max error is at most ``target`` (relative)."""
    ok = [c for c in cases if c.status == "ok" and c.err_max <= target]
    return min(ok, key=lambda c: c.run_time_s) if ok else None


def reference_solution(model: Model, t_grid: FloatArray, max_nfev: int = MAX_NFEV) -> Reference:
    """The reference for ``model`` on ``t_grid`` (module docstring), with its own error
    (``max_nfev``: the work budget of each solve_ivp run,
    :class:`~gear_dyn.solvers.SolverSettings`)."""
    start = time.perf_counter()
    if exact_applies(model):
        y, st = integrate(model, t_grid, SolverSettings(method="exact", estimate_error=False))
        own = rounding_estimate(model, error_series(model, t_grid, y), int(st["n_segments"]))
        return Reference(t_grid, y, "exact propagator", own, time.perf_counter() - start)
    y13, _ = integrate(model, t_grid, SolverSettings(method="DOP853", rtol=1e-13,
                                                     max_nfev=max_nfev))
    run_time = time.perf_counter() - start
    y12, _ = integrate(model, t_grid, SolverSettings(method="DOP853", rtol=1e-12,
                                                     max_nfev=max_nfev))
    own = relative_errors(model, t_grid, y12, y13)[0]
    return Reference(t_grid, y13, "DOP853 restarted at switching instants, rtol 1e-13", own,
                     run_time)


def run_case(model: Model, ref: Reference, method: str, mode: str, rtol: float,
             repeats: int = 3, budget_s: float = math.inf,
             max_nfev: int = MAX_NFEV) -> BenchCase:
    """Time one case (median of ``repeats``; one run only if it exceeds ``budget_s``;
    ``max_nfev``: the work budget of each solve_ivp run)."""
    t_grid = ref.t
    times: list[float] = []
    y: FloatArray | None = None
    st: dict[str, Any] = {}
    try:
        for _ in range(max(1, repeats)):
            start = time.perf_counter()
            if mode == "once":
                y, st = solve_once(model, t_grid, method, rtol)
            else:
                m = mode if mode in ("exact", "periodic") else method
                y, st = integrate(model, t_grid,
                                  SolverSettings(method=m, rtol=rtol, estimate_error=False,
                                                 max_nfev=max_nfev))
            times.append(time.perf_counter() - start)
            if times[-1] > budget_s:
                break
    except (SolverError, InputError) as exc:
        return BenchCase(method, mode, rtol, status="failed", message=" ".join(str(exc).split()))
    assert y is not None
    e_max, e_rms = relative_errors(model, t_grid, y, ref.y)
    return BenchCase(
        method=method, mode=mode, rtol=rtol, run_time_s=statistics.median(times),
        run_time_min_s=min(times), repeats=len(times), err_max=e_max, err_rms=e_rms,
        nfev=int(st.get("nfev", 0)), njev=int(st.get("njev", 0)), nlu=int(st.get("nlu", 0)),
        n_segments=int(st.get("n_segments", 0)),
    )


def run_bench(
    model: Model,
    t_end: float,
    name: str = "model",
    methods: Sequence[str] = ODE_METHODS,
    rtols: Sequence[float] = DEFAULT_RTOLS,
    repeats: int = 3,
    samples_per_period: int = 64,
    budget_s: float = 20.0,
    baseline: bool = True,
    progress: Callable[[int, int], None] | None = None,
    max_nfev: int = MAX_NFEV,
) -> BenchReport:
    """Benchmark every method and tolerance on ``model`` over ``[0, t_end]``.

    Parameters
    ----------
    model : Model
    t_end : float
        Simulated span in s (> 0).
    name : str
        Label for reports.
    methods : sequence of str
        solve_ivp methods (each restarted at switching instants).
    rtols : sequence of float
        Relative tolerances, run from loose to tight.
    repeats : int
        Runs per case; the median time is reported (>= 1).
    samples_per_period : int
        Output points per mesh period.
    budget_s : float
        A case slower than this is run once, and tighter tolerances of the same method are
        skipped (recorded with status ``skipped``).
    baseline : bool
        Also run RK45 once over the whole span (the hand-written baseline).
    progress : callable or None
        Called as ``progress(done, total)`` after the reference and after each case.
    max_nfev : int
        Work budget of each solve_ivp run, right-hand-side evaluations (``--max-nfev`` of
        ``gear-dyn bench``; :class:`~gear_dyn.solvers.settings.SolverSettings`): a case over it
        is recorded as failed with the solver's message, a reference over it raises.

    Raises
    ------
    InputError
        Unknown method, bad span or repeats.
    """
    for m in methods:
        if m not in ODE_METHODS:
            raise InputError(f"bench method {m!r}: valid choices are {', '.join(ODE_METHODS)}")
    if not (isinstance(repeats, int) and repeats >= 1):
        raise InputError(f"repeats = {repeats!r}: valid range >= 1")
    t_grid = time_grid(model.mesh_frequency, t_end, samples_per_period)
    if t_grid.size < 8:
        raise InputError(f"bench span {t_end:.6g} s is too short; valid range >= 8 samples")
    rt = sorted(rtols, reverse=True)
    runs: list[tuple[str, str]] = [(m, "restart") for m in methods]
    if not exact_applies(model) and periodic_map_applies(model, t_grid):
        runs.insert(0, ("periodic", "periodic"))
    if baseline:
        runs.append(("RK45", "once"))
    total = 1 + int(exact_applies(model)) + len(runs) * len(rt)

    def tick(cases: list[BenchCase]) -> None:
        if progress is not None:
            progress(1 + len(cases), total)

    ref = reference_solution(model, t_grid, max_nfev)
    cases: list[BenchCase] = []
    tick(cases)
    if exact_applies(model):
        c = run_case(model, ref, "exact", "exact", 1e-8, repeats)
        if ref.kind == "exact propagator":  # it is its own reference: state its rounding level
            c = replace(c, err_max=ref.own_error, err_rms=ref.own_error,
                        message="error = rounding estimate (the exact run is the reference)")
        cases.append(c)
        tick(cases)
    for method, mode in runs:
        over = False
        for r in rt:
            if over:
                cases.append(BenchCase(method, mode, r, status="skipped",
                                       message=f"looser rtol took > {budget_s:g} s"))
                tick(cases)
                continue
            c = run_case(model, ref, method, mode, r, repeats, budget_s, max_nfev)
            cases.append(c)
            tick(cases)
            over = c.status == "ok" and c.run_time_s > budget_s
    return BenchReport(
        name=name, t_end=float(t_grid[-1]), n_periods=float(t_grid[-1] * model.mesh_frequency),
        samples_per_period=samples_per_period, reference=ref, cases=tuple(cases),
        info={"reference": ref.kind, "reference_error": ref.own_error,
              "reference_run_time_s": ref.run_time_s},
    )


# ------------------------------------------------------------------ tables
#: the CSV columns: the fields of a case (:func:`dataclasses.asdict` of each is a row)
COLUMNS = tuple(f.name for f in fields(BenchCase))


def _g(x: float, digits: int = 3) -> str:
    return "-" if not math.isfinite(x) else f"{x:.{digits}g}"


def markdown_table(report: BenchReport, targets: Sequence[float] = (1e-4, 1e-6, 1e-8)) -> str:
    """The cases and the recommendation per target error, as markdown."""
    lines = [
        f"# Solver benchmark: {report.name}",
        "",
        f"Span {report.t_end:.6g} s ({report.n_periods:.0f} mesh periods), "
        f"{report.samples_per_period} samples per period. Reference: {report.reference.kind} "
        f"(own error {report.reference.own_error:.2g}, relative to the static deflection). "
        "Error = |x - x_ref| / (W/k_m) over the whole grid; time = median of repeats.",
        "",
        "| method | mode | rtol | time (s) | err max | err RMS | nfev | segments | status |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for c in report.cases:
        rtol = "-" if c.mode == "exact" else f"{c.rtol:.0e}"
        status = c.status if not c.message else f"{c.status}: {c.message[:60]}"
        lines.append(
            f"| {c.method} | {c.mode} | {rtol} | {_g(c.run_time_s)} | {_g(c.err_max, 2)} | "
            f"{_g(c.err_rms, 2)} | {c.nfev} | {c.n_segments} | {status} |"
        )
    lines += ["", "## Recommendation", ""]
    lines += recommendation_lines(report, targets)
    return "\n".join(lines) + "\n"


def recommendation_lines(report: BenchReport, targets: Sequence[float]) -> list[str]:
    """One line per target error: the fastest case meeting it, and its speed-up over RK45 once."""
    out = []
    for tgt in targets:
        best = report.recommend(tgt)
        if best is None:
            out.append(f"- max error <= {tgt:.0e}: no case reached it")
            continue
        base = recommend([c for c in report.cases if c.mode == "once"], tgt)
        speed = (f"; {base.run_time_s / best.run_time_s:.3g}x faster than RK45 once over the "
                 f"span ({base.run_time_s:.3g} s)") if base is not None else ""
        rtol = "" if best.mode == "exact" else f" rtol {best.rtol:.0e}"
        line = (f"- max error <= {tgt:.0e}: **{best.label}**{rtol} "
                f"({best.run_time_s:.3g} s, error {best.err_max:.2g}){speed}")
        ode = recommend([c for c in report.cases if c.mode == "restart"], tgt)
        if best.mode == "exact" and ode is not None:
            line += (f"; fastest solve_ivp method: {ode.label} rtol {ode.rtol:.0e} "
                     f"({ode.run_time_s:.3g} s)")
        out.append(line)
    return out


def summary_dict(report: BenchReport, targets: Sequence[float]) -> dict[str, Any]:
    """JSON-ready summary: info, recommendation per target, all cases."""
    rec = {}
    for tgt in targets:
        best = report.recommend(tgt)
        rec[f"{tgt:.0e}"] = None if best is None else {
            "method": best.method, "mode": best.mode, "rtol": best.rtol,
            "run_time_s": best.run_time_s, "err_max": best.err_max}
    return {
        "name": report.name, "t_end_s": report.t_end, "n_periods": report.n_periods,
        "samples_per_period": report.samples_per_period, **report.info,
        "recommendation": rec, "cases": [asdict(c) for c in report.cases],
    }

