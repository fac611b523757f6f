"""Error measures and the error estimate stated in every run summary.

All errors are on the dynamic transmission error (``dte`` output, else the first state) and
relative to the static deflection ``W / k_m`` of the model (else ``state_scale[0]``), so a figure
of 1e-6 means one millionth of the static deflection.

The estimate of a run (:func:`estimate_error`):

- exact propagator: rounding level, ``100 eps (pieces + 1) max(1, max|x| / x_s)``;
- solve_ivp and periodic methods: a second run with the same method at a 100 times tighter
  ``rtol`` (floor 1e-13) over the whole span; the estimate is ``2 max |x - x_tight| / x_s``
  (the factor 2 covers the tighter run's own error, about 1/60 of the checked run's for
  DOP853), never below the rounding level of the span's sequential products. No
  extrapolation: the difference is measured where it is stated.
- reproducibility: when the estimate exceeds :data:`REPRODUCIBLE` of the static deflection, the
  run does not pin its pointwise trajectory (``reproducible`` False) and states the error of the
  figures it prints instead (``figures``: RMS, peak-to-peak and mean DTE and the dynamic factor
  over the steady window, each ``2 |F - F_tight| / |F_tight|``). ``growth_per_period`` is the
  rate at which the two runs part (the largest difference of each mesh period, fitted
  exponentially from 1e-3 to 1/2 of its maximum); above :data:`GROWTH_LIMIT` the response is
  unstable or chaotic: nearby trajectories part exponentially and no tolerance pins them.

tests/analysis/test_solvers_estimate.py and tests/analysis/test_estimate_extreme.py check that
the estimate bounds the error measured against independent converged references.
"""

from __future__ import annotations

import math
import time
from dataclasses import replace
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.stability import UNIT_CIRCLE_TOL, floquet_multipliers, is_linear_periodic
from gear_dyn.errors import GearDynError
from gear_dyn.models.base import MeshModel, Model
from gear_dyn.solvers import integrate

FloatArray = NDArray[np.float64]

#: tighter-run factor and safety factor of the ODE error estimate
TIGHTEN = 100.0
SAFETY = 2.0
#: growth per mesh period of the run-to-run difference above which it is exponential
GROWTH_LIMIT = 1.02
#: pointwise difference (of the static deflection) beyond which an exponentially growing
#: trajectory is called not reproducible
REPRODUCIBLE = 1e-2


def error_scale(model: Model) -> float:
    """The static deflection ``W / k_m`` in m (else ``state_scale[0]``): the unit of errors."""
    k_m = model.mean_stiffness
    w = float(model.static_load)
    if k_m is not None and w > 0:
        return w / float(k_m)
    return float(np.asarray(model.state_scale, dtype=float)[0])


def error_series(model: Model, t: FloatArray, y: FloatArray) -> FloatArray:
    """The series errors are measured on: ``dte`` output if the model has one, else state 0."""
    out = model.outputs(np.asarray(t, dtype=float), y)
    if "dte" in out:
        return np.asarray(out["dte"], dtype=float)
    return np.asarray(y[0], dtype=float)


def relative_errors(model: Model, t: FloatArray, y: FloatArray, y_ref: FloatArray
                    ) -> tuple[float, float]:
    """``(max, rms)`` of ``|x - x_ref| / x_s`` over the grid (see module docstring)."""
    d = (error_series(model, t, y) - error_series(model, t, y_ref)) / error_scale(model)
    return float(np.max(np.abs(d))), float(np.sqrt(np.mean(d**2)))


def rounding_estimate(model: Model, t: FloatArray, y: FloatArray, n_segments: int) -> float:
    """Rounding-level error of the exact propagator, relative to the static deflection."""
    amp = float(np.max(np.abs(error_series(model, t, y)))) / error_scale(model)
    return float(100 * np.finfo(float).eps * (n_segments + 1) * max(amp, 1.0))


