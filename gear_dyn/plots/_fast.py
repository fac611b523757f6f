"""Cheaper drawing for figures written to files (``gear-dyn run``): same picture, less work.

A fresh ``gear-dyn run`` process spends most of its time in matplotlib; three things cost most
and change nothing visible:

- :func:`fixed_layout`: margins given in inches instead of ``tight_layout`` (which measures
  every tick label once more before the real draw);
- :func:`envelope`: a long line reduced to the first, smallest, largest and last sample of each
  block of ~half a pixel column (the "M4" reduction: the rasterised line covers the same pixels),
  here 12 800 samples -> ~2 900 per panel;
- :class:`UnicodeLogFormatter`: log-axis labels ``10⁻⁸`` in plain text with Unicode superscripts,
  not mathtext (whose parser costs ~75 ms to build in a new process).
"""

from __future__ import annotations

import re
from typing import Any

import numpy as np
from matplotlib.ticker import LogFormatterSciNotation


def fixed_layout(fig: Any, left: float, right: float, top: float, bottom: float,
                 wgap: float = 0.0, hgap: float = 0.0) -> None:
    """Place the figure's subplot grid with margins and gaps in inches.

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


def envelope(x: Any, y: Any, blocks: int) -> tuple[Any, Any]:
    """``(x, y)`` reduced to first, min, max and last sample of ``blocks`` equal blocks.

    Drawn as a line at most ``blocks / 2`` pixels wide, the result covers the pixels the whole
    series covers (every block's vertical extent and its joins to the neighbours are kept, at
    their own x). Series shorter than ``8 * blocks`` are returned whole.
    """
    x = np.asarray(x)
    y = np.asarray(y)
    n = y.size
    k = n // blocks if blocks > 0 else 0
    if k < 8:
        return x, y
    m = n // k * k
    yb = y[:m].reshape(-1, k)
    start = np.arange(0, m, k)
    idx = np.unique(np.concatenate([start, start + np.argmin(yb, axis=1),
                                    start + np.argmax(yb, axis=1), start + k - 1,
                                    np.arange(m, n)]))
    return x[idx], y[idx]


_SUP = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")
_MATH = re.compile(r"\$\\mathdefault\{(?:([0-9.]+)\\times\s*)?(10)\^\{([-−]?[0-9]+)\}\}\$")


class UnicodeLogFormatter(LogFormatterSciNotation):
    """matplotlib's log-axis labels (``10^{-8}``, ``2x10^{-8}``) as plain text with Unicode
    superscripts; anything else it would write is left as it is."""

    def __call__(self, x: float, pos: int | None = None) -> str:
        s = super().__call__(x, pos)
        m = _MATH.fullmatch(s)
        if m is None:
            return s
        mant, base, exp = m.groups()
        text = base + exp.replace("−", "-").translate(_SUP)
        return f"{mant}×{text}" if mant else text


__all__ = ["UnicodeLogFormatter", "envelope", "fixed_layout"]
