"""Bifurcation diagrams: stroboscopic samples against speed (pyplot-free Figures).

:func:`plot_bifurcation` draws a brute-force diagram (settled samples, up and down);
:func:`plot_branch_samples` the samples of a continuation's orbits, stable and unstable, with
a brute-force diagram behind them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.axes import Axes
from numpy.typing import NDArray

from gear_dyn.analysis.motion.diagram import RPM, BifurcationDiagram
from gear_dyn.errors import InputError
from gear_dyn.plots._axes import axes_of, tidy
from gear_dyn.plots._labels import label_marks, legend_once

if TYPE_CHECKING:
    from gear_dyn.analysis.continuation.strobe import BranchSamples
    from gear_dyn.analysis.motion.classify import Motion

FloatArray = NDArray[np.float64]
_STYLE = {"up": dict(color="tab:blue", marker="."), "down": dict(color="tab:orange", marker="x")}
#: display unit of each state component: (scale from SI, unit text)
_UNITS = {"x": (1e6, "µm"), "v": (1.0, "m/s")}


def plot_bifurcation(diagram: BifurcationDiagram, ax: Any = None, state: str = "x",
                     title: str | None = None) -> Any:
    """Stroboscopic samples of one state component against pinion speed, up and down.

    Parameters
    ----------
    diagram : BifurcationDiagram
    ax : Axes, two Axes or None
        Where to draw. None: a new figure of 8 x 4.5 in, or, where the diagram was classified
        (some speed has a Lyapunov exponent), of 8 x 6 in with a second panel below: the
        largest Lyapunov exponent with its error bar at the speeds where no periodic orbit
        was found (positive: chaos). A
        caller's single Axes gets the samples only; two Axes get both panels.
    state : str
        State component to draw (``x``: mesh deflection in um; ``v``: its rate in m/s).
    title : str or None
        Axes title (default: the scene name and what is drawn).

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    InputError
        ``state`` is not one of the diagram's state labels.
    """
    if state not in diagram.state_labels:
        raise InputError(f"state = {state!r}: valid choices are "
                         f"{', '.join(diagram.state_labels)}")
    i = diagram.state_labels.index(state)
    factor, unit = _UNITS.get(state, (1.0, "SI"))
    classified = any(np.isfinite(c.lyapunov).any() for c in diagram.curves)
    panels = 2 if classified and (ax is None or not isinstance(ax, Axes)) else 1
    if panels == 2:
        fig, (axes, lower) = axes_of(ax, nrows=2, figsize=(8, 6), name="plot_bifurcation",
                                     sharex=True, gridspec_kw={"height_ratios": (3, 1)})
    else:
        fig, axes = axes_of(ax, figsize=(8, 4.5), name="plot_bifurcation")
    both = len(diagram.curves) > 1
    for c in diagram.curves:
        n_s = c.samples.shape[1]
        rpm = np.repeat(c.speed / RPM, n_s)
        # up and down: side by side, a little apart, where both are drawn
        shift = 0.0
        if both and c.speed.size > 1:
            shift = (0.15 if c.direction == "up" else -0.15) * float(
                np.min(np.diff(np.sort(c.speed)))) / RPM
        axes.plot(rpm + shift, c.samples[:, :, i].ravel() * factor, ls="none", ms=2.5,
                  alpha=0.7, label=f"sweep {c.direction}", **_STYLE[c.direction])
    gone = [c.speed[i] / RPM for c in diagram.curves for i in range(c.speed.size)
            if c.label[i] == "unbounded"]
    if gone:
        axes.plot(gone, np.zeros(len(gone)), ls="none", marker="|", ms=10, color="0.4",
                  transform=axes.get_xaxis_transform(), clip_on=False,
                  label="unbounded (diverges)")
    if panels == 2:
        _plot_lyapunov(lower, diagram)
    else:
        axes.set_xlabel("pinion speed (rpm)")
    axes.set_ylabel(f"{state} at t = k T_m ({unit})")
    if title is None:
        name = f"{diagram.scene_name}: " if diagram.scene_name else ""
        title = (f"{name}bifurcation diagram ({diagram.options.samples} samples per speed "
                 f"after {diagram.options.settle} mesh periods)")
    axes.set_title(title, fontsize=10, pad=20 if np.isfinite(diagram.natural_frequency) else 6)
    fn, c = diagram.natural_frequency, diagram.curves[0]
    if np.isfinite(fn) and c.speed.size and c.speed[0] > 0:
        per = fn * c.speed[0] / (c.mesh_frequency[0] * RPM)  # rpm per unit f_m / f_n
        top = axes.secondary_xaxis("top", functions=(lambda r: r / per, lambda q: q * per))
        top.set_xlabel("f_m / f_n")
    axes.legend(loc="best", fontsize=8, markerscale=2)
    axes.grid(alpha=0.3)
    tidy(fig)
    return fig


def _plot_lyapunov(axes: Any, diagram: BifurcationDiagram) -> None:
    """Largest Lyapunov exponent (1/s) with its error bar, per direction, where classified."""
    for c in diagram.curves:
        ok = np.isfinite(c.lyapunov)
        if ok.any():
            err = np.where(np.isfinite(c.lyapunov_error), c.lyapunov_error, 0.0)[ok]
            axes.errorbar(c.speed[ok] / RPM, c.lyapunov[ok], yerr=err, ls="none", ms=3,
                          capsize=2, lw=0.8, color=_STYLE[c.direction]["color"],
                          marker=_STYLE[c.direction]["marker"], label=f"sweep {c.direction}")
    axes.axhline(0.0, color="0.3", lw=0.8)
    axes.set_ylabel("largest Lyapunov\nexponent (1/s)", fontsize=9)
    axes.set_xlabel("pinion speed (rpm)")
    axes.grid(alpha=0.3)


def plot_branch_samples(samples: BranchSamples, ax: Any = None, state: str = "x",
                        diagram: BifurcationDiagram | None = None, label_points: bool = True,
                        title: str | None = None) -> Any:
    """The continuation's bifurcation diagram: each orbit's stroboscopic samples against the
    parameter, with a brute-force diagram behind it.

    A period-n branch draws n curves (its orbits' states at t = k T_m, k < n): stable stretches
    solid, unstable ones dashed and light; folds (circles) and period doublings (squares) are
    marked on every sample of the located orbit and, with ``label_points``, labelled with their
    parameter value, as on the response curve
    (:func:`~gear_dyn.plots.continuation.plot_branch`).

    Parameters
    ----------
    samples : BranchSamples
        From :func:`gear_dyn.analysis.continuation.branch_samples`.
    ax : Axes or None
        Where to draw (None: a new figure of 10 x 4.5 in).
    state : str
        State component drawn: ``x`` (mesh deflection, um) or ``v`` (its rate, m/s).
    diagram : BifurcationDiagram or None
        A brute-force diagram over speed
        (:func:`~gear_dyn.analysis.motion.diagram.bifurcation_diagram`) drawn behind the
        branches in small grey dots (up and down
        alike): attractors the branches do not carry (chaos, period-n windows) show there.
    label_points : bool
        Write each fold's and period doubling's parameter value beside its highest sample,
        where it covers no other label (``gear_dyn.plots._labels.place_labels()``).
    title : str or None
        Axes title (None: none).

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    InputError
        ``state`` not ``x`` or ``v``; a ``diagram`` with a branch in another parameter than
        speed.
    """
    # the response curve's styles; imported here: the brute-force diagram alone loads no
    # continuation modules
    from gear_dyn.plots.continuation import _COLOURS, _fmt, _stretches, _x_of

    if state not in _UNITS:
        raise InputError(f"state = {state!r}: valid choices are {', '.join(_UNITS)}")
    if diagram is not None and samples.parameter_name != "speed":
        raise InputError(f"diagram: a brute-force diagram is over speed; this branch is in "
                         f"{samples.parameter_name}")
    i = ("x", "v").index(state)
    factor, unit = _UNITS[state]
    fig, axes = axes_of(ax, figsize=(10, 4.5), name="plot_branch_samples")
    first = samples.curves[0].branch if samples.curves else None
    fx, xlabel = _x_of(first) if first is not None else (1.0, samples.parameter_name)
    once = legend_once()

    if diagram is not None and diagram.curves:  # both directions as one artist
        n_s = diagram.curves[0].samples.shape[1]
        dx = np.concatenate([np.repeat(c.speed, n_s) for c in diagram.curves])
        dy = np.concatenate([c.samples[:, :, i].ravel() for c in diagram.curves])
        axes.plot(dx * fx, dy * factor, ls="none", marker=".", ms=2.5, color="0.6", zorder=1,
                  label=f"brute force, {'/'.join(c.direction for c in diagram.curves)} "
                  f"({n_s} samples per speed)")
    labels: list[tuple[float, FloatArray, str]] = []
    for curve in samples.curves:
        b = curve.branch
        if not b.points:
            continue
        colour = _COLOURS[min(b.periods.bit_length() - 1, len(_COLOURS) - 1)]
        items, pieces = _stretches(b)  # the located folds and doublings end the stretches
        px = np.array([curve.parameter[j] if kind == "point" else curve.marks[j][1]
                       for kind, j in items]) * fx
        ys = np.array([curve.samples[j] if kind == "point" else curve.marks[j][2]
                       for kind, j in items])
        for st, sl in pieces:
            name = once(f"period-{b.periods} {'stable' if st else 'unstable'}")
            for k in range(ys.shape[1]):
                axes.plot(px[sl], ys[sl, k, i] * factor, color=colour,
                          ls="-" if st else "--", lw=1.4 if st else 0.9,
                          alpha=1.0 if st else 0.55, zorder=3 if st else 2,
                          label=name if k == 0 else None)
        for kind, par, at in curve.marks:
            marker, text = ("o", "fold") if kind == "fold" else ("s", "PD")
            axes.plot(np.full(len(at), par * fx), at[:, i] * factor, marker, color="k",
                      mfc="none", ms=7, ls="none", zorder=4,
                      label=once("fold" if kind == "fold" else "period doubling"))
            labels.append((par * fx, at[:, i] * factor, f"{text} {_fmt(par, b)}"))
    if title is not None:
        axes.set_title(title, fontsize=10)
    axes.margins(y=0.08)  # room for the labels below the lowest and above the highest mark
    axes.set_xlabel(xlabel)
    axes.set_ylabel(f"{state} at t = k T_m ({unit})")
    axes.grid(alpha=0.3)
    # beside the located orbit's highest sample
    marks = [(bx, float(ys.max()), text) for bx, ys, text in labels] if label_points else []
    others = [(bx, float(v)) for bx, ys, _ in labels for v in ys] if label_points else []
    label_marks(axes, marks, own_figure=ax is None, layout=tidy, avoid=others)
    return fig


def plot_motion(motion: Motion, ax: Any = None) -> Any:
    """The stroboscopic samples of one motion in the state plane (a Poincaré section at mesh
    phase 0): the first state component (µm) against the second (m/s), the motion's label as
    the title. A period-n orbit shows n points, a quasi-periodic motion a closed curve, a
    chaotic one a scattered set.

    Parameters
    ----------
    motion : Motion
        From :func:`gear_dyn.analysis.motion.classify_motion` (at least two state components).
    ax : Axes or None
        Where to draw (None: a new figure of 5 x 4.5 in).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, axes = axes_of(ax, figsize=(5, 4.5), name="plot_motion")
    x, v = motion.samples[:, 0], motion.samples[:, 1]
    axes.plot(x * _UNITS["x"][0], v * _UNITS["v"][0], ".", color="tab:blue", ms=5)
    axes.set_xlabel(f"x at t = k T_m ({_UNITS['x'][1]})")
    axes.set_ylabel(f"v at t = k T_m ({_UNITS['v'][1]})")
    axes.set_title(motion.label, fontsize=10)
    axes.grid(alpha=0.3)
    return fig
