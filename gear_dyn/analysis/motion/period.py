"""Period-n detection: the smallest n for which the stroboscopic samples repeat.

The samples only suggest a period (they repeat to the settling's remainder); shooting over n mesh
periods from a sample confirms it: Newton converges to the orbit and its Floquet multipliers
say whether it is stable (:func:`gear_dyn.analysis.stability.shoot`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import check_range

FloatArray = NDArray[np.float64]

#: longest orbit looked for, in mesh periods
MAX_PERIOD = 16


def repeat_errors(samples: FloatArray, scale: FloatArray, max_period: int = MAX_PERIOD
                  ) -> FloatArray:
    """How far the samples are from repeating after n mesh periods, n = 1..max_period.

    Parameters
    ----------
    samples : ndarray (n_samples, n_states)
        Stroboscopic samples, SI units (:func:`gear_dyn.analysis.motion.samples.stroboscopic`).
    scale : ndarray (n_states,)
        State scale (``model.state_scale``): errors are relative to it.
    max_period : int
        Largest n (1..16); needs at least ``2 max_period`` samples.

    Returns
    -------
    ndarray (max_period,)
        ``e[n-1] = max_k max_i |y_{k+n,i} - y_{k,i}| / scale_i`` over the samples.

    Raises
    ------
    InputError
        ``max_period`` out of range or too few samples.
    """
    check_range("max_period", max_period, "", low=1, high=MAX_PERIOD)
    z = np.asarray(samples, dtype=float) / np.asarray(scale, dtype=float)
    check_range("samples", z.shape[0], "", low=2 * max_period)
    return np.array([float(np.max(np.abs(z[n:] - z[:-n]))) for n in range(1, max_period + 1)])


def detect_period(samples: FloatArray, scale: FloatArray, tol: float = 1e-4,
                  max_period: int = MAX_PERIOD) -> int:
    """The smallest n (1..max_period) after which the samples repeat to ``tol``, else 0.

    Parameters
    ----------
    samples, scale, max_period
        As :func:`repeat_errors`.
    tol : float
        Largest relative repeat error of a period (0 < tol < 1). It has to cover the settling
        remainder only: the orbit itself is confirmed by shooting.

    Returns
    -------
    int
        Period in mesh periods; 0 where none repeats.
    """
    check_range("tol", tol, "", low=0.0, high=1.0, low_open=True, high_open=True)
    err = repeat_errors(samples, scale, max_period)
    hit = np.flatnonzero(err <= tol)
    return int(hit[0]) + 1 if hit.size else 0
