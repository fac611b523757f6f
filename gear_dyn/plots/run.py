"""Figures of simulation results (pyplot-free matplotlib Figures; no window, no backend choice).

Plots are functions of results: they take an optional ``ax`` and return the figure.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gear_dyn.analysis.spectrum import amplitude_spectrum
from gear_dyn.plots._axes import axes_of, tidy
from gear_dyn.solvers import Result


def plot_time_history(result: Result, periods: float | None = 10.0, ax: Any = None) -> Any:
    """DTE and dynamic mesh force against time, the steady-state window shaded.

    Parameters
    ----------
    result : Result
    periods : float or None
        Also draws a zoom on the last ``periods`` mesh periods (None: no zoom).
    ax : sequence of Axes or None
        2 Axes (DTE, force), or 4 with a zoom (row-major: DTE, DTE zoom, force, force zoom).
    """
    ncols = 2 if periods else 1
    fig, axes = axes_of(ax, 2, ncols, figsize=(6 * ncols, 6), name="plot_time_history",
                        squeeze=False, sharex="col")
    t = result.t
    dte = result.outputs["dte"] * 1e6
    force = result.outputs["mesh_force"] / 1e3
    for col in range(ncols):
        sel = slice(None)
        if col == 1 and periods:
            sel = t >= t[-1] - periods / result.mesh_frequency
        for ax, y, label in ((axes[0, col], dte, "DTE x (µm)"),
                             (axes[1, col], force, "mesh force (kN)")):
            ax.plot(t[sel] * 1e3, y[sel], lw=0.8)
            ax.set_ylabel(label)
            ax.grid(alpha=0.3)
            if col == 0:
                ax.axvspan(result.steady_start * 1e3, t[-1] * 1e3, color="tab:green", alpha=0.1,
                           label="steady-state window")
        axes[1, col].set_xlabel("time (ms)")
    axes[0, 0].legend(loc="upper right", fontsize=8)
    axes[1, 0].axhline(result.static_load / 1e3, color="k", ls="--", lw=0.7, label="W")
    axes[1, 0].legend(loc="upper right", fontsize=8)
    if periods:
        axes[0, 1].set_title(f"last {periods:g} mesh periods")
    axes[0, 0].set_title("whole run")
    tidy(fig)
    return fig


def plot_spectrum(result: Result, name: str = "dte", harmonics: int = 5, ax: Any = None) -> Any:
    """Amplitude spectrum of a series over the steady window, mesh harmonics marked."""
    fig, ax = axes_of(ax, figsize=(8, 4), name="plot_spectrum")
    mask = result.steady
    f, amp = amplitude_spectrum(result.t[mask], result.series(name)[mask])
    scale, unit = (1e6, "µm") if name in ("dte", "x") else (1.0, "")
    ax.semilogy(f, np.maximum(amp * scale, 1e-12), lw=0.8)
    fm = result.mesh_frequency
    for n in range(1, harmonics + 1):
        if n * fm <= f[-1]:
            ax.axvline(n * fm, color="tab:red", ls=":", lw=0.8)
            ax.text(n * fm, ax.get_ylim()[1], f"{n}f_m", color="tab:red", fontsize=8,
                    ha="center", va="bottom")
    ax.set_xlim(0, min(f[-1], (harmonics + 0.5) * fm))
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel(f"amplitude of {name}" + (f" ({unit})" if unit else ""))
    ax.grid(alpha=0.3, which="both")
    tidy(fig)
    return fig