def estimate_error(
    model: Model, t_grid: FloatArray, y: FloatArray, settings: Any, stats: dict[str, Any],
    steady_start: float | None = None,
) -> dict[str, Any]:
    """Estimated error of a run, relative to the static deflection (module docstring).

    Parameters
    ----------
    model : Model
    t_grid : ndarray
        Output times in s.
    y : ndarray
        The run's states on ``t_grid``.
    settings : SolverSettings
        The run's settings (method already resolved from ``auto``).
    stats : dict
        The integrator's statistics (``n_segments``).
    steady_start : float or None
        Start of the steady window in s (for the figures' errors; None: the second half).

    Returns
    -------
    dict
        ``max_rel`` (the pointwise estimate), ``basis`` (how it was obtained), ``relative_to``,
        ``reproducible`` (bool), and for second-run estimates ``growth_per_period``,
        ``check_run_time_s`` and, where not reproducible, ``figures`` (relative errors of the
        summary figures).
    """
    if settings.method == "exact":
        return {
            "max_rel": rounding_estimate(model, t_grid, y, int(stats.get("n_segments", 1))),
            "basis": "rounding level of the exact propagator",
            "relative_to": "static deflection W/k_m",
            "reproducible": True,
        }
    if settings.method == "exact_contact":  # closed form between located contact changes
        return _exact_contact_estimate(model, t_grid, y, settings, stats, steady_start)
    tight = replace(settings, rtol=max(settings.rtol / TIGHTEN, 1e-13),
                    atol=None if settings.atol is None else settings.atol / TIGHTEN)
    start = time.perf_counter()
    y_t, _ = integrate(model, t_grid, tight, y[:, 0])
    cost = time.perf_counter() - start
    n_seq = int(stats.get("n_segments", 1)) + int(round((t_grid[-1] - t_grid[0])
                                                        * model.mesh_frequency))
    return _two_runs(model, t_grid, y, y_t, rounding_estimate(model, t_grid, y, n_seq),
                     f"second run at rtol/{TIGHTEN:g} over the whole span", cost, steady_start)


def _two_runs(model: Model, t_grid: FloatArray, y: FloatArray, y_other: FloatArray,
              floor: float, basis: str, cost: float, steady_start: float | None
              ) -> dict[str, Any]:
    """The estimate from a run and a second one: ``2 max |x - x_other| / x_s`` (never below
    ``floor``), the growth rate of the difference, and where it exceeds :data:`REPRODUCIBLE`
    the figures' errors instead of a pointwise promise."""
    d = np.abs(error_series(model, t_grid, y) - error_series(model, t_grid, y_other))
    d /= error_scale(model)
    growth = growth_per_period(t_grid, d, model.mesh_frequency)
    est = max(SAFETY * float(np.max(d)), floor)
    out: dict[str, Any] = {
        "max_rel": est if math.isfinite(est) else math.inf,
        "basis": basis,
        "relative_to": "static deflection W/k_m",
        "reproducible": est <= REPRODUCIBLE,
        "growth_per_period": growth,
        "check_run_time_s": cost,
    }
    if not out["reproducible"]:
        _not_reproducible(out, model, t_grid, y, y_other, growth, steady_start)
    return out


def summary_figures(model: Model, t: FloatArray, y: FloatArray, steady_start: float
                    ) -> dict[str, float]:
    """RMS (mean removed), peak-to-peak and mean DTE in m and the dynamic factor (peak mesh
    force / W) over the steady window ``t >= steady_start``, as the run summary defines them."""
    mask = t >= steady_start - 1e-12 * max(1.0, abs(steady_start))
    out = model.outputs(t[mask], y[:, mask])
    x = np.asarray(out.get("dte", y[0, mask]), dtype=float)
    figs = {"rms_dte": float(np.std(x)), "ptp_dte": float(np.ptp(x)),
            "mean_dte": float(np.mean(x))}
    if "mesh_force" in out and model.static_load > 0:
        figs["dynamic_factor"] = float(np.max(out["mesh_force"]) / model.static_load)
    return figs


