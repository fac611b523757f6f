"""Long lines decimated to their per-pixel envelope, for figures written to files.

A run's time history holds 12 801 samples per line for the helicopter tail scene, 40 321 for the
eccentric pair and more with ``--periods``: many per pixel column of its panel. :func:`envelope`
keeps the first, smallest, largest and last sample of each block of about half a pixel column
(the "M4" reduction): the rasterised line covers the same pixels from far fewer points
(tests/plots/test_decimate.py compares the pixels). What it saves, per scene and run length:
benchmarks/results/cli.md (``python benchmarks/cli_phases.py --choices``).
"""

from __future__ import annotations

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


__all__ = ["envelope"]
