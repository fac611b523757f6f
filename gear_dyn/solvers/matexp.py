"""Matrix exponential and diagonal balancing of small matrices in plain numpy.

The run path of ``gear-dyn run`` needs ``expm`` of 2x2..9x9 matrices and a diagonal balancing;
``scipy.linalg`` costs ~0.13 s to import (its array-API layer loads numpy.f2py, numpy.testing,
numpy.ma...), more than the whole solve. It stays for that hot path: ``gear-dyn run
helicopter_tail`` (the demo; exact route) imports no scipy.linalg and takes 1.35 s in all
(benchmarks/results/cli.md), so ``scipy.linalg.expm`` and ``matrix_balance``, which do the same
job, would add about 10 % to the command (import measured 0.12..0.26 s with numpy, scipy and
gear_dyn loaded; issue 22). These are the textbook algorithms:

- :func:`balance`: diagonal similarity ``D^-1 A D`` with ``D`` powers of 2 (exact in floating
  point) making row and column norms alike (Parlett & Reinsch 1969, as LAPACK ``gebal`` without
  permutation);
- :func:`expm`: scaling and squaring with the [13/13] Pade approximant (Higham 2005, SIAM J.
  Matrix Anal. Appl. 26(4):1179, Algorithm 2.3, degree 13 only), applied to the balanced matrix,
  batched over a stack. Its backward error is below the unit roundoff; tests compare it with
  ``scipy.linalg.expm`` (tests/solvers/test_matexp.py).
"""

from __future__ import annotations

from typing import cast

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: Pade [13/13] coefficients b_0..b_13 (Higham 2005, eq. 2.7 ff.)
_B13 = (64764752532480000.0, 32382376266240000.0, 7771770303897600.0, 1187353796428800.0,
        129060195264000.0, 10559470521600.0, 670442572800.0, 33522128640.0, 1323241920.0,
        40840800.0, 960960.0, 16380.0, 182.0, 1.0)
#: largest 1-norm for which [13/13] needs no scaling (Higham 2005, Table 2.3)
_THETA13 = 5.371920351148152


def balance(a: FloatArray) -> tuple[FloatArray, FloatArray]:
    """``(D^-1 a D, d)`` with ``D = diag(d)``, ``d`` powers of 2 balancing rows against columns.

    Parameters
    ----------
    a : ndarray, shape (n, n)

    Returns
    -------
    b : ndarray, shape (n, n)
        The balanced matrix (similar to ``a``; entries exact multiples of ``a``'s).
    d : ndarray, shape (n,)
        Scaling, powers of 2.
    """
    b = np.array(a, dtype=float)
    n = b.shape[0]
    d = np.ones(n)
    for _ in range(100):
        changed = False
        for i in range(n):
            c = float(np.abs(b[:, i]).sum() - abs(b[i, i]))
            r = float(np.abs(b[i, :]).sum() - abs(b[i, i]))
            if c == 0.0 or r == 0.0:
                continue
            f = 2.0 ** round(0.5 * np.log2(r / c))
            if f != 1.0 and c * f + r / f < 0.95 * (c + r):
                b[:, i] *= f
                b[i, :] /= f
                d[i] *= f
                changed = True
        if not changed:
            break
    return b, d


def expm(a: FloatArray) -> FloatArray:
    """``exp(a)`` of a matrix or a stack of matrices (shape (..., n, n)).

    Each matrix is balanced, scaled by ``2^-s`` to 1-norm <= 5.37, its [13/13] Pade approximant
    taken and squared ``s`` times, and the balancing undone.
    """
    a = np.asarray(a, dtype=float)
    if a.ndim == 2:
        return expm(a[None])[0]
    shape = a.shape
    stack = a.reshape(-1, shape[-2], shape[-1])
    out = np.empty_like(stack)
    for k, m in enumerate(stack):
        if not np.all(np.isfinite(m)):
            out[k] = np.nan
            continue
        b, d = balance(m)
        out[k] = _expm_pade13(b) * (d[:, None] / d[None, :])
    return out.reshape(shape)


def _expm_pade13(a: FloatArray) -> FloatArray:
    n = a.shape[0]
    norm = float(np.abs(a).sum(axis=0).max()) if n else 0.0
    s = max(0, int(np.ceil(np.log2(norm / _THETA13)))) if norm > _THETA13 else 0
    a = a / 2.0 ** s
    b = _B13
    ident = np.eye(n)
    a2 = a @ a
    a4 = a2 @ a2
    a6 = a4 @ a2
    u = a @ (a6 @ (b[13] * a6 + b[11] * a4 + b[9] * a2) + b[7] * a6 + b[5] * a4 + b[3] * a2
             + b[1] * ident)
    v = a6 @ (b[12] * a6 + b[10] * a4 + b[8] * a2) + b[6] * a6 + b[4] * a4 + b[2] * a2 \
        + b[0] * ident
    r = cast(FloatArray, np.linalg.solve(v - u, v + u))
    for _ in range(s):
        r = r @ r
    return r


__all__ = ["balance", "expm"]
