"""ctypes face of the kernel's contact walk (``gd_flow.c``, "the contact walk").

:mod:`gear_dyn.solvers.contact_exact` defines the single-DOF backlash model and exports its
tables: ``model`` (``GD_CW_MODEL + 2 nh`` floats: m, c, w, b, f_m, p0, nh, then ``2 pi n`` and
``2 pi n f_m`` of the nh forcing harmonics) and ``pieces`` (one row of ``GD_CW_ROW + 2 nh``
floats per contact state and stiffness value: state, k, a, w2, q, x_eq, h, amplitude and
curvature bounds of the particular solution, its cosine and sine coefficients; row
``3 j + state + 1``). The kernel walks: closed form in each piece, contact changes located by
the bracketed root finder, the sensitivity with the saltation of each change. These functions
check shapes and turn status codes into errors; they hold no algorithm.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from gear_dyn.solvers.kernel import _LONG, ROOT_FUNCTION, _c, _ptr, library

FloatArray = NDArray[np.float64]

#: fixed lengths of the model header and of a piece row (``GD_CW_MODEL``, ``GD_CW_ROW``)
MODEL_FIELDS, ROW_FIELDS = 7, 9
#: status codes of ``gd_contact_walk``
OK, FULL, CHATTER, GRAZE = 0, 1, 2, 3


@dataclass(frozen=True, eq=False)
class Segments:
    """The closed-form segments of one walk, in time order.

    Attributes
    ----------
    table : ndarray (n, 4)
        Start time (s), ``u``, ``u'`` at the start (m, m/s), duration (s).
    ids : ndarray (n, 2)
        Piece row, and 1 where the segment ends at a contact change.
    end : ndarray (2,)
        ``u, u'`` at the end (m, m/s).
    phi : ndarray (2, 2)
        ``d y(end) / d y(start)`` (entries dimensionless, s and 1/s).
    status : int
        ``OK``, ``CHATTER`` (too many changes in one stiffness piece) or ``GRAZE`` (a
        discontinuous field crossed tangentially); ``fail_time`` says where.
    fail_time : float
        Time of the failure (s; 0 when none).
    phis : ndarray (n_slots, 2, 2) or None
        The sensitivity over each slot's stiffness pieces (with ``slots``).
    dpar : ndarray (2,) or None
        ``d (u, u')(end) / d p`` of a parameter p (with ``rates``; m and m/s per unit of p).
    """

    table: FloatArray
    ids: NDArray[np.int64]
    end: FloatArray
    phi: FloatArray
    status: int
    fail_time: float
    phis: FloatArray | None
    dpar: FloatArray | None = None


def _tables(model: FloatArray, pieces: FloatArray) -> tuple[FloatArray, FloatArray, int]:
    model, pieces = _c(model), _c(pieces)
    nh = int(model[6]) if model.size >= MODEL_FIELDS else -1
    if nh < 0 or model.shape != (MODEL_FIELDS + 2 * nh,) or pieces.ndim != 2 \
            or pieces.shape[1] != ROW_FIELDS + 2 * nh:
        raise ValueError(f"contact walk tables of shapes {model.shape} and {pieces.shape}: need "
                         f"({MODEL_FIELDS} + 2 nh,) and (rows, {ROW_FIELDS} + 2 nh)")
    return model, pieces, pieces.shape[0]


def flow(state: int, k: float, m: float, c: float, w: float, b: float, x0: float, v0: float,
         s: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The kernel's closed form ``x(s), v(s)`` of one contact state (see
    :func:`gear_dyn.solvers.contact_exact.flow`)."""
    s = _c(np.atleast_1d(s))
    x, v = np.empty(s.shape), np.empty(s.shape)
    library().gd_contact_flow(int(state), k, m, c, w, b, x0, v0, s.size, _ptr(s), _ptr(x),
                              _ptr(v))
    return x, v


def find_root(f: Callable[[float], float], lo: float, hi: float, f_lo: float, f_hi: float,
              xtol: float) -> float:
    """The kernel's root finder on a Python function (see
    :func:`gear_dyn.solvers.contact_exact.find_root`)."""
    cb = ROOT_FUNCTION(lambda t, _ctx: float(f(t)))
    return float(library().gd_find_root(cb, None, lo, hi, f_lo, f_hi, xtol))


def stays_inside(model: FloatArray, pieces: FloatArray, row: int, u0: float, v0: float,
                 t0: float) -> bool:
    """True when piece ``row``'s motion from ``(u0, v0)`` at ``t0`` provably stays in its
    contact state (the amplitude bound of the walk)."""
    model, pieces, n = _tables(model, pieces)
    if not 0 <= row < n:
        raise ValueError(f"piece row {row} outside 0..{n - 1}")
    return bool(library().gd_contact_stays_inside(_ptr(model), _ptr(pieces), row, u0, v0, t0))


def first_crossing(model: FloatArray, pieces: FloatArray, row: int, t0: float, u0: float,
                   v0: float, length: float, xtol: float) -> float | None:
    """Time after ``t0`` (s) of piece ``row``'s first contact change within ``length``, or
    None (the walk's search, on one piece)."""
    model, pieces, n = _tables(model, pieces)
    if not 0 <= row < n:
        raise ValueError(f"piece row {row} outside 0..{n - 1}")
    hit = np.zeros(1)
    found = library().gd_contact_first_crossing(_ptr(model), _ptr(pieces), row, t0, u0, v0,
                                                length, xtol, _ptr(hit))
    return float(hit[0]) if found else None


def walk(model: FloatArray, pieces: FloatArray, cuts: FloatArray, kidx: NDArray[np.intp],
         u0: float, v0: float, xtol: float, max_events: int,
         slots: NDArray[np.intp] | None = None,
         param: tuple[FloatArray, FloatArray | None, FloatArray, float] | None = None
         ) -> Segments:
    """Walk from ``(u0, v0)`` at ``cuts[0]`` to ``cuts[-1]``; stiffness piece i spans
    ``cuts[i]..cuts[i+1]`` with stiffness value ``kidx[i]`` (rows ``3 kidx + state + 1``).
    ``slots[i]`` (non-decreasing from 0; None: none) names the slot of piece i: the walk also
    returns the sensitivity over each slot. ``param`` (None: none): ``(rates, dpieces, ds0,
    dfm)``, the cuts' ``d t / d p``, each row's ``d (ca, cb) / d p`` (None without harmonics),
    ``d (u0, u0') / d p`` and ``d f_m / d p``: the walk also returns ``d (u, u')(end) / d p``
    (``Segments.dpar``; ``gd_flow.h``)."""
    model, pieces, n = _tables(model, pieces)
    cuts = _c(cuts)
    kid = np.ascontiguousarray(kidx, dtype=_LONG)
    listed = kid.tolist() if kid.ndim == 1 else []
    if cuts.ndim != 1 or kid.shape != (cuts.size - 1,) \
            or (listed and (min(listed) < 0 or 3 * max(listed) + 2 >= n)):
        raise ValueError(f"contact walk: {cuts.size} cuts, {kid.size} stiffness indices, "
                         f"{n} piece rows")
    slot, phis = None, None
    if slots is not None:
        slot = np.ascontiguousarray(slots, dtype=_LONG)
        if slot.shape != kid.shape or (slot.size and (slot[0] < 0 or np.any(np.diff(slot) < 0))):
            raise ValueError(f"contact walk: slots {slot.shape} not non-decreasing from 0 for "
                             f"{kid.size} pieces")
    rates = dpieces = None
    if param is not None:
        rates = _c(param[0])
        if rates.shape != cuts.shape:
            raise ValueError(f"contact walk: {rates.size} cut rates for {cuts.size} cuts")
        if param[1] is not None:
            dpieces = _c(param[1])
            if dpieces.shape != (n, pieces.shape[1] - ROW_FIELDS):
                raise ValueError(f"contact walk: piece derivatives {dpieces.shape} for {n} rows "
                                 f"of {pieces.shape[1] - ROW_FIELDS} coefficients")
        elif pieces.shape[1] != ROW_FIELDS:
            raise ValueError("contact walk: a forced walk needs the piece derivatives")
    cap = 4 * kid.size + 64
    out = np.zeros(7)
    dpar = None
    count = np.zeros(1, dtype=_LONG)
    lib = library()
    while True:
        if slot is not None:
            phis = np.tile(np.eye(2), (int(slot[-1]) + 1 if slot.size else 0, 1, 1))
        table = np.empty((cap, 4))
        ids = np.empty((cap, 2), dtype=_LONG)
        if param is not None:
            dpar = np.array([float(param[2][0]), float(param[2][1]), float(param[3])])
        status = lib.gd_contact_walk(_ptr(model), _ptr(pieces), kid.size, _ptr(cuts), _ptr(kid),
                                     u0, v0, xtol, max_events, cap, _ptr(table), _ptr(ids),
                                     _ptr(count), _ptr(out),
                                     None if slot is None else _ptr(slot),
                                     None if phis is None else _ptr(phis),
                                     None if rates is None else _ptr(rates),
                                     None if dpieces is None else _ptr(dpieces),
                                     None if dpar is None else _ptr(dpar))
        if status != FULL:
            break
        cap = int(count[0])  # the number the walk needed: once more with room for all
    ns = min(int(count[0]), cap)
    return Segments(table[:ns], ids[:ns].astype(np.int64, copy=False), out[:2].copy(),
                    out[2:6].reshape(2, 2).copy(), int(status), float(out[6]), phis,
                    None if dpar is None else dpar[:2].copy())


def on_grid(model: FloatArray, pieces: FloatArray, table: FloatArray, ids: NDArray[np.int64],
            t: FloatArray) -> tuple[FloatArray, bool]:
    """``u, u'`` (shape ``(2, len(t))``) at times ``t`` (s) from the segments of :func:`walk`,
    each from the closed form of the segment it falls in; False where a state is not finite."""
    model, pieces, n = _tables(model, pieces)
    table, t = _c(table), _c(np.atleast_1d(t))
    sid = np.ascontiguousarray(ids, dtype=_LONG)
    if table.ndim != 2 or table.shape[1] != 4 or sid.shape != (table.shape[0], 2) \
            or not table.shape[0] or sid[:, 0].min() < 0 or sid[:, 0].max() >= n:
        raise ValueError(f"contact on_grid: segments {table.shape}, ids {sid.shape}, "
                         f"{n} piece rows")
    out = np.empty((2, t.size))
    bad = library().gd_contact_on_grid(_ptr(model), _ptr(pieces), table.shape[0], _ptr(table),
                                       _ptr(sid), t.size, _ptr(t), _ptr(out))
    return out, bad == 0


__all__ = ["CHATTER", "GRAZE", "OK", "Segments", "find_root", "first_crossing", "flow",
           "on_grid", "stays_inside", "walk"]
