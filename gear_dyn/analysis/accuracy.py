"""Error measures and the error estimate stated in every run summary (docs/solvers.md, "Error
estimate in every run summary", states each basis and how it is tested).

All errors are on the dynamic transmission error (``dte`` output, else the first state) and
relative to the static deflection ``W / k_m`` of the model (else ``state_scale[0]``), so a figure
of 1e-6 means one millionth of the static deflection.
"""

from __future__ import annotations

import itertools
import math
import time
from dataclasses import replace
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.stability import (
    floquet_stable,
    is_linear_periodic,
    one_period_map,
    period_map,
)
from gear_dyn.errors import GearDynError
from gear_dyn.models.base import MeshModel, Model
from gear_dyn.solvers import integrate
from gear_dyn.solvers.periodic import fill_periodic, gauss_step_maps, step_products

FloatArray = NDArray[np.float64]

#: tighter-run factor and safety factor of the ODE error estimate
TIGHTEN = 100.0
SAFETY = 2.0
#: growth per mesh period of the run-to-run difference above which it is exponential
GROWTH_LIMIT = 1.02
#: pointwise difference (of the static deflection) beyond which an exponentially growing
#: trajectory is called not reproducible
REPRODUCIBLE = 1e-2
#: substeps per grid step of the Gauss-Legendre reference of a periodic run, tried in turn
#: (each checked against the previous one)
GAUSS_SUBSTEPS = (1, 2, 4, 8)
#: the reference's own difference (from half its substeps) must stay below this share of the
#: run's difference from it (or of the rounding level)
REFERENCE_SHARE = 1e-2

ComplexArray = NDArray[np.complex128]
StepMaps = tuple[FloatArray, FloatArray]
#: monodromy matrices of the Gauss-Legendre reference of a periodic run: (finer, coarser)
_Monodromies = tuple[FloatArray, FloatArray]


def error_scale(model: Model) -> float:
    """The static deflection ``W / k_m`` in m (else ``state_scale[0]``): the unit of errors."""
    k_m = model.mean_stiffness
    w = float(model.static_load)
    if k_m is not None and w > 0:
        return w / float(k_m)
    return float(np.asarray(model.state_scale, dtype=float)[0])


def error_series(model: Model, t: FloatArray, y: FloatArray,
                 excitations: dict[str, FloatArray] | None = None) -> FloatArray:
    """The series errors are measured on: ``dte`` output if the model has one, else state 0.
    ``excitations``: the model's excitations on ``t`` where the run has them (a kernel run's
    table, passed to ``outputs``)."""
    t = np.asarray(t, dtype=float)
    out = (model.outputs(t, y) if excitations is None
           else cast(Any, model).outputs(t, y, excitations=excitations))
    if "dte" in out:
        return np.asarray(out["dte"], dtype=float)
    return np.asarray(y[0], dtype=float)


def relative_errors(model: Model, t: FloatArray, y: FloatArray, y_ref: FloatArray
                    ) -> tuple[float, float]:
    """``(max, rms)`` of ``|x - x_ref| / x_s`` over the grid (see module docstring)."""
    d = (error_series(model, t, y) - error_series(model, t, y_ref)) / error_scale(model)
    return float(np.max(np.abs(d))), float(np.sqrt(np.mean(d**2)))


def rounding_estimate(model: Model, x: FloatArray, n_segments: int) -> float:
    """Rounding-level error of the exact propagator over ``n_segments`` pieces, relative to the
    static deflection, from the run's error series ``x`` (:func:`error_series`)."""
    amp = float(np.max(np.abs(x))) / error_scale(model)
    return float(100 * np.finfo(float).eps * (n_segments + 1) * max(amp, 1.0))


def estimate_error(
    model: Model, t_grid: FloatArray, y: FloatArray, settings: Any, stats: dict[str, Any],
    steady_start: float | None = None, series: FloatArray | None = None,
) -> dict[str, Any]:
    """Estimated error of a run, relative to the static deflection (docs/solvers.md).

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
        The integrator's statistics (``n_segments``; ``step_maps`` for method ``periodic``).
    steady_start : float or None
        Start of the steady window in s (for the figures' errors; None: the second half).
    series : ndarray or None
        The run's error series (:func:`error_series` of ``y``) if already computed.

    Returns
    -------
    dict
        ``max_rel`` (the pointwise estimate), ``basis`` (how it was obtained), ``relative_to``,
        ``reproducible`` (bool), and for second-run estimates ``growth_per_period``,
        ``check_run_time_s`` and, where not reproducible, ``figures`` (relative errors of the
        summary figures).
    """
    return estimate_with_reference(model, t_grid, y, settings, stats, steady_start, series)[0]


