"""The response curve of a continuation: branches of periodic orbits against the parameter,
stable solid, unstable dashed, folds and period doublings marked and labelled with their value
(the figure of Kahraman & Singh 1990, fig. 7, with the unstable branch drawn).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gear_dyn.analysis.continuation.branch import Branch
from gear_dyn.analysis.motion.diagram import RPM
from gear_dyn.plots._axes import axes_of, tidy
from gear_dyn.plots._labels import label_marks, legend_once

#: y quantities: OrbitPoint field -> (axis label, factor to the plotted unit)
QUANTITIES = {
    "dte_rms": ("RMS DTE (µm)", 1e6),
    "dte_ptp": ("peak-to-peak DTE (µm)", 1e6),
    "dte_mean": ("mean DTE (µm)", 1e6),
    "separation": ("teeth apart (share of the period)", 1.0),
}
_COLOURS = ("tab:blue", "tab:red", "tab:green", "tab:purple", "tab:brown")


def _x_of(branch: Branch) -> tuple[float, str]:
    """Factor from the SI parameter to the plotted unit, and the axis label."""
    if branch.parameter_name == "speed":
        return 1.0 / RPM, "pinion speed (rpm)"
    if branch.parameter_name == "backlash":
        return 1e6, "half gap (µm)"
    unit = f" ({branch.unit})" if branch.unit else ""
    return 1.0, f"{branch.parameter_name}{unit}"


def _fmt(value: float, branch: Branch) -> str:
    fx, _ = _x_of(branch)
    unit = {"speed": " rpm", "backlash": " um"}.get(branch.parameter_name,
                                                     f" {branch.unit}" if branch.unit else "")
    return f"{value * fx:.6g}{unit}"


#: located points a branch's stretches end at (its stability changes there)
_LOCATED = ("fold", "period_doubling")


def _stretches(branch: Branch) -> tuple[list[tuple[str, int]], list[tuple[bool, slice]]]:
    """The branch's points with its located folds and period doublings in between, and its
    stable and unstable stretches.

    Returns ``(items, pieces)``: ``items`` in order along the branch, ``("point", i)`` for
    ``branch.points[i]`` and ``("mark", j)`` for the j-th fold or period doubling of
    ``branch.bifurcations`` (inserted by arclength); ``pieces`` as ``(stable, slice of
    items)``. A stretch ends at the located point where the stability changes, which it
    shares with the next stretch; where none was located (detection off, or a located point
    without an arclength) it is joined to the previous stretch's last point, as the points
    alone allow.
    """
    s = np.array([p.arclength for p in branch.points], dtype=float)
    s = np.where(np.isfinite(s), s, np.inf)  # the last point, clipped at the range end
    marks = [x for x in branch.bifurcations if x.kind in _LOCATED]
    keyed = [((i, 1), ("point", i)) for i in range(len(branch.points))]
    keyed += [((int(np.searchsorted(s, x.point.arclength, side="right")), 0), ("mark", j))
              for j, x in enumerate(marks) if np.isfinite(x.point.arclength)]
    items = [it for _, it in sorted(keyed)]
    regular = [k for k, (kind, _) in enumerate(items) if kind == "point"]
    stable = [branch.points[items[k][1]].stable for k in regular]
    pieces: list[tuple[bool, slice]] = []
    a = 0
    for e in range(1, len(regular) + 1):
        if e < len(regular) and stable[e] == stable[a]:
            continue
        lo, hi = regular[a], regular[e - 1]
        if lo > 0:  # the located point before, or the previous stretch's last point
            lo -= 1
        if hi + 1 < len(items) and items[hi + 1][0] == "mark":
            hi += 1
        pieces.append((stable[a], slice(lo, hi + 1)))
        a = e
    return items, pieces


def plot_branch(branch: Branch, ax: Any = None, y: str = "dte_rms", label_points: bool = True,
                sweep: Any = None) -> Any:
    """Draw a branch and its children (period-2n branches) against the parameter.

    Parameters
    ----------
    branch : Branch
    ax : matplotlib Axes or None
        None: a new figure.
    y : str
        Quantity on the y axis: ``dte_rms``, ``dte_ptp``, ``dte_mean`` or ``separation``.
    label_points : bool
        Write each fold's and period doubling's parameter value next to its mark.
    sweep : SweepResult or None
        A speed sweep of the same scene
        (:func:`gear_dyn.sweep_scene <gear_dyn.scene.sweep.sweep_scene>`) drawn over the branch:
        its periodic points up and down, and its jumps between two periodic points as arrows
        from the speed before to the speed after (speed branches only).

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ValueError
        An unknown ``y``.
    """
    if y not in QUANTITIES:
        raise ValueError(f"y = {y!r}: valid choices are {', '.join(QUANTITIES)}")
    fig, axis = axes_of(ax, figsize=(10, 4.5), name="plot_branch")
    ylabel, fy = QUANTITIES[y]
    fx, xlabel = _x_of(branch)
    once = legend_once()

    labels: list[tuple[float, float, str]] = []
    crosses: list[tuple[float, float]] = []  # the grazing marks
    for b in branch.walk():
        if not b.points:
            continue
        colour = _COLOURS[min(b.periods.bit_length() - 1, len(_COLOURS) - 1)]
        items, pieces = _stretches(b)
        located = [x.point for x in b.bifurcations if x.kind in _LOCATED]
        orbits = [b.points[i] if kind == "point" else located[i] for kind, i in items]
        px = np.array([p.parameter for p in orbits]) * fx
        py = np.array([getattr(p, y) for p in orbits]) * fy
        for st, sl in pieces:
            name = f"period-{b.periods} {'stable' if st else 'unstable'}"
            axis.plot(px[sl], py[sl], color=colour, ls="-" if st else "--", lw=1.4,
                      label=once(name))
        for bif in b.bifurcations:
            if bif.kind not in ("fold", "period_doubling"):
                continue
            bx, by = bif.parameter * fx, getattr(bif.point, y) * fy
            marker, text = ("o", "fold") if bif.kind == "fold" else ("s", "PD")
            axis.plot([bx], [by], marker, color="k", mfc="none", ms=7,
                      label=once("fold" if bif.kind == "fold" else "period doubling"))
            labels.append((bx, by, f"{text} {_fmt(bif.parameter, branch)}"))
        graze = [g for g in b.bifurcations if g.kind == "grazing"]
        crosses += [(g.parameter * fx, getattr(g.point, y) * fy) for g in graze]
        if graze:
            axis.plot([g.parameter * fx for g in graze], [getattr(g.point, y) * fy for g in graze],
                      "x", color="0.4", ms=5, label=once("grazing (contact pattern changes)"))
    if sweep is not None:
        _overlay_sweep(axis, sweep, y, fx, fy)
    axis.set_xlabel(xlabel)
    axis.set_ylabel(ylabel)
    axis.grid(True, alpha=0.3)
    label_marks(axis, labels if label_points else [], own_figure=ax is None, layout=tidy,
                avoid=crosses)  # no label on a grazing mark either
    return fig


#: OrbitPoint field -> SweepCurve field
_SWEEP_FIELDS = {"dte_rms": "rms_dte", "dte_ptp": "ptp_dte", "dte_mean": "mean_dte",
                 "separation": "separation"}


def _overlay_sweep(axis: Any, sweep: Any, y: str, fx: float, fy: float) -> None:
    """The sweep's periodic points (up: triangles up, down: triangles down) and its jumps."""
    for curve in sweep.curves:
        values = getattr(curve, _SWEEP_FIELDS[y]) * fy
        keep = np.asarray(curve.periodic, bool)
        marker = "^" if curve.direction == "up" else "v"
        axis.plot(curve.speed[keep] * fx, values[keep], marker, ms=3.5, mfc="none",
                  color="0.35", ls="none", label=f"sweep {curve.direction} (periodic orbits)")
        for jump in curve.jumps:
            i = int(np.argmin(np.abs(curve.speed - jump.from_speed)))
            j = int(np.argmin(np.abs(curve.speed - jump.to_speed)))
            if not (keep[i] and keep[j]):  # from or to a speed with no periodic orbit drawn
                continue
            axis.annotate("", (curve.speed[j] * fx, values[j]), (curve.speed[i] * fx, values[i]),
                          arrowprops={"arrowstyle": "->", "color": "0.35", "lw": 0.8})
