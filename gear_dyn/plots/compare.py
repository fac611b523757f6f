"""The design-comparison figure: peak force and RMS DTE against speed, peak force against the
baseline (pyplot-free matplotlib Figure)."""

from __future__ import annotations

from typing import Any

import numpy as np

from gear_dyn.analysis.compare import Comparison
from gear_dyn.analysis.sweep import RPM
from gear_dyn.plots._axes import axes_of, tidy

#: line styles cycled with the ten default colours: designs 1-10 solid, 11-20 dashed ...
_DASHES = ("-", "--", "-.", ":")
#: flags shown on the bar chart (short text beside the bar)
_FLAG_TEXT = {"peak_at_range_end": "peak at range end",
              "linear_model_invalid_at_peak": "F < 0: linear invalid",
              "teeth_separate_at_peak": "teeth separate",
              "operating_speed_outside_range": "oper. speed off range"}


def design_style(i: int) -> dict[str, Any]:
    """Colour and line style of the ``i``-th design: matplotlib's ten default colours, then
    the same colours dashed, dash-dotted, dotted (40 distinct styles)."""
    return {"color": f"C{i % 10}", "ls": _DASHES[(i // 10) % len(_DASHES)]}


def _short(name: str, width: int = 28) -> str:
    return name if len(name) <= width else name[:width - 1] + "…"


def plot_comparison(comparison: Comparison, ax: Any = None) -> Any:
    """Designs side by side: F_max / W and RMS DTE against speed, and the peak F_max / W of
    each design against the baseline's.

    Left, one line per design (its colour and style, the same in all panels; a sweep down
    thinner, where the model has backlash): the peak dynamic mesh force over the static load
    F_max / W (top; a star marks each design's peak, a circle its operating speed) and the RMS
    DTE (bottom). Right: one bar per design, rank order, the peak F_max / W with its change
    from the baseline (the first design) in per cent; a flag beside the bar where the peak lies
    at an end of the range or where a linear model's force goes negative. One legend entry per
    design, below the panels.

    Parameters
    ----------
    comparison : Comparison
        From :func:`gear_dyn.compare_scenes <gear_dyn.scene.compare.compare_scenes>` or
        :func:`gear_dyn.analysis.compare.compare_sweeps`.
    ax : sequence of 3 Axes or None
        Peak force against speed, RMS DTE against speed, bar chart (None: a new figure).

    Returns
    -------
    matplotlib.figure.Figure
    """
    own = ax is None
    n = len(comparison.names)
    ncol = min(n, 4)
    legend_rows = -(-n // ncol)
    height = 6.5 + 0.22 * legend_rows
    if own:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(13, height))
        grid = fig.add_gridspec(2, 2, width_ratios=(2.0, 1.0))
        a_force = fig.add_subplot(grid[0, 0])
        a_dte = fig.add_subplot(grid[1, 0], sharex=a_force)
        a_bar = fig.add_subplot(grid[:, 1])
    else:
        fig, axes = axes_of(ax, 3, 1, name="plot_comparison")
        a_force, a_dte, a_bar = axes
    handles = []
    for i, (name, res, row) in enumerate(zip(comparison.names, comparison.sweeps,
                                             comparison.designs, strict=True)):
        st = design_style(i)
        for c in res.curves:
            down = c.direction == "down"
            kw = dict(lw=0.8 if down else 1.4, alpha=0.6 if down else 1.0, **st)
            line, = a_force.plot(c.speed / RPM, c.peak_force_ratio, **kw)
            a_dte.plot(c.speed / RPM, c.rms_dte * 1e6, **kw)
            if c is res.curves[0]:
                line.set_label(_short(name) + (" (baseline)" if i == 0 else ""))
                handles.append(line)
        if np.isfinite(row["peak_peak_force_ratio"]):
            a_force.plot([row["peak_peak_force_ratio_speed_rpm"]], [row["peak_peak_force_ratio"]],
                         "*", ms=11, color=st["color"], mec="k", mew=0.6)
        if np.isfinite(row["operating_peak_force_ratio"]):
            a_force.plot([row["operating_speed_rpm"]], [row["operating_peak_force_ratio"]],
                         "o", ms=6, color=st["color"], mec="k", mew=0.6)
    a_force.set_ylabel("peak mesh force F_max / W")
    a_dte.set_ylabel("RMS DTE (µm)")
    a_dte.set_xlabel("pinion speed (rpm)")
    lo, hi = comparison.speed_range_rpm
    a_force.set_xlim(lo - 0.02 * (hi - lo), hi + 0.02 * (hi - lo))
    for a in (a_force, a_dte):
        a.grid(alpha=0.3)
    a_force.tick_params(labelbottom=False)
    a_force.set_title("star: peak over the range; circle: operating speed", fontsize=8)
    # bars in rank order, the best on top
    order = [comparison.names.index(nm) for nm in comparison.ranking]
    ypos = np.arange(len(order))[::-1]
    base = comparison.designs[0]["peak_peak_force_ratio"]
    top = max((comparison.designs[k]["peak_peak_force_ratio"] for k in order
               if np.isfinite(comparison.designs[k]["peak_peak_force_ratio"])), default=1.0)
    for y, k in zip(ypos, order, strict=True):
        row = comparison.designs[k]
        v = row["peak_peak_force_ratio"]
        st = design_style(k)
        a_bar.barh(y, v if np.isfinite(v) else 0.0, height=0.6, color=st["color"], alpha=0.85,
                   hatch="//" if k == 0 else None, edgecolor="k", lw=0.5)
        pct = row["peak_peak_force_ratio_delta_pct"]
        text = (f" {v:.3g}" + ("  baseline" if k == 0 else f"  {pct:+.1f} %")
                if np.isfinite(v) else " no finite peak")
        flags = [_FLAG_TEXT[f] for f in row["flags"] if f in _FLAG_TEXT]
        if flags:
            text += "\n ! " + ",\n   ".join(flags)
        a_bar.text(v if np.isfinite(v) else 0.0, y, text, va="center", ha="left", fontsize=7.5)
    if np.isfinite(base):
        a_bar.axvline(base, color="k", lw=0.8, ls="--")
    a_bar.set_yticks(ypos, [f"{comparison.designs[k]['rank'] or '-'}. "
                            f"{_short(comparison.names[k], 22)}" for k in order], fontsize=8)
    a_bar.set_xlim(0, 2.0 * top)
    a_bar.set_ylim(-0.7, len(order) - 0.3)  # room for the value, the change and the flags
    a_bar.set_xlabel("peak F_max / W over the range")
    a_bar.set_title("peak force vs baseline (dashed), best on top", fontsize=9)
    a_bar.grid(axis="x", alpha=0.3)
    if own:
        fig.legend(handles=handles, loc="lower center", ncol=ncol, fontsize=8, frameon=False,
                   bbox_to_anchor=(0.5, 0.0))
        fig.suptitle(f"{n} designs by peak dynamic mesh force F_max / W (baseline: "
                     f"{_short(comparison.baseline, 40)})", fontsize=11)
        bottom = (0.65 + 0.22 * legend_rows) / height
        fig.subplots_adjust(left=0.06, right=0.98, top=1 - 0.55 / height, bottom=bottom,
                            wspace=0.38, hspace=0.08)
    else:
        a_force.legend(handles=handles, fontsize=7, loc="best")
        tidy(fig)
    return fig


__all__ = ["design_style", "plot_comparison"]
