"""Figures of speed sweeps and stability charts (pyplot-free matplotlib Figures)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.colors import LogNorm, TwoSlopeNorm

from gear_dyn.analysis.chart import StabilityChart
from gear_dyn.analysis.stability import UNIT_CIRCLE_TOL
from gear_dyn.analysis.sweep import (
    RPM,
    SweepCurve,
    SweepResult,
    hysteresis_ranges,
    periodic_response,
)
from gear_dyn.analysis.sweep.types import (
    RESONANCES,
    resonance_notes,
    rpm_per_ratio,
    speed_ranges,
    sweep_peaks,
)
from gear_dyn.plots._axes import axes_of, tidy

_STYLE = {"up": dict(color="tab:blue", ls="-"), "down": dict(color="tab:orange", ls="--")}


def _layout(fig: Any, own: bool, **margins: float) -> None:
    """Fixed margins (fractions of the figure; why: :func:`~gear_dyn.plots._axes.fixed_layout`)
    on a figure made here, :func:`tidy` (``tight_layout``) on the caller's figure."""
    if own:
        fig.subplots_adjust(**margins)
    else:
        tidy(fig)


def _resonance_marks(ax: Any, result: SweepResult, lo: float, hi: float) -> None:
    """Dotted lines where f_m = f_n / k (k = 1, 2, 3) and f_m = 2 f_n, within [lo, hi] rpm
    (named by the ticks of the top axis, clear of the curves and of the legend)."""
    if not np.isfinite(result.natural_frequency):
        return
    for ratio, _label in RESONANCES:
        s = ratio * rpm_per_ratio(result)
        if lo <= s <= hi:
            ax.axvline(s, color="0.5", ls=":", lw=0.8)


def _markers(ax: Any, c: SweepCurve, y: np.ndarray, legend: bool, nonlinear: bool) -> None:
    """Marks of separation, back-side contact, no orbit and period 2 on one curve; with
    ``legend``, each kind is labelled once on ``ax`` (by the first curve that shows it).

    On a linear model (``nonlinear`` False) "separation" is a negative mesh force: the model
    does not hold there, and the label says so."""
    rpm = c.speed / RPM
    shown = set(ax.get_legend_handles_labels()[1])

    def label(text: str) -> str | None:
        return text if legend and text not in shown else None
    sep = np.nan_to_num(c.separation) > 0
    back = np.nan_to_num(c.backside) > 0
    # no periodic orbit: steady method "aperiodic", transient method a window that does not
    # repeat after one mesh period (unstable speeds are shaded instead)
    aper = ~periodic_response(c) & np.array([s != "unstable" for s in c.status])
    if np.any(sep):  # a legend entry only for what the sweep shows
        text = ("teeth separate" if nonlinear else
                "F < 0: linear model invalid here,\nadd [backlash]")
        ax.plot(rpm[sep], y[sep], "x", color="tab:red", ms=4, label=label(text))
    if np.any(back):
        ax.plot(rpm[back], y[back], "v", color="tab:purple", ms=4, mfc="none",
                label=label("back-side contact"))
    if np.any(aper):
        ax.plot(rpm[aper], y[aper], "o", color="0.3", ms=3, mfc="none",
                label=label("no periodic orbit"))
    p2 = c.orbit_periods == 2
    if np.any(p2):
        ax.plot(rpm[p2], y[p2], "D", color="tab:green", ms=3.5, mfc="none",
                label=label("period-2 (f_m/2)"))


#: left edge of the legends right of the panels, in axes fractions: clear of the right axis
#: of the peak force (its tick labels and its label)
LEGEND_X = 1.1


def _peak_force_axis(ax: Any, jump: float) -> None:
    """A right axis reading K_dyn as the peak force F_max / W = K_dyn x ``jump`` (the
    stiffness-jump factor F_qs,max / W), named with its value; none where ``jump`` is not
    finite (no quasi-static reference)."""
    if not (np.isfinite(jump) and jump > 0):
        return
    right = ax.secondary_yaxis("right", functions=(lambda k: k * jump, lambda f: f / jump))
    right.set_ylabel(f"peak force F_max / W\n= K_dyn x {jump:.3f} (stiffness jump)",
                     fontsize=8)
    right.tick_params(labelsize=8)


