"""Exact propagation of the single-DOF model with backlash and piecewise-constant stiffness.

``m x'' + c (x' - e') + k(t) f(x - e) = W`` with the dead zone f (half gap b) and no or a
harmonic transmission error e is, in ``u = x - e``, ``m u'' + c u' + k(t) f(u) = W - m e''``:
linear with constant coefficients between a stiffness switch and a contact change, in one of
three contact states (drive flank u > b, gap ``|u| <= b``, back flank u < -b), so each piece is
closed-form (:func:`flow` plus the harmonic particular solution of
:mod:`gear_dyn.solvers.harmonic_forcing`). This module defines the pieces (``_Piece``: the
constants of each contact state and stiffness value, exported as rows of a table) and the
compiled kernel walks them (:mod:`gear_dyn.solvers.kernel.contact`, ``gd_flow.c``): contact
changes ``u = +-b`` are bracketed on the closed form and closed by safeguarded Newton steps on
the gap and its slope to 4 ulps of time; pieces that provably stay in their contact state
(``_Piece.stays_inside``) are not searched. What is left is rounding
(:func:`rounding_bound`). Method ``exact_contact``; ``auto`` takes it where
:func:`contact_exact_applies`. The flow's exact sensitivity (:func:`flow_with_sensitivity`,
with the :func:`saltation` matrix of each contact change) serves shooting. docs/solvers.md
describes the method and its tests.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError, SolverError
from gear_dyn.excitation import HarmonicSignal
from gear_dyn.models.base import Model
from gear_dyn.solvers.harmonic_forcing import Forcing
from gear_dyn.solvers.kernel import contact as ck

FloatArray = NDArray[np.float64]

#: contact states
BACK, GAP, DRIVE = -1, 0, 1
#: largest number of contact changes in one stiffness piece (a chattering graze ends in an error)
MAX_EVENTS_PER_PIECE = 1000


def contact_exact_applies(model: Model) -> bool:
    """True for a mesh-periodic model with backlash, piecewise-constant stiffness and no
    transmission error or a harmonic one (:class:`~gear_dyn.excitation.HarmonicSignal`, with
    damping: an undamped resonance has no periodic particular solution). A sampled
    transmission error (piecewise-linear e, impulsive e'') is not covered."""
    if not getattr(model, "mesh_periodic", False) or model.backlash is None:
        return False
    te = getattr(model, "transmission_error", None)
    if te is not None and not (isinstance(te, HarmonicSignal)
                                 and float(getattr(model, "damping", 0.0)) > 0.0):
        return False
    stiffness = getattr(model, "stiffness", None)
    return stiffness is not None and _stiffness_pieces(stiffness) is not None


#: per stiffness object (immutable; held here so its id stays valid): its segments' edges
#: (cycles), the index of each segment's value among the distinct values, the distinct values
#: (N/m); None where not piecewise constant. Bounded: the oldest entry goes first.
_PIECES: dict[int, tuple[Any, tuple[FloatArray, NDArray[np.intp], FloatArray] | None]] = {}
#: piece rows per (stiffness, m, c, W, b, transmission error, f_m when it has harmonics)
_ROWS: dict[tuple[Any, ...], tuple[Any, FloatArray]] = {}
_CACHE_SIZE = 16


def _remember(cache: dict[Any, Any], key: Any, value: Any) -> Any:
    if len(cache) >= _CACHE_SIZE:
        cache.pop(next(iter(cache)))
    cache[key] = value
    return value


def _stiffness_pieces(stiffness: Any) -> tuple[FloatArray, NDArray[np.intp], FloatArray] | None:
    """``stiffness.segments()`` as the walk reads it: edges (cycles), each segment's index
    into the distinct values, the distinct values (N/m); None where not piecewise constant.
    Computed once per stiffness object (the family of models a continuation walks shares
    one)."""
    hit = _PIECES.get(id(stiffness))
    if hit is not None and hit[0] is stiffness:
        return hit[1]
    seg = stiffness.segments()
    out = None
    if seg is not None:
        edges, values = (np.asarray(a, dtype=float) for a in seg)
        k_values, kidx = np.unique(values, return_inverse=True)
        out = (edges, kidx.ravel().astype(np.intp), k_values)
    return _remember(_PIECES, id(stiffness), (stiffness, out))[1]


def flow(state: int, k: float, m: float, c: float, w: float, b: float, x0: float, v0: float,
         s: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Closed-form ``x(s), v(s)`` (m, m/s) after ``s`` seconds in one contact state.

    The kernel's closed form (the one the walk propagates with): about the contact
    equilibrium ``x_eq = state b + W/k``, ``e^(-a s/2) (cos(q s) u0 + sin(q s) (v0 + a u0/2) / q)``
    with ``a = c/m`` and ``q`` the damped frequency (cosh, sinh when overdamped); in the gap the
    exponential velocity relaxation under the static load.

    Parameters
    ----------
    state : int
        ``DRIVE`` (+1), ``GAP`` (0) or ``BACK`` (-1).
    k, m, c, w, b : float
        Stiffness (N/m), mass (kg), damping (N s/m), static load (N), half gap (m).
    x0, v0 : float
        State at ``s = 0``.
    s : ndarray
        Times since the piece start in s (>= 0).
    """
    x, v = ck.flow(state, float(k), float(m), float(c), float(w), float(b), float(x0),
                   float(v0), np.asarray(s, dtype=float))
    shape = np.shape(s)
    return x.reshape(shape), v.reshape(shape)


