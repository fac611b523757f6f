"""Long lines decimated to their per-pixel envelope, for figures written to files.

A run's time history holds 12 801 samples per line for the helicopter tail scene, 40 321 for the
eccentric pair and more with ``--periods``: many per pixel column of its panel. :func:`envelope`
keeps the first, smallest, largest and last sample of each block of about half a pixel column
(the "M4" reduction): the rasterised line covers the same pixels from far fewer points
(tests/plots/test_decimate.py compares the pixels). What it saves, per scene and run length:
benchmarks/results/cli.md (``python benchmarks/cli_phases.py --choices``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np


def envelope(x: Any, y: Any, blocks: int) -> tuple[Any, Any]:
    """``(x, y)`` reduced to first, min, max and last sample of ``blocks`` equal blocks.

    Drawn as a line at most ``blocks / 2`` pixels wide, the result covers the pixels the whole
    series covers (every block's vertical extent and its joins to the neighbours are kept, at
    their own x). Series shorter than ``8 * blocks`` are returned whole.

    Parameters
    ----------
    x, y : array_like
        The line's samples, in time order (any units).
    blocks : int
        Number of equal blocks (about two per pixel column of the drawn line).

    Returns
    -------
    (ndarray, ndarray)
        The kept samples of ``x`` and ``y``, in their order.
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


def period_envelope(t: Any, y: Any, period: float,
                    blocks: int | None = None) -> tuple[Any, Any, Any]:
    """Smallest and largest value of ``y`` in each period ``period`` from ``t[0]`` on.

    A run of thousands of mesh periods drawn as a line fills its panel from edge to edge; drawn
    as the band between these bounds it shows how the vibration grows, settles or beats.

    Parameters
    ----------
    t : array_like
        Sample times in s, increasing.
    y : array_like
        The series (any unit).
    period : float
        Bin width in s (a mesh period), > 0.
    blocks : int or None
        At most this many bins: a bin then spans a whole number of periods (None: no limit).

    Returns
    -------
    (ndarray, ndarray, ndarray)
        The bins' edges in s (one more than bins: ``t[0]``, ..., ``t[-1]``; the last bin takes
        the remainder of the run), each bin's smallest and its largest value of ``y``. Every
        sample lies within its bin's bounds (drawn as steps, ``Axes.stairs``: within the band
        at its time).

    Raises
    ------
    ValueError
        ``period`` is not positive and finite.
    """
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    if not (np.isfinite(period) and period > 0):
        raise ValueError(f"period_envelope: period = {period!r} s: must be positive and finite")
    width = period
    if blocks:
        width = period * max(1, math.ceil((t[-1] - t[0]) / period / blocks))
    # the last bin takes the remainder (a bin of a few samples would pinch the band)
    n = max(1, math.floor((t[-1] - t[0]) / width + 1e-9))
    k = np.minimum(np.floor((t - t[0]) / width + 1e-9).astype(np.int64), n - 1)
    starts = np.flatnonzero(np.r_[True, k[1:] != k[:-1]])
    lo = np.minimum.reduceat(y, starts)
    hi = np.maximum.reduceat(y, starts)
    edges = np.append(t[0] + k[starts] * width, t[-1])
    return edges, lo, hi


def draw_band(ax: Any, t: Any, y: Any, period: float, blocks: int | None = None,
              color: Any = "tab:blue", label: str | None = None,
              t_scale: float = 1.0) -> tuple[Any, Any, Any]:
    """Draw ``y`` as the band between its smallest and largest value in each ``period``
    (:func:`period_envelope`), filled and edged, as steps: every sample lies inside the band at
    its time. ``t_scale``: factor from s to the axis' time unit (1e3: ms). Returns the
    envelope ``(edges in s, lo, hi)``."""
    edges, lo, hi = period_envelope(t, y, period, blocks)
    x = edges * t_scale
    ax.stairs(hi, x, baseline=lo, fill=True, color=color, alpha=0.35, lw=0, label=label)
    ax.stairs(hi, x, baseline=None, color=color, lw=0.8)
    ax.stairs(lo, x, baseline=None, color=color, lw=0.8)
    return edges, lo, hi


__all__ = ["draw_band", "envelope", "period_envelope"]