def estimate_with_reference(
    model: Model, t_grid: FloatArray, y: FloatArray, settings: Any, stats: dict[str, Any],
    steady_start: float | None = None, series: FloatArray | None = None,
) -> tuple[dict[str, Any], _Monodromies | None]:
    """:func:`estimate_error`, and for a periodic run the monodromy matrices of the
    Gauss-Legendre reference it used, ``(finer, coarser)`` (None otherwise), for
    :func:`floquet_check`."""
    x = error_series(model, t_grid, y) if series is None else series
    if settings.method == "exact":
        return {
            "max_rel": rounding_estimate(model, x, int(stats.get("n_segments", 1))),
            "basis": "rounding level of the exact propagator",
            "relative_to": "static deflection W/k_m",
            "reproducible": True,
        }, None
    if settings.method == "exact_contact":
        # the closed form between located contact changes: rounding level where the response is
        # stable; where it is unstable or chaotic, rounding grows exponentially. A second run
        # from the initial state moved by 1e-12 of the state scale shows which: the larger of
        # the rounding bound and twice the difference is stated (``reproducible`` as for ODEs)
        from gear_dyn.solvers.contact_exact import rounding_bound

        scale = np.asarray(model.state_scale, dtype=float)
        start = time.perf_counter()
        y_p, _ = integrate(model, t_grid, settings, y[:, 0] + 1e-12 * scale)
        cost = time.perf_counter() - start
        return _two_runs(model, t_grid, y, y_p,
                         rounding_bound(y, scale, int(stats.get("n_segments", 1))),
                         "rounding level of the closed form between located contact changes, "
                         "checked by a run from a state moved by 1e-12", cost, steady_start), None
    if settings.method == "kernel":
        return _kernel_estimate(model, t_grid, y, x, settings, stats, steady_start), None
    n_seq = int(stats.get("n_segments", 1)) + int(round((t_grid[-1] - t_grid[0])
                                                        * model.mesh_frequency))
    floor = rounding_estimate(model, x, n_seq)
    if settings.method == "periodic" and stats.get("step_maps") is not None:
        done = _periodic_estimate(model, t_grid, y, x, stats["step_maps"], floor, steady_start)
        if done is not None:
            return done
    tight = replace(settings, rtol=max(settings.rtol / TIGHTEN, 1e-13),
                    atol=None if settings.atol is None else settings.atol / TIGHTEN)
    start = time.perf_counter()
    y_t, _ = integrate(model, t_grid, tight, y[:, 0])
    cost = time.perf_counter() - start
    return _two_runs(model, t_grid, y, y_t, floor,
                     f"second run at rtol/{TIGHTEN:g} over the whole span", cost, steady_start,
                     (x, None)), None


def _kernel_estimate(model: Model, t_grid: FloatArray, y: FloatArray, x: FloatArray,
                     settings: Any, stats: dict[str, Any], steady_start: float | None
                     ) -> dict[str, Any]:
    """The kernel run against its check run (every step halved, from a start moved by 1e-12),
    plus the bound on its table's interpolation error
    (:mod:`gear_dyn.solvers.kernel_method`)."""
    from gear_dyn.solvers.kernel_method import CHECK_TIGHTEN, check_run, table_bound

    start = time.perf_counter()
    y_c, tol, ex_c = check_run(model, t_grid, y[:, 0], settings.rtol)
    x_c = error_series(model, t_grid, y_c, ex_c)
    table = table_bound(model, t_grid, y)
    cost = time.perf_counter() - start
    n_seq = int(stats.get("n_segments", 1)) + t_grid.size
    est = _two_runs(model, t_grid, y, y_c, rounding_estimate(model, x, n_seq),
                    f"second kernel run with every step halved (the output grid's midpoints "
                    f"added, a {CHECK_TIGHTEN:g} times tighter tolerance, {tol:.3g}) from a "
                    "state moved by 1e-12 over the whole span, plus the table's "
                    "interpolation error carried to the DTE",
                    cost, steady_start, (x, x_c))
    est["max_rel"] = est["max_rel"] + table
    est["table_part"] = table
    return est