def find_root(f: Callable[[float], float], lo: float, hi: float, f_lo: float, f_hi: float,
              xtol: float) -> float:
    """A root of ``f`` in ``[lo, hi]`` (``f_lo``, ``f_hi`` of opposite signs), to ``xtol``.

    The kernel's bracketing root finder, here on a Python function (the walk closes contact
    changes with Newton steps on such a bracket: it has the slope too). Illinois false
    position, safeguarded by bisection: the midpoint is taken instead
    of the secant point when the secant is degenerate (equal end values, e.g. values near the
    smallest float, which the Illinois halving can underflow to zero), when it falls outside
    the open bracket, or when the bracket has not halved within two steps. The sign of ``f`` at
    ``hi`` is read once from ``f_hi``, so the halved end values never decide which side is
    kept. The bracket always shrinks: at most ~2 log2((hi - lo) / xtol) evaluations (200 at
    most).

    Parameters
    ----------
    f : callable
        ``f(t)``, continuous on the bracket.
    lo, hi : float
        Bracket (``lo < hi``).
    f_lo, f_hi : float
        ``f(lo)`` and ``f(hi)``, of opposite signs. A zero end value is not returned as the
        root: the bracket closes on the sign change inside it (a piece that starts on a
        contact boundary looks for where it leaves it).
    xtol : float
        Width of the final bracket, same unit as ``lo`` and ``hi``.

    Returns
    -------
    float
        A point of the final bracket (an exact zero of ``f`` if one is met).
    """
    return ck.find_root(f, float(lo), float(hi), float(f_lo), float(f_hi), float(xtol))


def _model_header(model: Any, forcing: Forcing) -> FloatArray:
    """The model table of the kernel walk: m, c, w, b, f_m, p0, nh, ``2 pi n``, ``2 pi n f_m``."""
    n = forcing.n
    head = np.empty(7 + 2 * n.size)
    head[:7] = (float(model.mass), float(model.damping), float(model.static_load),
                float(model.backlash), forcing.fm, forcing.p0, float(n.size))
    if n.size:
        head[7:7 + n.size] = 2 * math.pi * n
        head[7 + n.size:] = 2 * math.pi * n * forcing.fm
    return head