def _jump_marks(ax: Any, result: SweepResult, legend: bool) -> None:
    """A thin dotted vertical line per jump, in its direction's colour: at the located fold,
    else midway between the two speeds; one legend entry per direction."""
    for c in result.curves:
        color = _STYLE.get(c.direction, {}).get("color", "tab:blue")
        names = []
        for j in c.jumps:
            row = j.row()
            fold = row["fold_rpm"]
            x = fold if fold is not None else 0.5 * (row["from_rpm"] + row["to_rpm"])
            names.append(f"{x:.0f}" if j.kind == "fold" else
                         f"{x:.0f} ({j.kind.replace('_', ' ')})")
            ax.axvline(x, color=color, lw=0.9, ls=(0, (1, 2)), alpha=0.9)
        if legend and names:
            ax.plot([], [], color=color, lw=0.9, ls=(0, (1, 2)),
                    label=f"jumps {c.direction}"
                    + (" (folds)" if all(j.kind == "fold" for j in c.jumps) else "")
                    + " at\n" + ", ".join(names) + " rpm")


def plot_sweep_response(result: SweepResult, ax: Any = None,
                        iso_kv: tuple[Any, Any] | None = None) -> Any:
    """Dynamic factor K_dyn, RMS and peak-to-peak DTE against speed (top axis: f_m / f_n).

    The top panel draws K_dyn = F_max / F_qs,max (:mod:`gear_dyn.analysis.dynamic_factor`),
    the figure that compares like for like with ISO 6336-1 K_v (``iso_kv``, dash-dot); its
    right axis reads the same curves as the peak force F_max / W = K_dyn x the stiffness-jump
    factor, which the axis label names with its value.
    Up and down sweeps are drawn (solid, dashed) so jumps and hysteresis show; thin dotted
    vertical lines mark the jumps found from the orbits (at the located fold); crosses mark
    tooth separation (on a linear model: a negative mesh force, where the model does not
    hold), open triangles back-side contact, red bands parametric instability, orange bands
    hysteresis. The peak of each direction is starred and named in the legend (value, speed,
    direction); dotted lines mark f_m = f_n/3, f_n/2, f_n, 2 f_n (named on the top axis);
    resonances outside the range are named in the title. The legend sits right of the panels.

    Parameters
    ----------
    result : SweepResult
    ax : sequence of 3 Axes or None
        Dynamic factor, RMS DTE, peak-to-peak DTE (None: a new figure).
    iso_kv : (array, array) or None
        (pinion speeds in rpm, ISO 6336-1 K_v) drawn beside the simulated dynamic factor
        K_dyn.

    Returns
    -------
    matplotlib.figure.Figure
    """
    own = ax is None
    fig, axes = axes_of(ax, 3, 1, figsize=(11, 9), name="plot_sweep_response", sharex=True)
    quantities = (("dynamic_factor", 1.0, "dynamic factor K_dyn"),
                  ("rms_dte", 1e6, "RMS DTE (µm)"),
                  ("ptp_dte", 1e6, "peak-to-peak DTE (µm)"))
    all_rpm = np.concatenate([c.speed for c in result.curves]) / RPM
    lo, hi = float(np.min(all_rpm)), float(np.max(all_rpm))
    hyst = hysteresis_ranges(result)
    for row, (name, scale, label) in enumerate(quantities):
        ax = axes[row]
        for c in result.curves:
            y = getattr(c, name) * scale
            style = _STYLE.get(c.direction, {})
            lab = (f"K_dyn, sweep {c.direction}" if len(result.curves) > 1
                   else "K_dyn, simulated") if row == 0 else None
            ax.plot(c.speed / RPM, y, lw=1.1, marker=".", ms=2.5, label=lab, **style)
            _markers(ax, c, y, legend=row == 0, nonlinear=result.nonlinear)
            unstable = np.array([s == "unstable" for s in c.status])
            _shade(ax, c.speed / RPM, unstable, row == 0 and c is result.curves[0])
        for k, (a, b) in enumerate(hyst):
            # half a speed step beyond the first and last speed of the range (the directions
            # share the speeds: one curve's spacing)
            step = (hi - lo) / max(result.curves[0].speed.size - 1, 1)
            ax.axvspan(a - step / 2, b + step / 2, color="tab:orange", alpha=0.15, lw=0,
                       label="hysteresis: up and down\non different orbits"
                       if row == 0 and k == 0 else None)
        _jump_marks(ax, result, legend=row == 0)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        if row == 0:
            _resonance_marks(ax, result, lo, hi)
            if iso_kv is not None:
                ax.plot(*iso_kv, color="k", lw=1.0, ls="-.", label="ISO 6336-1 K_v (method B)")
            _peak_force_axis(ax, result.stiffness_jump_factor)
            for d, v, s in sweep_peaks(result):
                ax.plot([s], [v], "*", ms=11, mec="k", mew=0.6,
                        color=_STYLE.get(d, {}).get("color", "tab:blue"),
                        label=f"peak K_dyn {v:.3f} at {s:.0f} rpm" + (f" ({d})"
                                                                 if len(result.curves) > 1
                                                                 else ""))
    axes[-1].set_xlabel("pinion speed (rpm)")
    axes[0].legend(loc="upper left", bbox_to_anchor=(LEGEND_X, 1.0), fontsize=8,
                   borderaxespad=0.0)
    fn = result.natural_frequency
    if np.isfinite(fn):
        per = rpm_per_ratio(result)
        top = axes[0].secondary_xaxis("top", functions=(lambda s: s / per, lambda r: r * per))
        inside = [(r, lab) for r, lab in RESONANCES if lo <= r * per <= hi]
        if inside:
            top.set_xticks([r for r, _ in inside], [lab for _, lab in inside])
            top.tick_params(labelsize=8)
        top.set_xlabel(f"f_m / f_n (f_n = {fn:.0f} Hz; dotted lines: f_m = f_n/3, f_n/2, "
                       "f_n, 2 f_n)", fontsize=8)
    kind = "steady state (monodromy / shooting)" if result.options.method == "steady" else \
        "transient integration"
    title = f"{result.scene_name}: speed sweep, {kind}"
    notes = resonance_notes(result)
    if notes:
        title += "\n" + "; ".join(notes)
    if own:  # a caller's figure keeps its own title
        fig.suptitle(title, fontsize=10)
    _layout(fig, own, left=0.08, right=0.68, bottom=0.06, top=0.88, hspace=0.12)
    return fig


