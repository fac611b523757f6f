"""The bifurcation diagram: stroboscopic samples against speed (a pyplot-free Figure)."""

from __future__ import annotations

from typing import Any

import numpy as np

from gear_dyn.analysis.motion.diagram import RPM, BifurcationDiagram
from gear_dyn.errors import InputError
from gear_dyn.plots._axes import axes_of, tidy

_STYLE = {"up": dict(color="tab:blue", marker="."), "down": dict(color="tab:orange", marker="x")}
#: display unit of each state component: (scale from SI, unit text)
_UNITS = {"x": (1e6, "µm"), "v": (1.0, "m/s")}


def plot_bifurcation(diagram: BifurcationDiagram, ax: Any = None, state: str = "x",
                     title: str | None = None) -> Any:
    """Stroboscopic samples of one state component against pinion speed, up and down.

    Parameters
    ----------
    diagram : BifurcationDiagram
    ax : Axes or None
        Where to draw (None: a new Figure of 8 x 4.5 in).
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
    axes.set_xlabel("pinion speed (rpm)")
    axes.set_ylabel(f"{state} at t = k T_m ({unit})")
    if title is None:
        name = f"{diagram.scene_name}: " if diagram.scene_name else ""
        title = (f"{name}bifurcation diagram ({diagram.options.samples} samples per speed "
                 f"after {diagram.options.settle} mesh periods)")
    axes.set_title(title, fontsize=10, pad=20 if np.isfinite(diagram.natural_frequency) else 6)
    fn = diagram.natural_frequency
    z1 = _teeth(diagram)
    if np.isfinite(fn) and z1:
        per = fn * 60.0 / z1  # rpm per unit f_m / f_n
        top = axes.secondary_xaxis("top", functions=(lambda r: r / per, lambda q: q * per))
        top.set_xlabel("f_m / f_n")
    axes.legend(loc="best", fontsize=8, markerscale=2)
    axes.grid(alpha=0.3)
    tidy(fig)
    return fig


def _teeth(diagram: BifurcationDiagram) -> float:
    """Pinion teeth from the curves (f_m = z1 w / 2 pi), 0 where not known."""
    c = diagram.curves[0]
    if c.speed.size == 0 or c.speed[0] <= 0:
        return 0.0
    return float(c.mesh_frequency[0] * 2 * np.pi / c.speed[0])
