"""A run with its honesty figures: simulation, error estimate and stability checks composed.

:func:`gear_dyn.solvers.simulate` returns the bare trajectory; :func:`simulate` here (the public
``gear_dyn.simulate``, and what ``run_scene`` calls) adds to ``Result.extra``:

- ``estimated_error`` when ``settings.estimate_error`` (:func:`~.accuracy.estimate_error`);
- ``floquet``: the Floquet multipliers of a linear mesh-periodic model
  (:func:`~.accuracy.floquet_check`);
- ``stiffness_check`` for explicit Runge-Kutta methods (:func:`~.accuracy.stiffness_check`).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from gear_dyn.analysis.accuracy import EXPLICIT, estimate_error, floquet_check, stiffness_check
from gear_dyn.models.base import Model
from gear_dyn.solvers import Result, SolverSettings
from gear_dyn.solvers import simulate as simulate_bare


def checks(model: Model, result: Result) -> dict[str, Any]:
    """The error estimate and stability checks of ``result`` (a run of ``model``)."""
    out: dict[str, Any] = {}
    if result.settings.estimate_error:
        used = replace(result.settings, method=result.stats.method)
        stats = {"n_segments": result.stats.n_segments}
        out["estimated_error"] = estimate_error(model, result.t, result.y, used, stats)
    floquet = floquet_check(model)
    if floquet is not None:
        out["floquet"] = floquet
    if result.stats.method in EXPLICIT:
        out["stiffness_check"] = stiffness_check(model, result.stats.method)
    return out


def simulate(
    model: Model,
    t_end: float,
    settings: SolverSettings | None = None,
    steady_start: float | None = None,
    scene: Any = None,
) -> Result:
    """Integrate ``model`` from 0 to ``t_end`` and attach the error estimate and checks.

    Parameters are those of :func:`gear_dyn.solvers.simulate`.

    Raises
    ------
    InputError
        Bad time span.
    SolverError
        The integration failed or diverged.
    """
    result = simulate_bare(model, t_end, settings, steady_start, scene)
    result.extra.update(checks(model, result))
    return result