class _Piece:
    """The constants of one contact state in one stiffness piece, in ``u = x - e(t)``.

    The solution from ``(u0, v0)`` at ``t0`` is the particular part ``u_p(t)`` of the
    transmission error's forcing (:mod:`gear_dyn.solvers.harmonic_forcing`; zero without one)
    plus the closed form :func:`flow` of ``z = u - u_p`` (homogeneous and static load).
    :meth:`row` is the piece as the kernel walk reads it.
    """

    def __init__(self, model: Any, k: float, state: int, forcing: Forcing | None = None
                 ) -> None:
        self.m, self.c, self.w = float(model.mass), float(model.damping), float(model.static_load)
        self.b, self.k, self.state = float(model.backlash), float(k), state
        self.a = a = self.c / self.m
        self.w2 = w2 = self.k / self.m if state != GAP else 0.0
        wd2 = w2 - 0.25 * a * a
        forcing = Forcing.of(model) if forcing is None else forcing
        self.part = forcing.particular(w2, a)
        # sampling step: a quarter of the damped period and of the top harmonic's period
        om = max(math.sqrt(wd2) if wd2 > 0 else 0.0, forcing.top_frequency)
        self.h = 0.25 * 2 * math.pi / om if om > 0 else math.inf
        self.q = math.sqrt(wd2) if state != GAP and wd2 > 0 else 0.0  # damped rad/s; 0: none
        self.x_eq = state * self.b + self.w / self.k if state != GAP else 0.0
        self._header = _model_header(model, forcing)

    def row(self) -> FloatArray:
        """The kernel's row of this piece: state, k, a, w2, q, x_eq, h, the particular
        solution's amplitude and curvature bounds
        (:class:`~gear_dyn.solvers.harmonic_forcing.Particular`), its cosine and sine
        coefficients (m)."""
        p = self.part
        return np.concatenate([[float(self.state), self.k, self.a, self.w2, self.q, self.x_eq,
                                self.h, p.amplitude, p.curvature], p.ca, p.cb])

    def at(self, x0: float, v0: float, s: FloatArray, t0: float = 0.0
           ) -> tuple[FloatArray, FloatArray]:
        """``u, u'`` (m, m/s) at ``t0 + s`` from ``(x0, v0)`` at ``t0`` (s): the kernel's
        closed form of this piece (one segment of the walk)."""
        s = np.asarray(s, dtype=float)
        seg = np.array([[float(t0), float(x0), float(v0), math.inf]])
        out, _finite = ck.on_grid(self._header, self.row()[None, :], seg,
                                  np.zeros((1, 2), dtype=np.int64), float(t0) + s.ravel())
        return out[0].reshape(s.shape), out[1].reshape(s.shape)

    def stays_inside(self, x0: float, v0: float, t0: float = 0.0) -> bool:
        """True when the motion from ``(x0, v0)`` at ``t0`` provably never reaches the boundary.

        In a contact state with damped frequency ``q`` the closed form of :func:`flow` is
        ``z(s) - x_eq = e^(-a s / 2) (cos(q s) z0 + sin(q s) (zv0 + a z0 / 2) / q)`` about
        the equilibrium ``x_eq`` (``z0`` relative to it), so ``|z - x_eq| <= A =
        hypot(z0, (zv0 + a z0 / 2) / q)`` for all ``s >= 0`` (Cauchy-Schwarz), and the
        particular part ``|u_p| <= sum_n hypot(A_n, B_n)``. When ``x_eq`` lies inside the state
        at a distance above the sum of both from the boundary, no contact change can occur in
        this piece. The margin ``1e-6`` of it covers rounding. This spares the search where
        the response has settled, e.g. at very low speed, where a stiffness piece spans
        thousands of natural periods. The kernel's test (the walk's).
        """
        return ck.stays_inside(self._header, self.row()[None, :], 0, float(x0), float(v0),
                               float(t0))

    def field(self, x: float, v: float, t: float = 0.0) -> FloatArray:
        """The vector field ``[u', u'']`` of this contact state at ``(u, u')`` and t
        (m/s, m/s^2), the transmission error's forcing included."""
        spring = 0.0 if self.state == GAP else self.k * (x - self.state * self.b)
        return np.array([v, (self.w - self.c * v - spring) / self.m + self.part.forcing.value(t)])