def _shade(ax: Any, rpm: np.ndarray, mask: np.ndarray, label: bool) -> None:
    """Red bands over the speed ranges (rpm) where ``mask`` holds (parametric instability)."""
    step = float(np.median(np.diff(np.sort(rpm)))) if rpm.size > 1 else 0.0
    for k, (lo, hi) in enumerate(speed_ranges(rpm * RPM, mask)):
        ax.axvspan(lo - step / 2, hi + step / 2, color="tab:red", alpha=0.12,
                   label="parametric instability" if label and k == 0 else None)


def plot_waterfall(result: SweepResult, direction: str | None = None, floor: float = 1e-4,
                   ax: Any = None) -> Any:
    """Map of the DTE spectra over speed: frequency against speed, colour = amplitude.

    Dashed lines are the mesh orders k f_m (k = 1 .. harmonics, each labelled ``k f_m`` at
    its top end); the dotted red line is f_n, where the spectrum lines brighten as they cross
    it. Points between the orders (k / window_periods) show sub-harmonic response. Amplitudes
    below ``floor`` times the largest are not drawn.

    Parameters
    ----------
    result : SweepResult
    direction : {"up", "down"} or None
        The curve drawn (default: the first).
    floor : float
        Smallest amplitude drawn, relative to the largest (0..1).
    ax : Axes or None
        One Axes (None: a new figure); the colour bar is added beside it.

    Returns
    -------
    matplotlib.figure.Figure
    """
    c = result.curve(direction or result.curves[0].direction)
    order = np.argsort(c.speed)
    rpm = c.speed[order] / RPM
    fm = c.mesh_frequency[order]
    amp = c.spectrum[order] * 1e6
    freq = fm[:, None] * result.orders[None, :]
    top = np.nanmax(amp) if np.any(np.isfinite(amp)) else 1.0
    own = ax is None
    fig, ax = axes_of(ax, figsize=(9, 6), name="plot_waterfall")
    keep = np.isfinite(amp) & (amp > floor * top)
    sc = ax.scatter(freq[keep] / 1e3, np.broadcast_to(rpm[:, None], amp.shape)[keep],
                    c=amp[keep], s=10, cmap="viridis", norm=LogNorm(vmin=floor * top, vmax=top))
    fig.colorbar(sc, ax=ax, label="DTE amplitude (µm)")
    fmax = float(np.max(freq)) / 1e3
    span = float(rpm[-1] - rpm[0]) or 1.0
    for k in range(1, result.options.harmonics + 1):
        ax.plot(k * fm / 1e3, rpm, color="0.45", lw=0.7, ls="--",
                label="mesh orders k f_m" if k == 1 else None)
        x_end = k * fm[-1] / 1e3
        if x_end <= fmax:
            ax.text(x_end, rpm[-1] + 0.015 * span, f" {k} f_m", fontsize=8, color="0.25", ha="left",
                    va="bottom", rotation=0, clip_on=False)
    fn = result.natural_frequency
    if np.isfinite(fn):
        ax.axvline(fn / 1e3, color="tab:red", lw=0.9, ls=":", label=f"f_n = {fn:.0f} Hz")
    ax.legend(loc="lower right", fontsize=8)
    ax.set_xlabel("frequency (kHz)")
    ax.set_ylabel("pinion speed (rpm)")
    ax.set_xlim(0, fmax * 1.1)  # room for the " 5 f_m" labels at the top ends
    # whole dots at both ends, the order labels above the top row
    ax.set_ylim(rpm[0] - 0.03 * span, rpm[-1] + 0.08 * span)
    ax.grid(alpha=0.3)
    ax.set_title(f"{result.scene_name}: DTE spectra over speed (sweep {c.direction}); "
                 f"orders k/{result.options.window_periods} of f_m", fontsize=10)
    _layout(fig, own, left=0.09, right=0.98, bottom=0.09, top=0.92)
    return fig


