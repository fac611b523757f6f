"""The jump map: where in (pinion speed, torque) the response has coexisting orbits and a sweep
jumps. Each region between two fold curves is shaded, the fold curves drawn (the lower fold
where a sweep down jumps, the upper where a sweep up jumps), cusps marked, and the scene's
torque drawn as a dotted line.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gear_dyn.analysis.continuation.jump_map import FoldMap
from gear_dyn.analysis.sweep import RPM
from gear_dyn.plots._axes import axes_of, tidy
from gear_dyn.plots.continuation import _COLOURS


def plot_fold_map(fold_map: FoldMap, ax: Any = None) -> Any:
    """Draw a :class:`~gear_dyn.analysis.continuation.FoldMap`: speed (rpm) across, torque
    (N m) up.

    Parameters
    ----------
    fold_map : FoldMap
    ax : matplotlib Axes or None
        Axes to draw into; None makes a new figure.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, axis = axes_of(ax, figsize=(7, 4.5), name="plot_fold_map")
    for i, r in enumerate(fold_map.regions):
        c = _COLOURS[i % len(_COLOURS)]
        lo, hi, t = r.low / RPM, r.high / RPM, r.torque
        xs, ts = np.concatenate([lo, hi[::-1]]), np.concatenate([t, t[::-1]])
        for cusp in r.cusps:  # close the band at its cusp
            at_top = cusp.torque > t[-1]
            pt_x, pt_t = np.array([cusp.speed / RPM]), np.array([cusp.torque])
            if at_top:
                xs = np.concatenate([lo, pt_x, hi[::-1]])
                ts = np.concatenate([t, pt_t, t[::-1]])
            else:
                xs = np.concatenate([pt_x, lo, hi[::-1]])
                ts = np.concatenate([pt_t, t, t[::-1]])
        axis.fill(xs, ts, color=c, alpha=0.25, lw=0,
                  label=f"jump region {i + 1}")
        axis.plot(lo, t, "-", color=c, lw=1.5, marker=".", ms=4)
        axis.plot(hi, t, "--", color=c, lw=1.5, marker=".", ms=4)
        for cusp in r.cusps:
            axis.plot([cusp.speed / RPM], [cusp.torque], "k*", ms=10)
            axis.annotate(f"cusp {cusp.speed / RPM:.0f} rpm, {cusp.torque:.4g} N m",
                          (cusp.speed / RPM, cusp.torque), textcoords="offset points",
                          xytext=(6, 6), fontsize=8, bbox={"facecolor": "white", "alpha": 0.8,
                                                           "edgecolor": "none", "pad": 0.5})
    if fold_map.reference_torque is not None:
        axis.axhline(fold_map.reference_torque, color="0.4", ls=":", lw=1,
                     label=f"scene torque {fold_map.reference_torque:.4g} N m")
    axis.fill([], [], color="0.6", alpha=0.25, lw=0, label="shaded: coexisting stable orbits")
    axis.plot([], [], "k-", label="lower fold (sweep down jumps)")
    axis.plot([], [], "k--", label="upper fold (sweep up jumps)")
    axis.set_xlim(min(fold_map.speed_range) / RPM, max(fold_map.speed_range) / RPM)
    axis.set_ylim(float(np.min(fold_map.torques)), float(np.max(fold_map.torques)))
    axis.set_xlabel("pinion speed (rpm)")
    axis.set_ylabel("pinion torque (N m)")
    axis.set_title("jump map: folds of the periodic orbits in speed and torque")
    axis.legend(fontsize=8, loc="best")
    axis.grid(alpha=0.3)
    if ax is None:
        tidy(fig)
    return fig