def _first_crossing(pc: _Piece, t0: float, x0: float, v0: float, length: float, xtol: float
                    ) -> float | None:
    """Time after ``t0`` of the first contact change of ``pc`` from ``(x0, v0)`` within
    ``length``, or None: the kernel walk's search on one piece.

    Sampled ``pc.h`` apart (a quarter of the damped and of the top harmonic's period). Without
    a transmission error the motion about each contact state's equilibrium is a damped
    oscillation (or, in the gap, has one extremum at most), so each sample interval holds at
    most one extremum: a sign change is closed by safeguarded Newton steps (the closed form
    gives the slope), an extremum below the boundary by the root of the velocity first. With
    one, each sample interval of the distance
    ``g`` to a boundary is proved free of a zero (g lies above its chord less
    ``G (s - s0)(s1 - s) / 2``, ``G`` a bound on ``|u''|``) or ``g`` monotone (then closed by
    Newton steps), else halved, left half first (docs/solvers.md, "With a harmonic
    transmission error"). A tangential graze is bisected down to ``xtol``. Proofs hold up to
    the rounding of ``g`` (~ eps |u|).
    """
    return ck.first_crossing(pc._header, pc.row()[None, :], 0, float(t0), float(x0), float(v0),
                             float(length), float(xtol))


def _te_shift(mm: Any, t: FloatArray) -> tuple[FloatArray, FloatArray]:
    """``e(t), e'(t)`` of the model's transmission error (m, m/s; zeros without one)."""
    t = np.asarray(t, dtype=float)
    te = getattr(mm, "transmission_error", None)
    if te is None:
        return np.zeros_like(t), np.zeros_like(t)
    p = mm.phase(t)
    return (np.asarray(te.value(p), dtype=float),
            float(mm.mesh_frequency) * np.asarray(te.slope(p), dtype=float))


