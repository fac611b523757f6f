"""Figures of mesh stiffness (pyplot-free matplotlib): curves over mesh cycles, component split."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from gear_dyn.plots._axes import axes_of, tidy
from gear_dyn.stiffness.periodic import PeriodicStiffness
from gear_dyn.stiffness.potential_energy import PairCompliance


def plot_stiffness_curves(curves: Mapping[str, PeriodicStiffness], contact_ratio: float,
                          cycles: float = 2.0, points_per_cycle: int = 800,
                          ax: Any = None, transverse_note: bool = False) -> Any:
    """k(p) of several methods over ``cycles`` mesh cycles, double-contact zones shaded.

    Parameters
    ----------
    curves : mapping of name -> PeriodicStiffness
    contact_ratio : float
        Transverse contact ratio; phases [n, n + frac(eps_a)] (more pairs in contact) are shaded.
    cycles : float
        Mesh cycles shown (> 0).
    points_per_cycle : int
        Plot resolution.
    ax : matplotlib Axes or None
    transverse_note : bool
        Say that the shaded zones count pairs in the transverse section (helical pairs).

    Returns
    -------
    matplotlib Figure
    """
    where = "transverse section: " if transverse_note else ""
    fig, ax = axes_of(ax, figsize=(9, 4.5), name="plot_stiffness_curves")
    n_pts = max(int(points_per_cycle * cycles), 10)
    p = np.linspace(0.0, cycles, n_pts + 1)
    f = contact_ratio - math.floor(contact_ratio)
    n_low = int(math.floor(contact_ratio))
    for c in range(int(math.ceil(cycles))):
        if f > 1e-9:
            ax.axvspan(c, min(c + f, cycles), color="0.9", lw=0,
                       label=f"{where}{n_low + 1} pairs in contact" if c == 0 else None)
    for name, k in curves.items():
        sw = k.switching_phases
        # insert both sides of each jump so the plot shows it vertical
        extra = np.concatenate([(c + sw) for c in range(int(math.ceil(cycles)) + 1)])
        extra = extra[(extra > 0) & (extra < cycles)]
        pp = np.sort(np.concatenate([p, extra - 1e-9, extra + 1e-9]))
        ax.plot(pp, k(pp) / 1e8, lw=1.2, label=f"{name} (mean {k.mean / 1e8:.3g})")
    ax.set_xlabel(f"mesh phase (cycles; unshaded: {where}{n_low} pair{'s' if n_low > 1 else ''})")
    ax.set_ylabel("mesh stiffness k (1e8 N/m)")
    ax.set_xlim(0, cycles)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    ax.set_title(f"mesh stiffness over {cycles:g} mesh cycles (eps_a = {contact_ratio:.3f})")
    tidy(fig)
    return fig


def plot_components(comp: PairCompliance, title: str = "", ax: Any = None) -> Any:
    """Bar chart of the compliance split of one tooth pair (one contact position).

    Bars: Hertz (pair), then bending, shear, axial, fillet foundation of pinion and gear, in
    1e-10 m/N, with the share of the total compliance printed on each bar.
    """
    fig, ax = axes_of(ax, figsize=(8, 4), name="plot_components")
    labels, vals = ["Hertz"], [float(np.ravel(comp.hertz)[0])]
    for term in ("bending", "shear", "axial", "fillet"):
        arr = np.asarray(getattr(comp, term))
        for g, who in ((0, "pinion"), (1, "gear")):
            labels.append(f"{term}\n{who}")
            vals.append(float(np.ravel(arr[g])[0]))
    total = float(np.ravel(comp.total)[0])
    v = np.array(vals) * 1e10
    bars = ax.bar(range(len(v)), v, color=["C3"] + ["C0", "C1"] * 4)
    for b, val in zip(bars, vals, strict=True):
        ax.annotate(f"{100 * val / total:.0f}%", (b.get_x() + b.get_width() / 2, b.get_height()),
                    ha="center", va="bottom", fontsize=8)
    ax.set_xticks(range(len(v)), labels, fontsize=8)
    ax.set_ylabel("compliance (1e-10 m/N)")
    ax.set_title(title or f"compliance split, pair stiffness {1 / total:.4g} N/m")
    ax.grid(True, axis="y", alpha=0.3)
    tidy(fig)
    return fig