def plot_stability_chart(chart: StabilityChart, ax: Any = None,
                         sweep_range: tuple[float, float] | None = None,
                         title: str | None = None) -> Any:
    """Map of the largest Floquet multiplier modulus; the ``|mu| = 1`` contour bounds instability.

    Parameters
    ----------
    chart : StabilityChart
    ax : matplotlib axes or None
    sweep_range : (float, float) or None
        f_m / f_n range of a sweep, drawn on the scene's own parameter line.
    title : str or None
    """
    own = ax is None
    fig, ax = axes_of(ax, figsize=(7, 4.5), name="plot_stability_chart")
    _draw_chart(fig, ax, chart, sweep_range, title)
    _layout(fig, own, left=0.11, right=0.98, bottom=0.12, top=0.92)
    return fig


def _draw_chart(fig: Any, ax: Any, chart: StabilityChart,
                sweep_range: tuple[float, float] | None, title: str | None) -> None:
    rho = chart.spectral_radius
    vmax = max(float(np.max(rho)), 1.2)
    pm = ax.pcolormesh(chart.frequency_ratio, chart.parameter, rho, shading="auto",
                       cmap="RdBu_r", norm=TwoSlopeNorm(vmin=0.0, vcenter=1.0, vmax=vmax))
    fig.colorbar(pm, ax=ax, label="largest |Floquet multiplier|")
    level = 1.0 + UNIT_CIRCLE_TOL
    if np.min(rho) < level < np.max(rho):
        ax.contour(chart.frequency_ratio, chart.parameter, rho, levels=[level], colors="k",
                   linewidths=1.0)
    ylabel = ("stiffness variation (k_max - k_min) / 2 k_m"
              if chart.parameter_name == "stiffness_variation" else "damping ratio")
    ax.axhline(chart.scene_value, color="k", ls="--", lw=0.8, label="scene")
    if sweep_range is not None:
        ax.plot(sweep_range, [chart.scene_value] * 2, color="tab:green", lw=3, alpha=0.8,
                label="sweep")
    ax.legend(loc="upper right", fontsize=8)
    ax.set_xlabel("f_m / f_n")
    ax.set_ylabel(ylabel)
    ax.set_title(title or "parametric stability (black line: |mu| = 1; inside: unstable)",
                 fontsize=9)


def plot_stability_charts(charts: Sequence[StabilityChart],
                          sweep_range: tuple[float, float] | None = None, title: str = "",
                          ax: Any = None) -> Any:
    """Several stability charts one per row (:func:`plot_stability_chart` for each).

    Parameters
    ----------
    charts : sequence of StabilityChart
    sweep_range : (float, float) or None
        f_m / f_n range of a sweep, drawn on each chart.
    title : str
        Title of every chart ("" : the default title).
    ax : Axes, sequence of Axes or None
        One Axes per chart.
    """
    own = ax is None
    n = len(charts)
    fig, axes = axes_of(ax, n, 1, figsize=(8, 4.2 * n), name="plot_stability_charts",
                        squeeze=False)
    for a, ch in zip(axes[:, 0], charts, strict=True):
        _draw_chart(fig, a, ch, sweep_range, title or None)
    h = 4.2 * n  # inches: margins of 0.5 in at the bottom, 0.4 in at the top, 0.75 in between
    _layout(fig, own, left=0.1, right=0.98, bottom=0.5 / h, top=1 - 0.4 / h,
            hspace=0.75 / ((h - 0.9 - 0.75 * (n - 1)) / n) if n > 1 else 0.2)
    return fig