class Walk:
    """The closed-form pieces of one propagation (:func:`walk`): the end state, the located
    contact changes, the exact sensitivity and states on any grid inside the walked span, all
    from the same pieces, with no second propagation.

    Attributes
    ----------
    model : Model
        The model walked.
    t0, t1 : float
        Start and end time (s).
    start : ndarray (2,)
        State at ``t0`` [m, m/s].
    end : ndarray (2,)
        State at ``t1`` [m, m/s].
    n_segments : int
        Closed-form pieces.
    """

    def __init__(self, model: Any, t0: float, t1: float, start: tuple[float, float],
                 tables: tuple[FloatArray, FloatArray], segments: ck.Segments,
                 end: tuple[float, float], end_rate: FloatArray | None = None) -> None:
        self.model, self.t0, self.t1 = model, t0, t1
        self.start = np.array(start)
        self._tables, self._segs = tables, segments
        self.end = np.array(end)
        self._end_rate = end_rate
        self.n_segments = int(segments.table.shape[0])

    @property
    def event_times(self) -> FloatArray:
        """Times of the located contact changes (s), in order (the ends of the segments that
        end at one)."""
        tab, ids = self._segs.table, self._segs.ids
        return np.asarray((tab[:, 0] + tab[:, 3])[ids[:, 1] == 1])

    def sensitivity(self) -> FloatArray:
        """``d y(t1) / d y(t0)`` (entries dimensionless, s and 1/s): the product, in time
        order, of each piece's ``exp(A_j s_j)`` and, at each contact change, the
        :func:`saltation` matrix of the surface ``x = +-b``: the identity where the field is
        continuous (the dead zone's ends; a field with a jump gets the general formula),
        formed by the kernel during the walk. A stiffness switch is a fixed instant, not a
        state surface: the sensitivity carries over unchanged.

        Raises
        ------
        SolverError
            Non-finite end state or sensitivity (a diverging response), or a discontinuous
            field crossed tangentially (no derivative).
        """
        if self._segs.status == ck.GRAZE:
            raise SolverError("a discontinuous vector field is crossed tangentially (grazing) "
                              f"at t = {self._segs.fail_time:.6g} s: the flow has no derivative "
                              "there")
        phi = self._segs.phi.copy()
        if not (np.isfinite(self.end).all() and np.isfinite(phi).all()):
            raise SolverError("exact_contact produced non-finite states: the response diverges")
        return phi

    def spells(self) -> tuple[NDArray[np.int64], FloatArray]:
        """The contact state (``BACK``, ``GAP``, ``DRIVE``) and duration (s) of each
        closed-form segment, in time order: the state the walk propagated it in (its piece
        row ``3 j + state + 1``), so every spell between located contact changes is seen,
        however short. Consecutive segments of one state are split at stiffness switches."""
        rows = self._segs.ids[:, 0]
        return rows % 3 - 1, self._segs.table[:, 3].copy()

    def mesh_rate(self) -> FloatArray:
        """``d y(t1) / d f_m`` [m/Hz, m/(s Hz)]: the end state's derivative with respect to the
        mesh frequency, the span fixed in mesh phase (both ends and every stiffness switch
        at their phase, so ``d t / d f_m = -t / f_m``), the start state fixed: for
        ``t0 = 0``, ``t1 = n / f_m`` the n-period map's, ``dP / d f_m``.

        Derivation (the trajectory sensitivity of a hybrid system to a parameter, Hiskens &
        Pai 2000, IEEE Trans. Circuits Syst. I 47(2)). With ``tau = f_m t`` the
        map is ``P(y0; f_m)``: the flow of ``m u'' + c u' + k(tau) f(u) = W + m g(t)`` over
        ``0 <= tau <= n``; in time t the stiffness switches at ``t_j = (tau_j - p0) / f_m``
        and the end ``t1 = n / f_m`` move with ``f_m`` (``d t_j / d f_m = -t_j / f_m``), the
        coefficients ``m, c, k`` of each piece do not, and the transmission error's forcing
        ``g = -e''`` and the particular solution ``u_p`` of each piece do
        (:meth:`~gear_dyn.solvers.harmonic_forcing.Forcing.particular_rate`). The
        derivative ``s = d u(t) / d f_m`` at fixed t is then carried along the walk:

        - across a piece from ``t_a`` to ``t_b``, ``u = u_p + H (u(t_a) - u_p(t_a))`` + the
          static part, so ``s_b = H (s_a - du_p(t_a)) + du_p(t_b)`` with ``H`` the piece's
          transition matrix (the state sensitivity's factor) and ``du_p`` the explicit
          derivative of ``u_p`` at fixed time (coefficients and phase ``2 pi n f_m t``);
        - at a contact change ``u = +-b`` (a surface that does not move with ``f_m``),
          ``s+ = S s-`` with the saltation matrix S of the state sensitivity;
        - at a stiffness switch, ``s+ = s- + (F- - F+) d t_j / d f_m``, ``F-+`` the fields
          of the pieces before and after there (they differ in the spring force only);
        - at the ends, ``- F(t0) d t0 / d f_m`` and ``+ F(t1) d t1 / d f_m`` (the field of
          the first and last piece), and back from ``u = x - e`` to x: ``e(t1)`` is fixed in
          phase, ``e'(t1) = f_m E'(phase)`` adds ``E'``, and at the start ``-E'``.

        Exact to rounding, like :meth:`sensitivity` (tests/solvers/test_mesh_rate.py
        against a central difference).

        Raises
        ------
        InputError
            The walk was made without ``mesh_rate=True``.
        SolverError
            As :meth:`sensitivity` (a graze of a discontinuous field, a diverging response).
        """
        if self._end_rate is None:
            raise InputError("mesh_rate: walk(..., mesh_rate=True) was not asked for")
        if self._segs.status == ck.GRAZE:
            self.sensitivity()  # raises, naming the graze
        rate = self._end_rate.copy()
        if not (np.isfinite(rate).all() and np.isfinite(self.end).all()):
            raise SolverError("exact_contact produced a non-finite mesh-frequency derivative")
        return rate

    def mark_sensitivities(self) -> FloatArray:
        """``d y(m_{j+1}) / d y(m_j)`` over each span between consecutive marks of
        :func:`walk` (``m_0 = t0``, the last ``t1``), shape ``(len(marks) + 1, 2, 2)``, as
        :meth:`sensitivity` per span (no product over the whole walk, which can overflow
        where the motion is chaotic).

        Raises
        ------
        InputError
            The walk had no marks.
        SolverError
            As :meth:`sensitivity`.
        """
        phis = self._segs.phis
        if phis is None:
            raise InputError("mark_sensitivities: walk(..., marks=...) was called without marks")
        if self._segs.status == ck.GRAZE:
            self.sensitivity()  # raises, naming the graze
        if not (np.all(np.isfinite(self.end)) and np.all(np.isfinite(phis))):
            raise SolverError("exact_contact produced non-finite states: the response diverges")
        return phis.copy()

    def on_grid(self, t_grid: FloatArray) -> FloatArray:
        """States ``[x, v]`` (m, m/s), shape ``(2, len(t_grid))``, at times ``t_grid`` (s)
        within ``[t0, t1]``, each from the closed form of the piece it falls in (the kernel).

        Raises
        ------
        SolverError
            Non-finite states (a diverging response).
        """
        t_grid = np.asarray(t_grid, dtype=float)
        out, finite = ck.on_grid(*self._tables, self._segs.table, self._segs.ids, t_grid)
        out = out.reshape((2, *t_grid.shape))
        if getattr(self.model, "transmission_error", None) is not None:
            out += np.asarray(_te_shift(self.model, t_grid))  # back from u = x - e to x
            finite = finite and bool(np.all(np.isfinite(out)))
        if not finite:  # the kernel's flag: a state not finite
            raise SolverError("exact_contact produced non-finite states: the response diverges")
        return out


