"""One bare run of a model: the trajectory on a uniform grid and the solver statistics.

Bare: it does no analysis. :func:`gear_dyn.simulate <gear_dyn.analysis.study.simulate>` is the
same run with its error estimate and stability checks, and what the API and ``run_scene`` use.
"""

from __future__ import annotations

import time
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError, SolverError, check_range
from gear_dyn.models.base import Model
from gear_dyn.solvers import settings as limits
from gear_dyn.solvers.integrate import integrate
from gear_dyn.solvers.ode import atol_of
from gear_dyn.solvers.result import Result, SolverStats, time_grid
from gear_dyn.solvers.settings import SolverSettings

FloatArray = NDArray[np.float64]

#: solver statistics that go into :class:`SolverStats` (the rest go to ``Result.extra``)
COUNTED = ("nfev", "njev", "nlu", "n_segments", "method")


def output_grid(model: Model, t_end: float, settings: SolverSettings) -> FloatArray:
    """The uniform output grid of a run from 0 to ``t_end`` (checked against the work limits).

    Raises
    ------
    InputError
        ``t_end`` not > 0, too many samples, or fewer than 8 samples.
    """
    check_range("duration", t_end, "s", low=0.0, low_open=True)
    n_samples = t_end * model.mesh_frequency * settings.samples_per_period
    if n_samples > limits.MAX_SAMPLES:
        raise InputError(
            f"solver.periods x solver.samples_per_period = {n_samples:.4g} output samples "
            f"(duration {t_end:.6g} s at mesh frequency {model.mesh_frequency:.6g} Hz): valid "
            f"range <= {limits.MAX_SAMPLES} samples; simulate fewer periods or fewer samples "
            "per period (solver.periods, --periods on the command line; "
            "solver.samples_per_period)"
        )
    t_grid = time_grid(model.mesh_frequency, t_end, settings.samples_per_period)
    if t_grid.size < 8:
        raise InputError(
            f"duration = {t_end:.6g} s is shorter than a few samples; valid range >= "
            f"{8 / (model.mesh_frequency * settings.samples_per_period):.3g} s"
        )
    return t_grid


def simulate_bare(
    model: Model,
    t_end: float,
    settings: SolverSettings | None = None,
    steady_start: float | None = None,
    scene: Any = None,
) -> Result:
    """Integrate ``model`` from 0 to ``t_end``: trajectory, outputs and solver statistics only.

    No error estimate and no stability check (:func:`~gear_dyn.analysis.study.simulate` adds them).

    Parameters
    ----------
    model : Model
        Any model offering the face of :mod:`gear_dyn.models.base`.
    t_end : float
        End time in s (> 0, at least eight output samples).
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
    t_grid = output_grid(model, t_end, settings)
    if steady_start is None:
        steady_start = 0.5 * t_grid[-1]
    check_range("steady_start", steady_start, "s", low=0.0, high=float(t_grid[-1]))
    start = time.perf_counter()
    y, st = integrate(model, t_grid, settings)
    run_time = time.perf_counter() - start
    # the kernel method's table on the grid, where it has one (the torsional model)
    excitations = st.pop("excitations", None)
    outputs = (model.outputs(t_grid, y) if excitations is None
               else cast(Any, model).outputs(t_grid, y, excitations=excitations))
    for name, arr in outputs.items():
        if not np.all(np.isfinite(arr)):
            raise SolverError(f"output {name!r} is not finite; the response diverges")
    stats = SolverStats(
        method=str(st["method"]), rtol=settings.rtol,
        atol=[float(a) for a in atol_of(model, settings)], nfev=int(st.get("nfev", 0)),
        njev=int(st.get("njev", 0)), nlu=int(st.get("nlu", 0)),
        n_segments=int(st.get("n_segments", 0)), run_time_s=run_time,
    )
    step_maps = st.pop("step_maps", None)  # arrays: on the Result, not in the summary
    extra = {**model.summary_info(), **{k: v for k, v in st.items() if k not in COUNTED}}
    return Result(
        t=t_grid, y=y, state_labels=tuple(model.state_labels), outputs=outputs,
        steady_start=float(steady_start), mesh_frequency=model.mesh_frequency,
        static_load=model.static_load, stats=stats, settings=settings, scene=scene, extra=extra,
        step_maps=step_maps,
    )
