"""Work-precision figure of a solver benchmark (pyplot-free matplotlib Figure)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from gear_dyn.analysis.bench import BenchReport
from gear_dyn.plots._axes import axes_of, tidy

_MARKERS = {"RK45": "o", "DOP853": "s", "Radau": "^", "BDF": "v", "LSODA": "D", "RK23": "x",
            "periodic": "P"}


def plot_work_precision(report: BenchReport, targets: Sequence[float] = (1e-6,),
                        ax: Any = None) -> Any:
    """Max error (relative to the static deflection) against run time, log-log.

    One line per method and mode through its tolerances (tightest at the right), the exact
    propagator as a star, the target errors as dashed lines. Returns the figure.
    """
    fig, ax = axes_of(ax, figsize=(7, 5), name="plot_work_precision")
    groups: dict[str, list[Any]] = {}
    for c in report.cases:
        if c.status == "ok" and math.isfinite(c.err_max):
            groups.setdefault(c.label, []).append(c)
    floor = 1e-16
    for label, cs in groups.items():
        cs = sorted(cs, key=lambda c: -c.rtol)
        err = [max(c.err_max, floor) for c in cs]
        tm = [c.run_time_s for c in cs]
        if label == "exact":
            ax.loglog(tm, err, "*", ms=14, color="k", label="exact propagator")
            continue
        mk = _MARKERS.get(cs[0].method, "o")
        ls = "--" if cs[0].mode == "once" else "-"
        (line,) = ax.loglog(tm, err, ls, marker=mk, label=label)
        for c, e in zip(cs, err, strict=True):
            ax.annotate(f"{c.rtol:.0e}", (c.run_time_s, e), fontsize=6, xytext=(3, 3),
                        textcoords="offset points", color=line.get_color())
    for tgt in targets:
        ax.axhline(tgt, color="tab:red", ls=":", lw=0.8)
    ax.set_xlabel("run time (s, median of repeats)")
    ax.set_ylabel("max |x - x_ref| / static deflection")
    ax.set_title(f"{report.name}: {report.n_periods:.0f} mesh periods", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8, loc="best")
    tidy(fig)
    return fig