def _piece_tables(mm: Any, k_values: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The kernel's model table and piece rows ``3 j + state + 1`` for the stiffness values
    ``k_values[j]`` (N/m)."""
    forcing = Forcing.of(mm)
    rows = [_Piece(mm, float(k), st, forcing).row() for k in k_values.tolist()
            for st in (BACK, GAP, DRIVE)]
    return _model_header(mm, forcing), np.array(rows)


def _walk_tables(mm: Any, k_values: FloatArray, forcing: Forcing | None = None
                 ) -> tuple[FloatArray, FloatArray]:
    """:func:`_piece_tables` for all of the stiffness's distinct values ``k_values``, the
    rows reused while the model differs only in what they do not depend on (speed and phase
    without a transmission error: the rows of a continuation's family are built once)."""
    forcing = Forcing.of(mm) if forcing is None else forcing
    te = getattr(mm, "transmission_error", None)
    key = (id(mm.stiffness), float(mm.mass), float(mm.damping), float(mm.static_load),
           float(mm.backlash), id(te), forcing.fm if forcing.n.size else 0.0)
    hit = _ROWS.get(key)
    if hit is None or hit[0][0] is not mm.stiffness or hit[0][1] is not te:
        hit = _remember(_ROWS, key, ((mm.stiffness, te), _piece_tables(mm, k_values)[1]))
    return _model_header(mm, forcing), hit[1]


def _piece_rates(mm: Any, k_values: FloatArray, forcing: Forcing | None = None
                 ) -> FloatArray | None:
    """``d (ca, cb) / d f_m`` of the rows of :func:`_piece_tables` (None without harmonics)."""
    forcing = Forcing.of(mm) if forcing is None else forcing
    if not forcing.n.size:
        return None
    m, c = float(mm.mass), float(mm.damping)
    rows = [np.concatenate(forcing.particular_rate(float(k) / m if st != GAP else 0.0, c / m))
            for k in k_values.tolist() for st in (BACK, GAP, DRIVE)]
    return np.array(rows)


def walk(model: Model, y0: FloatArray, t1: float, t0: float = 0.0,
         marks: FloatArray | None = None, mesh_rate: bool = False) -> Walk:
    """The exact propagation of ``model`` from ``y(t0) = y0`` to ``t1``, kept as its pieces.

    :func:`propagate_contact_exact` and :func:`flow_with_sensitivity` are its states on a grid
    and its end state with :meth:`Walk.sensitivity`; a caller that needs both (a shooting
    point and its response measures) walks once. The pieces are in ``u = x - e(t)``, ``u'``,
    cut at the stiffness switches; within a stiffness piece each located contact change ends a
    segment, its state put exactly on the boundary it crossed, where the next state starts.
    Python sets up the pieces (``_Piece``, one row per contact state and stiffness value) and
    the compiled kernel walks them (:func:`gear_dyn.solvers.kernel.contact.walk`).

    Parameters
    ----------
    model : Model
        Where :func:`contact_exact_applies`.
    y0 : ndarray
        Start state [m, m/s].
    t1 : float
        End time in s (> t0).
    t0 : float
        Start time in s.
    marks : ndarray or None
        Increasing times in ``(t0, t1)`` (s) at which the walk also takes the sensitivity
        apart (:meth:`Walk.mark_sensitivities`), e.g. every mesh period for a Lyapunov
        exponent; the pieces are cut there too.
    mesh_rate : bool
        Also the end state's derivative with respect to the mesh frequency
        (:meth:`Walk.mesh_rate`).

    Raises
    ------
    InputError
        The model is not of that kind, or marks outside ``(t0, t1)`` or not increasing.
    SolverError
        A chattering contact (too many events in one stiffness piece).
    """
    if not contact_exact_applies(model):
        raise InputError(
            "solver.method = 'exact_contact' needs the single-DOF model with backlash, "
            "piecewise-constant stiffness and no or a damped harmonic transmission error; "
            "use DOP853 or LSODA")
    mm: Any = model  # a mesh model with backlash: checked above
    t0, t1 = float(t0), float(t1)
    x0, v0 = float(y0[0]), float(y0[1])
    edges, seg_k, k_values = _stiffness_pieces(mm.stiffness)  # type: ignore[misc]
    inner = np.asarray(mm.switching_times(t0, t1), dtype=float)
    slots = None
    if marks is not None:
        marks = np.asarray(marks, dtype=float).ravel()
        if marks.size and not (marks[0] > t0 and marks[-1] < t1 and np.all(np.diff(marks) > 0)):
            raise InputError(f"walk: marks must increase strictly inside ({t0:.6g}, {t1:.6g}) s")
        inner = np.union1d(inner, marks)
    cuts = np.concatenate([[t0], inner, [t1]])
    if marks is not None:
        slots = np.searchsorted(marks, cuts[:-1], side="right")
    # each stiffness piece's segment, from its middle phase
    mid = np.mod(np.asarray(mm.phase(0.5 * (cuts[:-1] + cuts[1:])), dtype=float), 1.0)
    kidx = seg_k.take(np.searchsorted(edges, mid, side="right") - 1, mode="clip")
    forcing = Forcing.of(mm)
    tables = _walk_tables(mm, k_values, forcing)
    xtol = 4 * math.ulp(max(abs(t0), abs(t1), 1e-300))
    shifted = getattr(mm, "transmission_error", None) is not None
    e0 = ed0 = e1 = ed1 = 0.0
    if shifted:
        e0, ed0 = (float(a[0]) for a in _te_shift(mm, np.array([t0])))
        e1, ed1 = (float(a[0]) for a in _te_shift(mm, np.array([t1])))
    param = None
    fm = float(mm.mesh_frequency)
    if mesh_rate:  # every cut fixed in phase: d t / d f_m = -t / f_m; the start u' has -E'
        param = (-cuts / fm, _piece_rates(mm, k_values, forcing), np.array([0.0, -ed0 / fm]),
                 1.0)
    segs = ck.walk(*tables, cuts, kidx.ravel(), x0 - e0, v0 - ed0, xtol,
                   MAX_EVENTS_PER_PIECE, slots, param)
    if segs.status == ck.CHATTER:
        raise SolverError(
            f"exact_contact: more than {MAX_EVENTS_PER_PIECE} contact changes in one "
            f"stiffness piece at t = {segs.fail_time:.6g} s (a chattering graze); use LSODA")
    x, v = segs.end.tolist()
    end_rate = None
    if segs.dpar is not None:  # back to x: e(t1) is fixed in phase, e'(t1) = f_m E' adds E'
        end_rate = segs.dpar + np.array([0.0, ed1 / fm])
    return Walk(model, t0, t1, (x0, v0), tables, segs, (x + e1, v + ed1), end_rate)


def propagate_contact_exact(
    model: Model, t_grid: FloatArray, settings: Any = None, y0: FloatArray | None = None
) -> tuple[FloatArray, dict[str, Any]]:
    """States of ``model`` on ``t_grid``: closed form between located contact changes
    (:meth:`Walk.on_grid` of :func:`walk`).

    Parameters
    ----------
    model : Model
        Single-DOF mesh model with backlash, piecewise-constant stiffness, no or a damped
        harmonic transmission error (:func:`contact_exact_applies`).
    t_grid : ndarray
        Increasing output times in s; the first is the initial time.
    settings : SolverSettings, unused
        Accepted for the solver registry's signature (there is no tolerance to set).
    y0 : ndarray or None
        Initial state [x, v]; None uses ``model.initial_state()``.

    Returns
    -------
    y : ndarray (2, n_t)
    stats : dict
        ``nfev`` 0, ``n_segments`` (closed-form pieces), ``n_contact_events``, ``event_times``
        (s, the located contact changes).

    Raises
    ------
    InputError
        The model is not of that kind.
    SolverError
        A chattering contact (too many events in one stiffness piece) or non-finite states.
    """
    del settings
    t_grid = np.asarray(t_grid, dtype=float)
    w = walk(model, model.initial_state() if y0 is None else y0, float(t_grid[-1]),
             float(t_grid[0]))
    out = w.on_grid(t_grid)
    stats = {"nfev": 0, "njev": 0, "nlu": 0, "n_segments": w.n_segments,
             "n_contact_events": len(w.event_times), "event_times": w.event_times}
    return out, stats


def saltation(f_minus: FloatArray, f_plus: FloatArray, normal: FloatArray) -> FloatArray:
    """Saltation matrix ``S = I + (f+ - f-) n^T / (n^T f-)`` of a crossing of a state surface.

    Maps a state perturbation just before the crossing to one just after it, the crossing
    time moving with the perturbation (Aizerman & Gantmacher 1958, J. Appl. Math. Mech. 22;
    Leine & Nijmeijer 2004, Dynamics and Bifurcations of Non-Smooth Mechanical Systems).

    Parameters
    ----------
    f_minus, f_plus : ndarray (n,)
        Vector field before and after the crossing, at the crossing point.
    normal : ndarray (n,)
        Gradient of the switching function ``h(y)`` (the surface ``h = 0``).

    Returns
    -------
    ndarray (n, n)
        The identity where the field is continuous (``f+ = f-``, as at the dead zone's ends).

    Raises
    ------
    SolverError
        A discontinuous field crossed tangentially (``n^T f- = 0``, grazing): no derivative.
    """
    jump = np.asarray(f_plus, dtype=float) - np.asarray(f_minus, dtype=float)
    eye = np.eye(jump.size)
    if not np.any(jump):
        return eye
    rate = float(np.dot(normal, f_minus))
    if rate == 0.0:
        raise SolverError("a discontinuous vector field is crossed tangentially (grazing): "
                          "the flow has no derivative there")
    return eye + np.outer(jump, normal) / rate


def flow_with_sensitivity(model: Model, y0: FloatArray, t1: float, t0: float = 0.0
                          ) -> tuple[FloatArray, FloatArray]:
    """State ``y(t1)`` from ``y(t0) = y0`` and its exact sensitivity ``d y(t1) / d y0``.

    :meth:`Walk.sensitivity` of :func:`walk`. No truncation error: rounding and the event
    times' rounding (4 ulps, :func:`rounding_bound`).

    Parameters
    ----------
    model : Model
        Where :func:`contact_exact_applies`.
    y0 : ndarray
        Start state [m, m/s].
    t1 : float
        End time in s (> t0).
    t0 : float
        Start time in s.

    Returns
    -------
    y : ndarray (2,)
    phi : ndarray (2, 2)
        ``d y(t1) / d y0`` (entries dimensionless, s and 1/s).

    Raises
    ------
    InputError
        The model is not of that kind.
    SolverError
        A chattering contact or non-finite states.
    """
    w = walk(model, y0, t1, t0)
    phi = w.sensitivity()
    return w.end, phi


def rounding_bound(y: FloatArray, scale: FloatArray, n_segments: int) -> float:
    """Stated error of :func:`propagate_contact_exact`, relative to ``scale[0]``.

    Rounding of the closed form and of the carried state, ``eps`` per piece relative to the
    state magnitude, taken linear in the number of pieces with a safety factor of 1000 (the
    event times are located to 4 ulps; the dead zone is continuous, so an event-time error
    dt changes the state by O(k dt^2 / m) only): ``1000 eps (n_segments + 1) max|x| / scale``.
    """
    amp = float(np.max(np.abs(y[0]))) / float(scale[0])
    return float(1000 * np.finfo(float).eps * (n_segments + 1) * max(amp, 1.0))
