"""Tables and summaries of a sweep: CSV columns, ranges, jumps, hysteresis, sweep.json.

The dynamic factor and the figures beside it are those of a run
(:mod:`gear_dyn.analysis.dynamic_factor`). The jumps themselves are found from the orbits when
the sweep runs (:mod:`gear_dyn.analysis.sweep.orbit_jumps`); here they are only listed.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.dynamic_factor import (
    DYNAMIC_FACTOR_DEFINITION,
    STIFFNESS_JUMP_DEFINITION,
)
from gear_dyn.analysis.sweep.types import RPM, SweepCurve, SweepResult

FloatArray = NDArray[np.float64]


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