def _exact_contact_estimate(model: Model, t_grid: FloatArray, y: FloatArray, settings: Any,
                            stats: dict[str, Any], steady_start: float | None
                            ) -> dict[str, Any]:
    """The closed form between located contact changes: rounding level where the response is
    stable; where it is unstable or chaotic, rounding grows exponentially. A second run from
    the initial state moved by 1e-12 of the state scale shows which: the larger of the rounding
    bound and twice the difference is stated (and ``reproducible`` as for ODE runs)."""
    from gear_dyn.solvers.contact_exact import rounding_bound

    scale = np.asarray(model.state_scale, dtype=float)
    start = time.perf_counter()
    y_p, _ = integrate(model, t_grid, settings, y[:, 0] + 1e-12 * scale)
    cost = time.perf_counter() - start
    return _two_runs(model, t_grid, y, y_p,
                     rounding_bound(y, scale, int(stats.get("n_segments", 1))),
                     "rounding level of the closed form between located contact changes, "
                     "checked by a run from a state moved by 1e-12", cost, steady_start)


def _not_reproducible(out: dict[str, Any], model: Model, t_grid: FloatArray, y: FloatArray,
                      y_other: FloatArray, growth: float, steady_start: float | None) -> None:
    """Mark an estimate as not reproducible: say why, and state the figures' errors."""
    why = (f"the runs part exponentially (x{growth:.3g} per mesh period: an unstable or "
           "chaotic response, no tolerance pins it)" if growth > GROWTH_LIMIT
           else "tighten rtol to pin it")
    out["basis"] += (f"; the pointwise trajectory is not reproducible to {REPRODUCIBLE:g} of "
                     f"the static deflection: {why}; the figures' errors are stated")
    start_s = 0.5 * float(t_grid[-1]) if steady_start is None else steady_start
    out["figures"] = figure_errors(summary_figures(model, t_grid, y, start_s),
                                   summary_figures(model, t_grid, y_other, start_s))


def growth_per_period(t: FloatArray, d: FloatArray, mesh_frequency: float) -> float:
    """Rate (factor per mesh period) at which the difference ``d`` of two runs grows.

    The largest ``d`` of each mesh period, made monotone (running maximum), is fitted
    exponentially between its first periods at 1e-3 and at 1/2 of its maximum. 1.0 when that
    rise spans fewer than 5 periods (no sustained growth) or the span has fewer than 8 periods.
    """
    k = np.floor((t - t[0]) * mesh_frequency + 1e-9).astype(int)
    n = int(k[-1])
    if n < 8:
        return 1.0
    env = np.zeros(n)
    np.maximum.at(env, np.minimum(k, n - 1), d)
    env = np.maximum.accumulate(env)
    top = float(env[-1])
    if not (math.isfinite(top) and top > 0):
        return 1.0
    i0 = int(np.argmax(env >= 1e-3 * top))
    i1 = int(np.argmax(env >= 0.5 * top))
    if i1 - i0 < 5 or env[i0] <= 0:
        return 1.0
    return float(max((env[i1] / env[i0]) ** (1.0 / (i1 - i0)), 1.0))


def figure_errors(result_figures: dict[str, float], tight_figures: dict[str, float]
                  ) -> dict[str, float]:
    """Stated relative errors of summary figures: ``SAFETY |F - F_tight| / |F_tight|``."""
    out = {}
    for name, value in result_figures.items():
        ref = tight_figures[name]
        out[name] = (SAFETY * abs(value - ref) / abs(ref)) if ref != 0 else math.inf
    return out


#: explicit solve_ivp methods (stability-limited on stiff or very fast problems)
EXPLICIT = ("RK45", "RK23", "DOP853")
#: a problem is called stiff when max|Re lambda| / min|Re lambda| exceeds this and stability
#: alone forces an explicit method to more than STIFF_STEPS steps per mesh period ...
STIFF_RATIO = 50.0
STIFF_STEPS = 20.0
#: ... or when an explicit method needs more than this many steps per mesh period for stability
FAST_STEPS = 500.0
#: eigenvalues below this fraction of the largest count as zero (rigid-body modes, rounding)
ZERO_EIG = 1e-6


