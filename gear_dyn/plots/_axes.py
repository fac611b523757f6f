"""Axes for the plot functions: new pyplot-free figures, or the caller's axes.

Figures are plain :class:`matplotlib.figure.Figure` objects (no pyplot, so no global figure
registry and no backend choice); :func:`gear_dyn.io.save_figure` renders them off-screen.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.layout_engine import PlaceHolderLayoutEngine, TightLayoutEngine


def axes_of(ax: Any, nrows: int = 1, ncols: int = 1, figsize: tuple[float, float] = (8, 4),
            name: str = "plot", **kw: Any) -> tuple[Figure, Any]:
    """(figure, axes) to draw into, shaped as ``Figure.subplots(nrows, ncols, **kw)`` returns.

    Parameters
    ----------
    ax : None, Axes or sequence of Axes
        None: a new :class:`~matplotlib.figure.Figure` of ``figsize`` with
        ``fig.subplots(nrows, ncols, **kw)``. Otherwise the caller's axes: one Axes for a
        single panel, else ``nrows * ncols`` Axes (flat in row-major order, or an array of that
        size) of one figure; ``kw`` (``sharex``, ``gridspec_kw``...) is then ignored except
        ``squeeze``.
    nrows, ncols : int
        Panel grid.
    figsize : (float, float)
        Size in inches of a new figure.
    name : str
        The plot function, named in errors.

    Raises
    ------
    ValueError
        ``ax`` is not one Axes / ``nrows * ncols`` Axes of one figure.
    """
    if ax is None:
        fig = Figure(figsize=figsize)
        return fig, fig.subplots(nrows, ncols, **kw)
    n = nrows * ncols
    if isinstance(ax, Axes):
        flat: list[Any] = [ax]
    elif isinstance(ax, Sequence | np.ndarray):
        flat = list(np.asarray(ax, dtype=object).ravel())
    else:
        raise ValueError(f"{name}: ax must be a matplotlib Axes or a sequence of {n} Axes, "
                         f"got {type(ax).__name__}")
    if len(flat) != n or not all(isinstance(a, Axes) for a in flat):
        raise ValueError(f"{name}: expected {n} matplotlib Axes, got {len(flat)} "
                         f"item{'s' if len(flat) != 1 else ''}")
    fig = flat[0].figure
    if any(a.figure is not fig for a in flat):
        raise ValueError(f"{name}: the {n} Axes must belong to one figure")
    grid = np.array(flat, dtype=object).reshape(nrows, ncols)
    if not kw.get("squeeze", True):
        return fig, grid
    return fig, grid.item() if n == 1 else grid.squeeze()  # as Figure.subplots squeezes


def fixed_layout(fig: Any, left: float, right: float, top: float, bottom: float,
                 wgap: float = 0.0, hgap: float = 0.0) -> None:
    """Place the figure's subplot grid with margins and gaps in inches.

    The look of ``tight_layout`` for a figure whose labels are known in advance, without
    drawing every text once more to measure it (measured: benchmarks/results/cli.md).

    Parameters
    ----------
    fig : Figure
        Its subplots form one regular grid (``fig.subplots``).
    left, right, top, bottom : float
        Margins in inches (room for tick labels, axis labels, titles).
    wgap, hgap : float
        Space between columns / rows in inches.
    """
    w, h = fig.get_size_inches()
    gs = fig.axes[0].get_subplotspec().get_gridspec()
    nrows, ncols = gs.get_geometry()
    aw = (w - left - right - (ncols - 1) * wgap) / ncols
    ah = (h - top - bottom - (nrows - 1) * hgap) / nrows
    fig.subplots_adjust(left=left / w, right=1 - right / w, top=1 - top / h, bottom=bottom / h,
                        wspace=wgap / aw, hspace=hgap / ah)


def tidy(fig: Any) -> None:
    """``fig.tight_layout()``, unless the caller's figure has a layout engine of its own
    (constrained layout...), which tight_layout would replace with a warning."""
    engine = fig.get_layout_engine()
    if engine is None or isinstance(engine, PlaceHolderLayoutEngine | TightLayoutEngine):
        fig.tight_layout()
        if not isinstance(engine, TightLayoutEngine):
            # tight_layout leaves a placeholder engine behind, and with any engine savefig
            # lays the figure out once more (a whole draw pass): none, as before the call
            fig.set_layout_engine(None)


__all__ = ["axes_of", "fixed_layout", "tidy"]
