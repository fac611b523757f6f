"""A run with its honesty figures: simulation, error estimate and stability checks composed.

:func:`gear_dyn.solvers.simulate_bare` returns the bare trajectory; :func:`simulate` here (the
public ``gear_dyn.simulate``, and what ``run_scene`` calls) adds to ``Result.extra``:

- ``estimated_error`` when ``settings.estimate_error`` (:func:`~.accuracy.estimate_error`);
- ``floquet``: the largest Floquet multiplier of a linear mesh-periodic model
  (:func:`~.accuracy.floquet_check`; a periodic run's own step maps are reused);
- ``stiffness_check`` for explicit Runge-Kutta methods (:func:`~.accuracy.stiffness_check`);
- ``contact`` (:func:`contact_check`: teeth apart and back-side shares, or a negative force);
- ``orbit`` for nonlinear mesh-periodic models (backlash): :func:`orbit_check`, the period-1
  orbit by shooting from the run's end state and its largest Floquet multiplier, or none;
- ``dynamic_factor``, ``peak_force_ratio``, ``stiffness_jump_factor`` and ``quasi_static``: the
  dynamic factor against a quasi-static run of the same model
  (:mod:`~.dynamic_factor`);
- ``warnings``: one line each, printed by the CLI.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, cast

import numpy as np

from gear_dyn.analysis.accuracy import (
    EXPLICIT,
    estimate_with_reference,
    floquet_check,
    stiffness_check,
)
from gear_dyn.analysis.dynamic_factor import (
    dynamic_factor_figures,
    quasi_static_model,
    quasi_static_reference,
)
from gear_dyn.analysis.newton import NewtonSettings
from gear_dyn.analysis.stability import contact_shares, contact_states, shoot
from gear_dyn.analysis.threads import blas_limited
from gear_dyn.errors import GearDynError
from gear_dyn.models.base import MeshModel, Model
from gear_dyn.solvers import Result, SolverSettings, simulate_bare

#: shooting of the orbit check from a run's end state (:func:`orbit_check`)
ORBIT_NEWTON = NewtonSettings(max_iter=12)


def checks(model: Model, result: Result, quasi_static: Model | None = None) -> dict[str, Any]:
    """The error estimate and stability checks of ``result`` (a run of ``model``), and its
    dynamic factor against a quasi-static run of ``quasi_static`` (default: ``model`` at
    :func:`~.dynamic_factor.quasi_static_model`'s mesh frequency)."""
    out: dict[str, Any] = {}
    warnings: list[str] = []
    reference = None  # a periodic run's Gauss-Legendre monodromy matrices, for the Floquet check
    if result.settings.estimate_error:
        used = replace(result.settings, method=result.stats.method)
        stats = {"n_segments": result.stats.n_segments, "step_maps": result.step_maps}
        series = result.outputs.get("dte", result.y[0])
        est, reference = estimate_with_reference(model, result.t, result.y, used, stats,
                                                 result.steady_start, series)
        out["estimated_error"] = est
        if not est.get("reproducible", True):
            warnings.append(est["basis"].split("; ", 1)[-1])
    floquet_model = model
    if int(getattr(model, "excitation_period", 1)) > 1:
        # the multipliers belong to k(t) alone: a shaft-order excitation does not change them
        floquet_model = replace(cast(Any, model), transmission_error=None)
    floquet = floquet_check(floquet_model, result.step_maps, reference,
                            exact=result.stats.method == "exact")
    if floquet is not None:
        out["floquet"] = floquet
        if floquet["advice"]:
            warnings.append(floquet["advice"])
    if result.stats.method in EXPLICIT:
        out["stiffness_check"] = stiffness_check(model, result.stats.method)
        if out["stiffness_check"]["advice"]:
            warnings.append(out["stiffness_check"]["advice"])
    period = int(getattr(model, "excitation_period", 1))
    window = (result.t[-1] - result.steady_start) * model.mesh_frequency
    if period > 1 and window < period - 1e-9:
        warnings.append(
            f"the steady window ({window:.0f} mesh periods) is shorter than the period of the "
            f"transmission error ({period} mesh periods: deviations repeat over the hunting "
            "period): its peaks and spectrum cover part of it; raise solver.steady_periods, or "
            "use gear-dyn tolerance (exact over that period)")
    out["contact"] = contact_check(model, result)
    if out["contact"].get("warning"):
        warnings.append(out["contact"]["warning"])
    if model.mesh_periodic and not model.is_linear:
        out["orbit"] = orbit_check(model, result)
    if quasi_static is None:
        quasi_static = quasi_static_model(model)
    if quasi_static is not None and "mesh_force" in result.outputs:
        qs_ref = quasi_static_reference(quasi_static, result.settings)
        out.update(dynamic_factor_figures(result, qs_ref))
    out["warnings"] = warnings
    return out


def contact_check(model: Model, result: Result) -> dict[str, Any]:
    """Contact over the steady window: teeth apart / back-side shares, or a negative force.

    With backlash (mesh-periodic model): ``separation_share`` (``|x - e| <= b_g``) and
    ``backside_share`` (x - e < -b_g) of the steady samples. Without it: ``min_force_n`` and,
    when it is negative, a ``warning``: a linear model cannot represent teeth that separate.
    """
    steady = result.steady
    force = result.outputs.get("mesh_force")
    out: dict[str, Any] = {}
    if "n_contact_events" in result.extra:
        out["n_contact_events"] = int(result.extra["n_contact_events"])
    if model.backlash is not None and model.mesh_periodic:
        states = contact_states(model, result.t[steady], result.y[:, steady])
        out["separation_share"], out["backside_share"] = contact_shares(states)
        return out
    if force is not None and model.is_linear:
        fmin = float(np.min(force[steady]))
        out["min_force_n"] = fmin
        if fmin < 0:
            out["warning"] = (
                f"the mesh force goes negative (down to {fmin:.4g} N, "
                f"{fmin / max(model.static_load, 1e-300):.3g} W): the teeth would separate, "
                "which this linear model cannot represent; add a [backlash] table (the "
                "backlash model) for contact loss")
    return out


def orbit_check(model: Model, result: Result) -> dict[str, Any]:
    """The stability statement of a nonlinear mesh-periodic run: shooting from its end state.

    Returns ``period1`` (a period-1 orbit was found), ``max_multiplier_modulus`` and
    ``stable``, or the reason none was found.
    """
    mesh = cast(MeshModel, model)
    rtol = min(max(result.settings.rtol, 1e-10), 1e-6)
    try:
        sol = shoot(mesh, result.y[:, -1], rtol=rtol, max_iter=ORBIT_NEWTON.max_iter,
                    tol=ORBIT_NEWTON.tolerance)
    except GearDynError as exc:
        return {"period1": False, "statement": f"shooting failed: {exc}"}
    if not sol.converged:
        return {"period1": False, "statement": "no period-1 orbit near the end state: the "
                "response is not periodic in the mesh period (subharmonic, quasi-periodic or "
                "chaotic)"}
    rho = sol.spectral_radius
    stable = sol.stable
    return {"period1": True, "max_multiplier_modulus": rho, "stable": stable,
            "statement": f"period-1 orbit, largest Floquet multiplier {rho:.3g} "
                         f"({'stable' if stable else 'unstable'})"}


@blas_limited
def simulate(
    model: Model,
    t_end: float,
    settings: SolverSettings | None = None,
    steady_start: float | None = None,
    scene: Any = None,
    quasi_static: Model | None = None,
) -> Result:
    """Integrate ``model`` from 0 to ``t_end`` and attach the error estimate and checks.

    This is ``gear_dyn.simulate``: the run of :func:`gear_dyn.solvers.simulate_bare` (the same
    parameters) plus what :func:`checks` adds to ``Result.extra`` (see the module docstring).

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
    quasi_static : Model or None
        The same model at a mesh frequency far below f_n, for the dynamic factor's reference
        (:mod:`gear_dyn.analysis.dynamic_factor`); None: ``model.at_mesh_frequency`` gives it.

    Returns
    -------
    Result
        With ``extra["estimated_error"]`` (``max_rel``: the estimated max DTE error over the
        static deflection W/k_m, and its ``basis``) and ``extra["floquet"]`` (the largest
        Floquet multiplier of the linear model).

    Raises
    ------
    InputError
        Bad time span.
    SolverError
        The integration failed or diverged.

    See Also
    --------
    :class:`~gear_dyn.solvers.settings.SolverSettings` : Method, tolerances, output grid.
    :class:`~gear_dyn.solvers.result.Result` : The run.
    :func:`~gear_dyn.scene.run_scene` : The same for a scene.
    :func:`~gear_dyn.analysis.report.summarize` : The run's summary.

    Examples
    --------
    >>> from gear_dyn import SDOFModel, rectangular_stiffness
    >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
    >>> res = simulate(m, 0.2)  # 100 mesh periods (s)
    >>> round(res.dynamic_factor, 3)  # far below resonance (f_m / f_n = 0.19)
    0.982
    >>> res.extra["estimated_error"]["max_rel"] < 1e-6  # error over W / k_m
    True
    >>> simulate(m, -1.0)
    Traceback (most recent call last):
    ...
    gear_dyn.errors.InputError: duration = -1 s is out of range: valid range > 0 s
    """
    result = simulate_bare(model, t_end, settings, steady_start, scene)
    result.extra.update(checks(model, result, quasi_static))
    return result
