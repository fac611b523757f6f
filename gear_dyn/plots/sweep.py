"""Figures of speed sweeps and stability charts (pyplot-free matplotlib Figures).

Plots are functions of results: each takes an optional ``ax`` and returns the figure.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.colors import LogNorm, TwoSlopeNorm
from matplotlib.figure import Figure

from gear_dyn.analysis.chart import StabilityChart
from gear_dyn.analysis.stability import UNIT_CIRCLE_TOL
from gear_dyn.analysis.sweep import RPM, SweepCurve, SweepResult
from gear_dyn.plots._axes import axes_of, given_axes, tidy

_STYLE = {"up": dict(color="tab:blue", ls="-"), "down": dict(color="tab:orange", ls="--")}


def _layout(fig: Any, own: bool, **margins: float) -> None:
    """Fixed margins (fractions of the figure) on a figure made here, the caller's figure gets
    :func:`tidy` (``tight_layout``). Fixed margins spare drawing every text once more to
    measure it (for the run figures ``tight_layout`` costs about half again the time of
    drawing them: benchmarks/results/cli.md)."""
    if own:
        fig.subplots_adjust(**margins)
    else:
        tidy(fig)


def _resonance_marks(ax: Any, result: SweepResult, lo: float, hi: float) -> None:
    """Dotted lines where f_m = f_n / k (k = 1, 2, 3) and f_m = 2 f_n, within [lo, hi] rpm."""
    fn = result.natural_frequency
    if not np.isfinite(fn):
        return
    c = result.curves[0]
    per_rpm = c.mesh_frequency[0] / (c.speed[0] / RPM)  # Hz per rpm
    drawn = 0
    for ratio, label in ((1 / 3, "f_n/3"), (0.5, "f_n/2"), (1.0, "f_n"), (2.0, "2f_n")):
        s = ratio * fn / per_rpm
        if lo <= s <= hi:
            ax.axvline(s, color="0.5", ls=":", lw=0.8)
            # every other label a line lower: f_n/3 and f_n/2 are close on a wide range
            ax.text(s, 0.98 - 0.07 * (drawn % 2), f" f_m={label}",
                    transform=ax.get_xaxis_transform(), fontsize=7, ha="left", va="top",
                    color="0.35")
            drawn += 1


def _markers(ax: Any, c: SweepCurve, y: np.ndarray, legend: bool) -> None:
    """Marks of separation, back-side contact, no orbit and period 2 on one curve; with
    ``legend``, each kind is labelled once on ``ax`` (by the first curve that shows it)."""
    rpm = c.speed / RPM
    shown = set(ax.get_legend_handles_labels()[1])

    def label(text: str) -> str | None:
        return text if legend and text not in shown else None
    sep = np.nan_to_num(c.separation) > 0
    back = np.nan_to_num(c.backside) > 0
    aper = np.array([s == "aperiodic" for s in c.status])
    if np.any(sep):  # a legend entry only for what the sweep shows
        ax.plot(rpm[sep], y[sep], "x", color="tab:red", ms=4,
                label=label("teeth separate"))
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


def plot_sweep_response(result: SweepResult, ax: Any = None,
                        iso_kv: tuple[Any, Any] | None = None) -> Any:
    """Dynamic factor, RMS and peak-to-peak DTE against speed (top axis: f_m / f_n).

    Up and down sweeps are drawn (solid, dashed) so jumps and hysteresis show; crosses mark
    tooth separation, open triangles back-side contact, shaded bands parametric instability.
    ``ax``: 3 Axes (dynamic factor, RMS, peak-to-peak) or None. ``iso_kv``: (pinion speeds in
    rpm, ISO 6336-1 K_v) drawn beside the simulated dynamic factor.
    """
    own = ax is None
    fig, axes = axes_of(ax, 3, 1, figsize=(9, 9), name="plot_sweep_response", sharex=True)
    quantities = (("dynamic_factor", 1.0, "dynamic factor"), ("rms_dte", 1e6, "RMS DTE (µm)"),
                  ("ptp_dte", 1e6, "peak-to-peak DTE (µm)"))
    all_rpm = np.concatenate([c.speed for c in result.curves]) / RPM
    lo, hi = float(np.min(all_rpm)), float(np.max(all_rpm))
    for row, (name, scale, label) in enumerate(quantities):
        ax = axes[row]
        for c in result.curves:
            y = getattr(c, name) * scale
            style = _STYLE.get(c.direction, {})
            lab = (f"sweep {c.direction}" if len(result.curves) > 1
                   else "simulated (steady state)") if row == 0 else None
            ax.plot(c.speed / RPM, y, lw=1.1, marker=".", ms=2.5, label=lab, **style)
            _markers(ax, c, y, legend=row == 0)
            unstable = np.array([s == "unstable" for s in c.status])
            _shade(ax, c.speed / RPM, unstable, row == 0 and c is result.curves[0])
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        if row == 0:
            _resonance_marks(ax, result, lo, hi)
            if iso_kv is not None:
                ax.plot(*iso_kv, color="k", lw=1.0, ls="-.", label="ISO 6336-1 K_v (method B)")
    axes[-1].set_xlabel("pinion speed (rpm)")
    axes[0].legend(loc="best", fontsize=8, ncol=2)  # clear of the resonance peaks
    fn = result.natural_frequency
    if np.isfinite(fn):
        c = result.curves[0]
        per_rpm = c.mesh_frequency[0] / (c.speed[0] / RPM) / fn
        top = axes[0].secondary_xaxis("top", functions=(lambda s: s * per_rpm,
                                                        lambda r: r / per_rpm))
        top.set_xlabel("f_m / f_n")
    kind = "steady state (monodromy / shooting)" if result.options.method == "steady" else \
        "transient integration"
    if own:  # a caller's figure gets no title
        fig.suptitle(f"{result.scene_name}: speed sweep, {kind}", fontsize=10)
    _layout(fig, own, left=0.09, right=0.98, bottom=0.06, top=0.9, hspace=0.08)
    return fig


def _shade(ax: Any, rpm: np.ndarray, mask: np.ndarray, label: bool) -> None:
    order = np.argsort(rpm)
    r, m = rpm[order], mask[order]
    step = float(np.median(np.diff(r))) if r.size > 1 else 0.0
    first = True
    i = 0
    while i < r.size:
        if m[i]:
            j = i
            while j + 1 < r.size and m[j + 1]:
                j += 1
            ax.axvspan(r[i] - step / 2, r[j] + step / 2, color="tab:red", alpha=0.12,
                       label="parametric instability" if (label and first) else None)
            first = False
            i = j + 1
        else:
            i += 1


def _waterfall_axes(ax: Any) -> tuple[Any, Any, Any]:
    """(figure, 3-D axes, 2-D axes) of the waterfall: new, or the caller's two Axes."""
    if ax is None:
        fig = Figure(figsize=(13, 5.5))
        return fig, fig.add_subplot(1, 2, 1, projection="3d"), fig.add_subplot(1, 2, 2)
    ax3, ax2 = given_axes(ax, 2, "plot_waterfall")
    if ax3.name != "3d":
        raise ValueError("plot_waterfall: the first of the 2 Axes must be 3-D "
                         "(projection='3d')")
    return ax3.figure, ax3, ax2