def stiffness_check(model: Model, method: str, samples: int = 16) -> dict[str, Any]:
    """Is the problem stiff (or very fast) for an explicit method? With advice.

    The Jacobian is evaluated at the initial state at ``samples`` instants over one mesh period.
    ``stiffness_ratio`` = max |Re lambda| / min |Re lambda| over the real parts that are not
    zero (below ZERO_EIG of the largest |lambda|: rigid-body modes and rounding are left out;
    a heavily over-damped mesh, xi = 5, gives about 100); ``explicit_steps_per_period`` =
    max |lambda| T_m / 3, the fewest steps per mesh period an explicit Runge-Kutta method
    (stability bound |h lambda| <~ 3) can take, whatever the tolerance. Stiff: ratio > 50 with
    > 20 such steps, or > 500 steps (a very fast mesh).

    Returns
    -------
    dict
        ``stiffness_ratio``, ``explicit_steps_per_period``, ``stiff`` (bool) and ``advice``
        (empty when the method suits the problem).
    """
    period = 1.0 / model.mesh_frequency
    y0 = model.initial_state()
    lam_max, re_max, re_min = 0.0, 0.0, math.inf
    for t in np.linspace(0.0, period, samples, endpoint=False):
        lam = np.linalg.eigvals(np.asarray(model.jac(float(t), y0), dtype=float))
        lam_max = max(lam_max, float(np.max(np.abs(lam))))
        re = np.abs(lam.real)
        re = re[re > ZERO_EIG * max(float(np.max(np.abs(lam))), 1e-300)]
        if re.size:
            re_max = max(re_max, float(np.max(re)))
            re_min = min(re_min, float(np.min(re)))
    ratio = re_max / re_min if re_min < math.inf and re_min > 0 else 1.0
    steps = lam_max * period / 3.0
    stiff_steps = re_max * period / 3.0
    stiff = (ratio > STIFF_RATIO and stiff_steps > STIFF_STEPS) or steps > FAST_STEPS
    advice = ""
    if stiff and method in EXPLICIT:
        advice = (
            f"stiff or very fast problem (stiffness ratio {ratio:.3g}, an explicit method needs "
            f">= {steps:.3g} steps per mesh period for stability): {method} is slow here; use "
            "method auto (exact propagator where it applies, else LSODA, which switches to BDF "
            "when stiff) or Radau"
        )
    return {"stiffness_ratio": ratio, "explicit_steps_per_period": steps, "stiff": stiff,
            "advice": advice}


def floquet_check(model: Model) -> dict[str, Any] | None:
    """Parametric stability of a linear single-DOF model before integrating it.

    Uses :func:`gear_dyn.analysis.stability.floquet_multipliers` (the monodromy matrix over one
    mesh period). Returns None for models it does not cover (not linear or not mesh-periodic).

    Returns
    -------
    dict or None
        ``max_multiplier_modulus`` (growth factor per mesh period of the free response),
        ``unstable`` (bool) and ``advice``.
    """
    if not is_linear_periodic(model):
        return None
    try:
        rho = float(np.max(np.abs(floquet_multipliers(cast(MeshModel, model)))))
    except GearDynError:
        return None
    unstable = rho > 1.0 + UNIT_CIRCLE_TOL
    advice = ""
    if unstable:
        advice = (f"parametrically unstable: the free response grows by {rho:.4g} per mesh "
                  "period (Floquet multiplier); the time history diverges and its peak "
                  "figures mean nothing - change speed, stiffness variation or damping "
                  "(see gear-dyn sweep)")
    return {"max_multiplier_modulus": rho, "unstable": unstable, "advice": advice}