def _periodic_estimate(model: Model, t_grid: FloatArray, y: FloatArray, x: FloatArray,
                       run_maps: StepMaps, floor: float, steady_start: float | None
                       ) -> tuple[dict[str, Any], _Monodromies] | None:
    """The periodic run against the same fill with Gauss-Legendre step maps (docs/solvers.md),
    or None where no reference passes its own check."""
    start = time.perf_counter()
    s_per = run_maps[0].shape[0]
    t0, dt = float(t_grid[0]), float(t_grid[1] - t_grid[0])
    scale = np.asarray(model.state_scale, dtype=float)
    maps = gauss_step_maps(model, t0, dt, s_per, GAUSS_SUBSTEPS[0])
    coarse = step_products(*maps)
    y_c = fill_periodic(*maps, y[:, 0], t_grid.size, s_per, coarse)
    for n in GAUSS_SUBSTEPS[1:]:
        maps = gauss_step_maps(model, t0, dt, s_per, n)
        fine = step_products(*maps)
        y_f = fill_periodic(*maps, y[:, 0], t_grid.size, s_per, fine)
        own = np.max(np.abs(y_c - y_f), axis=1) / scale  # per state, relative to its scale
        diff = np.max(np.abs(y - y_f), axis=1) / scale
        if np.all(own <= REFERENCE_SHARE * np.maximum(diff, floor)):
            cost = time.perf_counter() - start
            # the mesh model's DTE is its state x: the reference's series is then its first state
            x_f = (np.asarray(y_f[0], dtype=float) if np.array_equal(x, y[0])
                   else error_series(model, t_grid, y_f))
            est = _two_runs(model, t_grid, y, y_f, floor,
                            f"second run with Gauss-Legendre step maps ({n} substeps, checked "
                            f"against {n // 2}) over the whole span", cost, steady_start,
                            (x, x_f))
            return est, (fine[0][-1], coarse[0][-1])
        coarse, y_c = fine, y_f
    return None


def _two_runs(model: Model, t_grid: FloatArray, y: FloatArray, y_other: FloatArray,
              floor: float, basis: str, cost: float, steady_start: float | None,
              series: tuple[FloatArray | None, FloatArray | None] = (None, None)
              ) -> dict[str, Any]:
    """The estimate from a run and a second one: ``2 max |x - x_other| / x_s`` (never below
    ``floor``), the growth rate of the difference, and where it exceeds :data:`REPRODUCIBLE`
    the figures' errors instead of a pointwise promise. ``series``: the two runs' error series
    where already known."""
    x, x_other = series
    x = error_series(model, t_grid, y) if x is None else x
    x_other = error_series(model, t_grid, y_other) if x_other is None else x_other
    d = np.abs(x - x_other) / error_scale(model)
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
    if not out["reproducible"]:  # say why, and state the figures' errors
        why = (f"the runs part exponentially (x{growth:.3g} per mesh period: an unstable or "
               "chaotic response, no tolerance pins it)" if growth > GROWTH_LIMIT
               else "tighten rtol to pin it")
        out["basis"] += (f"; the pointwise trajectory is not reproducible to {REPRODUCIBLE:g} "
                         f"of the static deflection: {why}; the figures' errors are stated")
        start_s = 0.5 * float(t_grid[-1]) if steady_start is None else steady_start
        out["figures"] = figure_errors(summary_figures(model, t_grid, y, start_s),
                                       summary_figures(model, t_grid, y_other, start_s))
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
    return {name: SAFETY * abs(value - tight_figures[name]) / abs(tight_figures[name])
            if tight_figures[name] != 0 else math.inf for name, value in result_figures.items()}


