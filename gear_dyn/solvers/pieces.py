"""The pieces of a time grid between switching instants (shared by solvers and analysis)."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


def pieces(
    t_grid: FloatArray, cuts: FloatArray
) -> Iterator[tuple[float, float, int, int, FloatArray]]:
    """The pieces ``[ta, tb]`` between consecutive ``cuts`` with the output points they own.

    Yields ``(ta, tb, i0, i1, t_eval)``: grid points ``t_grid[i0:i1]`` lie in ``(ta, tb]`` (the
    first piece also owns ``ta``), and ``t_eval`` is those points with ``tb`` appended when it is
    not a grid point, so the end state of every piece is always returned.
    """
    idx = np.searchsorted(t_grid, cuts, side="right")  # grid points up to each cut
    for k in range(cuts.size - 1):
        ta, tb = float(cuts[k]), float(cuts[k + 1])
        if tb <= ta:
            continue
        i0, i1 = int(idx[k]), int(idx[k + 1])
        te = t_grid[i0:i1]
        t_eval = np.concatenate([te, [tb]]) if te.size == 0 or te[-1] < tb else te
        yield ta, tb, i0, i1, t_eval
