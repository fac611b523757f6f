"""The second method the continuation tests locate folds and period doublings with: the
minimally extended system of a period-1 orbit solved by MINPACK (no tangent, no arclength, no
bracketing)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from scipy.optimize import OptimizeResult, root


def solve_extended(fam: Callable[[float], Any], test: Callable[[np.ndarray], float],
                   flow: Callable[[Any, np.ndarray, float], tuple[np.ndarray, np.ndarray]],
                   scale: np.ndarray, w: float, u0: np.ndarray, xtol: float) -> OptimizeResult:
    """``P(y, w) - y = 0, test(M) = 0`` by MINPACK's hybrid method (finite-difference
    Jacobian) from ``u0``, the unknowns scaled: ``u = (y / scale, w' / w)``. ``fam(w)`` is the
    model at parameter ``w``; ``flow(model, y, T)`` gives the state after one mesh period
    ``T`` and the monodromy matrix ``M``."""
    def eqs(u: np.ndarray) -> np.ndarray:
        yy, ww = u[:2] * scale, u[2] * w
        model = fam(ww)
        yt, mono = flow(model, yy, 1.0 / model.mesh_frequency)
        return np.append((yt - yy) / scale, test(mono))

    return root(eqs, u0, method="hybr", options={"xtol": xtol})