#: explicit solve_ivp methods (stability-limited on stiff or very fast problems)
EXPLICIT = ("RK45", "RK23", "DOP853")
#: a problem is called stiff when ``max|Re lambda| / min|Re lambda|`` exceeds this and stability
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
    ``stiffness_ratio = max |Re lambda| / min |Re lambda|`` over the real parts that are not
    zero (below ZERO_EIG of the largest ``|lambda|``: rigid-body modes and rounding are left out;
    a heavily over-damped mesh, xi = 5, gives about 100); ``explicit_steps_per_period`` =
    ``max |lambda| T_m / 3``, the fewest steps per mesh period an explicit Runge-Kutta method
    (stability bound ``|h lambda| <~ 3``) can take, whatever the tolerance. Stiff: ratio > 50 with
    > 20 such steps, or > 500 steps (a very fast mesh).

    Returns
    -------
    dict
        ``stiffness_ratio``, ``explicit_steps_per_period``, ``stiff`` (bool) and ``advice``
        (empty when the method suits the problem).
    """
    period = 1.0 / model.mesh_frequency
    y0 = model.initial_state()
    lam = np.linalg.eigvals(np.array([model.jac(float(t), y0) for t in np.linspace(
        0.0, period, samples, endpoint=False)], dtype=float))  # (samples, n)
    lam_max = float(np.max(np.abs(lam)))
    re = np.abs(lam.real)
    re = re[re > ZERO_EIG * np.maximum(np.max(np.abs(lam), axis=1, keepdims=True), 1e-300)]
    re_max, re_min = (float(np.max(re)), float(np.min(re))) if re.size else (0.0, math.inf)
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


def floquet_check(model: Model, step_maps: StepMaps | None = None,
                  reference: _Monodromies | None = None, exact: bool = False
                  ) -> dict[str, Any] | None:
    """Parametric stability of a linear single-DOF model: its largest Floquet multiplier.

    The monodromy matrix is the product of the run's own maps of one mesh period where it has
    them (``step_maps``: ``Result.step_maps``, of an ``exact`` run if ``exact``; ``reference``:
    the Gauss-Legendre ``(finer, coarser)`` monodromy matrices of a periodic run's estimate),
    else that of :func:`gear_dyn.analysis.stability.one_period_map`; docs/solvers.md says how
    ``multiplier_error`` is stated for each. Returns None for models it does not cover (not
    linear or not mesh-periodic).

    Returns
    -------
    dict or None
        ``max_multiplier_modulus`` (growth factor per mesh period of the free response),
        ``multiplier_error`` (None where not measured), ``basis``, ``unstable`` (bool) and
        ``advice``.
    """
    if not is_linear_periodic(model):
        return None
    mesh = cast(MeshModel, model)
    try:
        if step_maps is not None and exact:
            rho, err, basis = _floquet_exact(mesh, step_maps)
        elif step_maps is not None:
            rho, err, basis = _floquet_reused(mesh, step_maps, reference)
        else:
            phi, _q, how = one_period_map(mesh)
            rho, err = float(np.max(np.abs(np.linalg.eigvals(phi)))), None
            basis = ("monodromy matrix by expm of the pieces (exact up to rounding)"
                     if how == "expm" else "monodromy matrix by the variational equations "
                     "(DOP853, rtol 1e-10)")
    except GearDynError:
        return None
    unstable = not floquet_stable(rho)
    advice = ""
    if unstable:
        advice = (f"parametrically unstable: the free response grows by {rho:.4g} per mesh "
                  "period (Floquet multiplier); the time history diverges and its peak "
                  "figures mean nothing - change speed, stiffness variation or damping "
                  "(see gear-dyn sweep)")
    return {"max_multiplier_modulus": rho, "multiplier_error": err, "basis": basis,
            "unstable": unstable, "advice": advice}


def multiplier_distance(mu: ComplexArray, nu: ComplexArray) -> float:
    """Largest distance between two sets of Floquet multipliers, paired the closest way (the
    minimum over pairings of the largest pair distance); it bounds the difference of their
    spectral radii too."""
    return min(float(np.max(np.abs(mu - nu[list(perm)])))
               for perm in itertools.permutations(range(nu.size)))


def _floquet_reused(model: MeshModel, step_maps: StepMaps,
                    reference: _Monodromies | None) -> tuple[float, float, str]:
    """Spectral radius of the run's own period map, the error of its multipliers against the
    Gauss-Legendre maps' and the basis (see :func:`floquet_check`)."""
    s_per = step_maps[0].shape[0]
    if reference is None:
        dt = 1.0 / (model.mesh_frequency * s_per)
        reference = (period_map(*gauss_step_maps(model, 0.0, dt, s_per, 2))[0],
                     period_map(*gauss_step_maps(model, 0.0, dt, s_per, 1))[0])
    mu, mu_ref, mu_coarse = (np.linalg.eigvals(phi).astype(np.complex128) for phi in
                             (period_map(*step_maps)[0], reference[0], reference[1]))
    rho = float(np.max(np.abs(mu)))
    floor = 100 * np.finfo(float).eps * (s_per + 1) * max(rho, 1.0)
    basis = "monodromy matrix: product of the run's step maps (no integration), checked "
    diff = multiplier_distance(mu, mu_ref)
    if multiplier_distance(mu_ref, mu_coarse) <= REFERENCE_SHARE * max(diff, floor):
        return rho, float(max(SAFETY * diff, floor)), basis + (
            "against Gauss-Legendre collocation maps")
    # the collocation maps do not converge (a kink inside a step): the variational route
    mu_var = np.linalg.eigvals(one_period_map(model)[0]).astype(np.complex128)
    return rho, float(max(SAFETY * multiplier_distance(mu, mu_var), floor)), basis + (
        "against the variational equations (DOP853, rtol 1e-10)")


def _floquet_exact(model: MeshModel, piece_maps: StepMaps) -> tuple[float, float, str]:
    """Spectral radius of the product of the exact propagator's piece maps over one mesh
    period and its rounding bound (see :func:`floquet_check`)."""
    d = np.asarray(model.state_scale, dtype=float)
    scaled = piece_maps[0] * (d[None, None, :] / d[None, :, None])  # D^-1 P D
    phi = period_map(*piece_maps)[0] * (d[None, :] / d[:, None])
    mu, vec = np.linalg.eig(phi)
    norms = float(np.prod(np.linalg.norm(scaled, 2, axis=(1, 2))))
    kappa = float(np.linalg.cond(vec))
    err = kappa * 100 * np.finfo(float).eps * (scaled.shape[0] + 1) * max(norms, 1.0)
    return float(np.max(np.abs(mu))), float(err), (
        "monodromy matrix: product of the exact propagator's piece maps (no integration), "
        "rounding bound")
