"""Error measures and the error estimate stated in every run summary.

All errors are on the dynamic transmission error (``dte`` output, else the first state) and
relative to the static deflection ``W / k_m`` of the model (else ``state_scale[0]``), so a figure
of 1e-6 means one millionth of the static deflection.

The estimate of a run (:func:`estimate_error`):

- exact propagator: rounding level, ``100 eps (pieces + 1) max(1, max|x| / x_s)``;
- solve_ivp methods: a second run with the same method at a 100 times tighter ``rtol`` (floor
  1e-13) over the first part of the span (at least 20 mesh periods, at least 10 % of the span);
  the largest difference on each half of that window gives ``e1`` and ``e2``. If the difference
  does not grow (``e2 <= e1``: damped error), the estimate is ``2 max(e1, e2)``; if it grows, it
  is extrapolated linearly to the end of the span, ``2 (e2 + (e2 - e1) (T - T_s) / (T_s / 2))``
  (undamped phase drift grows linearly), and never below the rounding level of the span's
  sequential products. The factor 2 covers the tighter run's own error (about
  1/60 of the checked run's for DOP853) and the variation of the error along the span; the tests
  in tests/analysis/test_solvers_estimate.py check that the estimate bounds the measured error.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.stability import UNIT_CIRCLE_TOL, floquet_multipliers, is_linear_periodic
from gear_dyn.errors import GearDynError
from gear_dyn.models.base import MeshModel, Model
from gear_dyn.solvers import integrate

FloatArray = NDArray[np.float64]

#: tighter-run factor, window and safety factor of the ODE error estimate
TIGHTEN = 100.0
MIN_WINDOW_PERIODS = 20
WINDOW_FRACTION = 0.1
SAFETY = 2.0


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
    model: Model, t_grid: FloatArray, y: FloatArray, settings: Any, stats: dict[str, Any]
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

    Returns
    -------
    dict
        ``max_rel`` (the estimate), ``basis`` (how it was obtained), ``relative_to``, and for
        ODE methods the check window ``window_s`` and its cost ``check_run_time_s``.
    """
    if settings.method == "exact":
        return {
            "max_rel": rounding_estimate(model, t_grid, y, int(stats.get("n_segments", 1))),
            "basis": "rounding level of the exact propagator",
            "relative_to": "static deflection W/k_m",
        }
    if settings.method == "exact_contact":  # closed form between located contact changes
        from gear_dyn.solvers.contact_exact import rounding_bound

        return {
            "max_rel": rounding_bound(y, np.asarray(model.state_scale),
                                      int(stats.get("n_segments", 1))),
            "basis": "rounding level of the closed form between located contact changes",
            "relative_to": "static deflection W/k_m",
        }
    import time

    period = 1.0 / model.mesh_frequency
    t_end = float(t_grid[-1] - t_grid[0])
    window = min(t_end, max(MIN_WINDOW_PERIODS * period, WINDOW_FRACTION * t_end))
    n_w = int(np.searchsorted(t_grid, t_grid[0] + window, side="right"))
    n_w = max(n_w, min(4, t_grid.size))
    tight = replace(settings, rtol=max(settings.rtol / TIGHTEN, 1e-13),
                    atol=None if settings.atol is None else settings.atol / TIGHTEN)
    start = time.perf_counter()
    y_t, _ = integrate(model, t_grid[:n_w], tight, y[:, 0])
    cost = time.perf_counter() - start
    tw = t_grid[:n_w]
    d = np.abs(error_series(model, tw, y[:, :n_w]) - error_series(model, tw, y_t))
    d /= error_scale(model)
    half = max(1, n_w // 2)
    e1 = float(np.max(d[:half]))
    e2 = float(np.max(d[half:])) if n_w > half else e1
    t_w = float(tw[-1] - tw[0])
    if t_w >= t_end * (1 - 1e-9) or e2 <= e1:
        est = SAFETY * max(e1, e2)
        basis = "second run at rtol/100 over the window; error not growing"
    else:
        est = SAFETY * (e2 + (e2 - e1) * (t_end - t_w) / max(0.5 * t_w, 1e-300))
        basis = "second run at rtol/100 over the window; growth extrapolated linearly"
    # never below the rounding level of the sequential products over the span
    n_seq = int(stats.get("n_segments", 1)) + int(round(t_end * model.mesh_frequency))
    est = max(est, rounding_estimate(model, t_grid, y, n_seq))
    return {
        "max_rel": est if math.isfinite(est) else math.inf,
        "basis": basis,
        "relative_to": "static deflection W/k_m",
        "window_s": [float(tw[0]), float(tw[-1])],
        "check_run_time_s": cost,
    }


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
