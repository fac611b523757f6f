"""Figures of a co-simulation check: FMU over solve_ivp, and the difference against the step.

The report is a :class:`gear_dyn.fmu.cosim.CosimReport`, typed ``Any`` here: the plot layer
never imports :mod:`gear_dyn.fmu`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.ticker import NullFormatter, ScalarFormatter

from gear_dyn.plots._axes import axes_of, tidy

_LABELS = {"dte": ("DTE", "µm", 1e6), "mesh_force": ("mesh force", "kN", 1e-3),
           "driven_speed": ("driven speed", "rad/s", 1.0)}
#: units of a difference, finest last: (unit, factor from SI), per output
_DIFF_UNITS = {"dte": (("µm", 1e6), ("nm", 1e9), ("pm", 1e12), ("fm", 1e15)),
               "mesh_force": (("kN", 1e-3), ("N", 1.0), ("mN", 1e3), ("µN", 1e6)),
               "driven_speed": (("rad/s", 1.0), ("mrad/s", 1e3), ("µrad/s", 1e6))}


def diff_unit(name: str, diff: Any) -> tuple[str, float]:
    """(unit, factor from SI) in which the largest ``|diff|`` reads as at least 1, so the axis
    needs no offset or power-of-ten multiplier (a difference of picometres in pm, not 1e-6 um);
    the coarsest unit if the difference is larger, or zero."""
    units = _DIFF_UNITS.get(name)
    if units is None:
        return _LABELS.get(name, (name, "SI", 1.0))[1:]
    top = float(np.max(np.abs(diff))) if np.size(diff) else 0.0
    for unit, f in units:
        if top * f >= 1.0:
            return unit, f
    return units[-1] if top > 0 else units[0]


def overlay_figure(report: Any, periods: float = 5.0, ax: Any = None) -> Any:
    """FMU (finest communication step) over the solve_ivp reference for the last ``periods``
    mesh periods, one row per output, with the difference below each; the DTE difference with
    the band the verdict allows (``report.bounds``, if any) and the verdict in the title.

    ``report``: a CosimReport; ``ax``: 2 Axes per output (overlay, difference) or None.
    """
    n = len(report.outputs)
    fig, axes = axes_of(ax, 2 * n, 1, figsize=(8, 3.2 * n + 1), name="overlay_figure",
                        squeeze=False, sharex=True, gridspec_kw={"height_ratios": [3, 1] * n})
    axes = axes[:, 0]
    t = report.t
    keep = t >= t[-1] - periods / report.mesh_frequency
    tm = t[keep] * 1e3
    h = min(s.step for s in report.steps)
    bounds = report.bounds
    for i, name in enumerate(report.outputs):
        title, unit, f = _LABELS.get(name, (name, "SI", 1.0))
        a, d = axes[2 * i], axes[2 * i + 1]
        a.plot(tm, report.ref_y[i][keep] * f, color="0.2", lw=2.2,
               label=f"solve_ivp {report.reference_method}")
        a.plot(tm, report.fmu_y[i][keep] * f, color="tab:orange", lw=1.0, ls="--",
               label=f"FMU via fmpy, step {h * 1e6:.3g} us")
        a.set_ylabel(f"{title} ({unit})")
        a.legend(loc="upper right", fontsize=8)
        diff = report.fmu_y[i][keep] - report.ref_y[i][keep]
        dunit, df = diff_unit(name, diff)
        d.plot(tm, diff * df, color="tab:red", lw=0.8)
        if name == "dte" and bounds is not None:
            for sign in (1, -1):
                d.axhline(sign * bounds.total * df, color="0.4", lw=0.8, ls=":",
                          label="allowed (FMU + solve_ivp error)" if sign > 0 else None)
            d.legend(loc="upper right", fontsize=7)
        d.ticklabel_format(axis="y", useOffset=False)
        d.set_ylabel(f"diff ({dunit})")
    axes[-1].set_xlabel("time (ms)")
    verdict = "" if bounds is None else f": {'PASS' if report.passed else 'FAIL'}"
    axes[0].set_title(f"{report.scene_name}: FMU ({report.fmu_method}) against solve_ivp "
                      f"(rtol {report.rtol:g}){verdict}")
    tidy(fig)
    return fig


def convergence_figure(report: Any, ax: Any = None) -> Any:
    """Max and RMS difference (relative to each output's RMS) and FMU run time per step,
    against the communication step; the DTE difference the verdict allows, if any.

    ``report``: a CosimReport; ``ax``: 2 Axes (difference, run time) or None.
    """
    fig, (a, b) = axes_of(ax, 1, 2, figsize=(10, 4), name="convergence_figure")
    hs = np.array([s.step for s in report.steps]) * 1e6
    for name in report.outputs:
        scale = report.scales[name]
        a.loglog(hs, [max(s.max_diff[name] / scale, 1e-17) for s in report.steps], "o-",
                 label=f"{name} max")
        a.loglog(hs, [max(s.rms_diff[name] / scale, 1e-17) for s in report.steps], "s--",
                 label=f"{name} RMS")
    a.axhline(report.rtol, color="0.5", lw=0.8, ls=":", label="rtol")
    bounds = report.bounds
    if bounds is not None and "dte" in report.scales:
        a.axhline(bounds.total / report.scales["dte"], color="tab:blue", lw=1.0, ls="-.",
                  label="allowed dte max (verdict)")
    a.set_xlabel("communication step (us)")
    a.set_ylabel("|FMU - solve_ivp| / RMS of the output")
    a.legend(fontsize=8)
    b.loglog(hs, [s.fmu_run_time_s for s in report.steps], "o-", label="FMU (fmpy)")
    b.axhline(report.reference_run_time_s, color="0.2", ls="--", label="solve_ivp (one run)")
    b.set_xlabel("communication step (us)")
    b.set_ylabel("run time (s)")
    b.legend(fontsize=8)
    for axis in (a.xaxis, b.xaxis, b.yaxis):
        axis.set_major_formatter(ScalarFormatter())
        axis.set_minor_formatter(NullFormatter())
    if ax is None:  # a caller's figure gets no title and keeps its layout
        fig.suptitle(f"{report.scene_name}: difference and cost against the communication step")
        tidy(fig)
    return fig