def plot_waterfall(result: SweepResult, direction: str | None = None, max_lines: int = 60,
                   floor: float = 1e-4, ax: Any = None) -> Any:
    """Waterfall of DTE spectra: speed vs frequency vs amplitude.

    Left: 3-D waterfall (one line spectrum per speed, at most ``max_lines`` speeds). Right: the
    same as a map (frequency vs speed, colour = amplitude) with the mesh-harmonic lines and the
    natural frequency. Amplitudes below ``floor`` times the largest are not drawn. ``ax``: 2
    Axes, the first 3-D (``projection="3d"``), or None.
    """
    c = result.curve(direction or result.curves[0].direction)
    order = np.argsort(c.speed)
    rpm = c.speed[order] / RPM
    fm = c.mesh_frequency[order]
    amp = c.spectrum[order] * 1e6
    freq = fm[:, None] * result.orders[None, :]
    top = np.nanmax(amp) if np.any(np.isfinite(amp)) else 1.0
    own = ax is None
    fig, ax3, ax = _waterfall_axes(ax)
    pick = np.unique(np.linspace(0, rpm.size - 1, min(max_lines, rpm.size)).astype(int))
    for i in pick:
        a = amp[i]
        if not np.any(np.isfinite(a)):
            continue
        f = freq[i]
        xs = np.repeat(f, 3)
        zs = np.column_stack([np.zeros_like(a), np.nan_to_num(a), np.zeros_like(a)]).ravel()
        ax3.plot(xs / 1e3, np.full(xs.size, rpm[i]), zs, lw=0.7, color="tab:blue")
    ax3.set_xlabel("frequency (kHz)")
    ax3.set_ylabel("speed (rpm)")
    ax3.set_zlabel("DTE amplitude (µm)")
    ax3.view_init(elev=28, azim=-60)
    keep = np.isfinite(amp) & (amp > floor * top)
    sc = ax.scatter(freq[keep] / 1e3, np.broadcast_to(rpm[:, None], amp.shape)[keep],
                    c=amp[keep], s=8, cmap="viridis", norm=LogNorm(vmin=floor * top, vmax=top))
    fig.colorbar(sc, ax=ax, label="DTE amplitude (µm)")
    for k in range(1, result.options.harmonics + 1):
        ax.plot(k * fm / 1e3, rpm, color="0.6", lw=0.6, ls="--")
    fn = result.natural_frequency
    if np.isfinite(fn):
        ax.axvline(fn / 1e3, color="tab:red", lw=0.8, ls=":", label="f_n")
        ax.legend(loc="lower right", fontsize=8)
    ax.set_xlabel("frequency (kHz)  (dashed: k f_m)")
    ax.set_ylabel("speed (rpm)")
    ax.set_xlim(0, float(np.max(freq)) / 1e3)
    ax.grid(alpha=0.3)
    if own:  # a caller's figure gets no title
        fig.suptitle(f"{result.scene_name}: DTE spectra over speed (sweep {c.direction})",
                     fontsize=10)
    _layout(fig, own, left=0.02, right=0.97, bottom=0.11, top=0.9, wspace=0.12)
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
