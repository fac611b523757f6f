"""Exact propagation of the single-DOF model with backlash and piecewise-constant stiffness.

``m x'' + c (x' - e') + k(t) f(x - e) = W`` with the dead zone f (half gap b) and no or a
harmonic transmission error e is, in ``u = x - e``, ``m u'' + c u' + k(t) f(u) = W - m e''``:
linear with constant coefficients between a stiffness switch and a contact change, in one of
three contact states (drive flank u > b, gap ``|u| <= b``, back flank u < -b), so each piece is
closed-form (:func:`flow` plus the harmonic particular solution of
:mod:`gear_dyn.solvers.harmonic_forcing`). Contact changes ``u = +-b`` are bracketed on that
closed form (``_first_crossing()``) and closed by :func:`find_root`; pieces that provably
stay in their contact state (``_Piece.stays_inside``) are not searched. What is left is
rounding (:func:`rounding_bound`). Method ``exact_contact``; ``auto`` takes it where
:func:`contact_exact_applies`. The flow's exact sensitivity (:func:`flow_with_sensitivity`,
with the :func:`saltation` matrix of each contact change) serves shooting. docs/solvers.md
describes the method and its tests.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError, SolverError
from gear_dyn.excitation import HarmonicSignal
from gear_dyn.models.base import Model
from gear_dyn.solvers.harmonic_forcing import Forcing

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
    return stiffness is not None and stiffness.segments() is not None


def flow(state: int, k: float, m: float, c: float, w: float, b: float, x0: float, v0: float,
         s: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Closed-form ``x(s), v(s)`` (m, m/s) after ``s`` seconds in one contact state.

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
    return _flow(np, state, k, m, c, w, b, x0, v0, np.asarray(s, dtype=float))


def _flow(xp: Any, state: int, k: float, m: float, c: float, w: float, b: float, x0: float,
          v0: float, s: Any) -> tuple[Any, Any]:
    """:func:`flow` with the functions of ``xp``: numpy for arrays, or math for one time ``s``
    with Python floats (the root finders' inner loop: no array set-up per call)."""
    a = c / m
    if state == GAP:
        if a == 0.0:
            return x0 + v0 * s + 0.5 * (w / m) * s * s, v0 + (w / m) * s
        e1 = -xp.expm1(-a * s) / a  # (1 - e^{-a s}) / a, exact also for small a s
        return x0 + v0 * e1 + (w / m) * (s - e1) / a, v0 + (w / m - a * v0) * e1
    w2 = k / m
    x_eq = state * b + w / k
    u0 = x0 - x_eq
    q2 = 0.25 * a * a - w2
    if q2 < 0.0:  # underdamped: cos, sin
        q = math.sqrt(-q2)
        cs, sn = xp.cos(q * s), xp.sin(q * s) / q
    elif q2 > 0.0:  # overdamped: cosh, sinh
        q = math.sqrt(q2)
        cs, sn = xp.cosh(q * s), xp.sinh(q * s) / q
    else:
        cs, sn = 1.0, s
    dec = xp.exp(-0.5 * a * s)
    u = dec * (cs * u0 + sn * (v0 + 0.5 * a * u0))
    v = dec * (cs * v0 - sn * (w2 * u0 + 0.5 * a * v0))
    return x_eq + u, v


def find_root(f: Callable[[float], float], lo: float, hi: float, f_lo: float, f_hi: float,
              xtol: float) -> float:
    """A root of ``f`` in ``[lo, hi]`` (``f_lo``, ``f_hi`` of opposite signs), to ``xtol``.

    Illinois false position, safeguarded by bisection: the midpoint is taken instead of the
    secant point when the secant is degenerate (equal end values, e.g. values near the smallest
    float, which the Illinois halving can underflow to zero), when it falls outside the open
    bracket, or when the bracket has not halved within two steps. The sign of ``f`` at ``hi``
    is read once from ``f_hi``, so the halved end values never decide which side is kept. The
    bracket always shrinks: at most ~2 log2((hi - lo) / xtol) evaluations.

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
    hi_positive = f_hi > 0.0 or (f_hi == 0.0 and f_lo < 0.0)
    side = 0
    width = hi - lo
    for it in range(200):
        if hi - lo <= xtol:
            break
        den = f_hi - f_lo
        t = (lo * f_hi - hi * f_lo) / den if den != 0.0 else math.nan
        if not (lo < t < hi) or (it % 2 == 1 and hi - lo > 0.5 * width):
            t = 0.5 * (lo + hi)  # also when t is nan (degenerate secant)
        width = hi - lo
        ft = f(t)
        if ft == 0.0:
            return t
        if (ft > 0.0) == hi_positive:
            hi, f_hi = t, ft
            if side == -1:
                f_lo *= 0.5
            side = -1
        else:
            lo, f_lo = t, ft
            if side == 1:
                f_hi *= 0.5
            side = 1
    return 0.5 * (lo + hi)


class _Piece:
    """The constants of one contact state in one stiffness piece, in ``u = x - e(t)``.

    The solution from ``(u0, v0)`` at ``t0`` is the particular part ``u_p(t)`` of the
    transmission error's forcing (:mod:`gear_dyn.solvers.harmonic_forcing`; zero without one)
    plus the closed form :func:`flow` of ``z = u - u_p`` (homogeneous and static load).
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

    def _z(self, u0: float, v0: float, t0: float) -> tuple[float, float]:
        """The state of ``z = u - u_p`` at ``t0``."""
        if not self.part.active:
            return u0, v0
        pu, pv = self.part.at_scalar(t0)
        return u0 - pu, v0 - pv

    def hom(self, z0: float, zv0: float, s: FloatArray) -> tuple[FloatArray, FloatArray]:
        """``z(s), z'(s)``: :func:`flow` of this state (m, m/s)."""
        return flow(self.state, self.k, self.m, self.c, self.w, self.b, z0, zv0, s)

    def at(self, x0: float, v0: float, s: FloatArray, t0: float = 0.0
           ) -> tuple[FloatArray, FloatArray]:
        """``u, u'`` (m, m/s) at ``t0 + s`` from ``(x0, v0)`` at ``t0`` (s)."""
        if not self.part.active:
            return self.hom(x0, v0, s)
        z0, zv0 = self._z(x0, v0, t0)
        zx, zv = self.hom(z0, zv0, s)
        pu, pv = self.part.at(t0 + np.asarray(s, dtype=float))
        return zx + pu, zv + pv

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
        thousands of natural periods.
        """
        if self.q == 0.0:
            return False
        z0, zv0 = self._z(x0, v0, t0)
        u0 = z0 - self.x_eq
        amp = math.hypot(u0, (zv0 + 0.5 * self.a * u0) / self.q) + self.part.amplitude
        return self.state * (self.x_eq - self.state * self.b) > amp * (1.0 + 1e-6)

    def curvature_bound(self, z: FloatArray, zv: FloatArray, h: float) -> FloatArray:
        """A bound on ``|u''|`` over ``[s, s + h]`` from the state ``(z, zv)`` of ``z`` at s.

        Gap: ``z'' = (w/m - a zv) e^(-a s)``, so ``|w/m - a zv|``. Contact:
        ``z'' = -a z' - w2 (z - x_eq)`` with ``|z - x_eq|`` and ``|z'|`` bounded as in
        :meth:`stays_inside` (underdamped: ``hypot`` amplitudes, for all later s; overdamped or
        critical: ``e^(-a s/2) cosh(q s) <= 1`` and ``e^(-a s/2) sinh(q s) / q <= s <= h``). Plus
        the particular part's ``sum_n W_n^2 hypot(A_n, B_n)``.
        """
        a, w2 = self.a, self.w2
        if self.state == GAP:
            return np.abs(self.w / self.m - a * zv) + self.part.curvature
        u = z - self.x_eq
        cu, cv = zv + 0.5 * a * u, w2 * u + 0.5 * a * zv
        if self.q > 0.0:
            amp_u, amp_v = np.hypot(u, cu / self.q), np.hypot(zv, cv / self.q)
        else:
            amp_u, amp_v = np.abs(u) + h * np.abs(cu), np.abs(zv) + h * np.abs(cv)
        return a * amp_v + w2 * amp_u + self.part.curvature

    def levels(self) -> tuple[float, ...]:
        """The contact boundaries this state can leave through."""
        return (self.b, -self.b) if self.state == GAP else (self.state * self.b,)

    def field(self, x: float, v: float, t: float = 0.0) -> FloatArray:
        """The vector field ``[u', u'']`` of this contact state at ``(u, u')`` and t
        (m/s, m/s^2), the transmission error's forcing included."""
        spring = 0.0 if self.state == GAP else self.k * (x - self.state * self.b)
        return np.array([v, (self.w - self.c * v - spring) / self.m + self.part.forcing.value(t)])

    def transition(self, s: FloatArray) -> FloatArray:
        """``exp(A s)`` of this contact state's homogeneous part, shape ``(len(s), 2, 2)``:
        the closed form of :func:`flow` with unit start states, no load and no gap."""
        s = np.asarray(s, dtype=float)
        out = np.empty((s.size, 2, 2))
        out[:, 0, 0], out[:, 1, 0] = flow(self.state, self.k, self.m, self.c, 0.0, 0.0, 1.0, 0.0, s)
        out[:, 0, 1], out[:, 1, 1] = flow(self.state, self.k, self.m, self.c, 0.0, 0.0, 0.0, 1.0, s)
        return out


def _first_crossing(pc: _Piece, t0: float, x0: float, v0: float, length: float, xtol: float
                    ) -> float | None:
    """Time after ``t0`` of the first contact change within ``length``, or None.

    Sampled ``pc.h`` apart (a quarter of the damped and of the top harmonic's period), each
    sample interval of the distance ``g`` to a boundary is proved free of a zero (g lies above
    its chord less ``G (s - s0)(s1 - s) / 2``, ``G`` the :meth:`_Piece.curvature_bound`) or
    ``g`` monotone (then closed by :func:`find_root`), else halved, left half first
    (docs/solvers.md, "With a harmonic transmission error"). A tangential graze is bisected
    down to ``xtol``. Proofs hold up to the rounding of ``g`` (~ eps |u|).
    """
    if not pc.part.n.size:
        return _first_crossing_unforced(pc, x0, v0, length, xtol)
    if pc.stays_inside(x0, v0, t0):
        return None
    n = max(2, math.ceil(length / pc.h)) if math.isfinite(pc.h) else 4
    s = np.linspace(0.0, length, n + 1)
    z0, zv0 = pc._z(x0, v0, t0)
    zx, zv = pc.hom(z0, zv0, s)
    pu, pv = pc.part.at(t0 + s)
    d = float(s[1] - s[0])
    curv = pc.curvature_bound(zx, zv, d)
    zargs = (z0, zv0)
    best: float | None = None
    for level in pc.levels():
        inside = 1.0 if pc.state == DRIVE or (pc.state == GAP and level < 0) else -1.0
        g = (zx + pu - level) * inside  # >= 0 while in this state
        dg = (zv + pv) * inside
        g[0] = abs(g[0])  # the piece starts on or inside the boundary
        lo, hi = g[:-1], g[1:]
        clear = (lo > 0.0) & (hi > 0.0) & (np.minimum(lo, hi) > curv[:-1] * d * d / 8)
        clear |= (np.abs(dg[:-1]) > curv[:-1] * d) & (hi >= 0.0)
        for j in np.flatnonzero(~clear).tolist():
            if best is not None and s[j] >= best:
                break
            hit = _refine(pc, zargs, t0, level, inside, float(s[j]), float(s[j + 1]),
                          float(g[j]), float(dg[j]), float(curv[j]), float(g[j + 1]), xtol)
            if hit is not None:
                best = hit if best is None else min(best, hit)
                break
    return best


def _refine(pc: _Piece, zargs: tuple[float, float], t0: float, level: float, inside: float,
            s0: float, s1: float, g0: float, dg0: float, curv0: float, g1: float, xtol: float
            ) -> float | None:
    """First zero of ``g`` in ``[s0, s1]`` by the proofs of ``_first_crossing()``, or None."""
    part = pc.part

    def gv(s: float) -> tuple[float, float, float, float]:
        zx, zv = _flow(math, pc.state, pc.k, pc.m, pc.c, pc.w, pc.b, zargs[0], zargs[1], s)
        pu, pv = part.at_scalar(t0 + s)
        return (zx + pu - level) * inside, (zv + pv) * inside, zx, zv

    def gf(s: float) -> float:
        return gv(s)[0]

    stack = [(s0, s1, g0, dg0, curv0, g1)]
    while stack:
        a, b, ga, dga, ca, gb = stack.pop()
        wd = b - a
        if ga > 0.0 and gb > 0.0 and min(ga, gb) > ca * wd * wd / 8:
            continue
        if abs(dga) > ca * wd:  # monotone on [a, b]
            if gb < 0.0:
                return find_root(gf, a, b, ga, gb, xtol)
            continue
        if wd <= xtol:
            if gb < 0.0:
                return b
            continue
        mid = 0.5 * (a + b)
        gm, dgm, zx, zv = gv(mid)
        cm = float(pc.curvature_bound(np.array([zx]), np.array([zv]), b - mid)[0])
        stack.append((mid, b, gm, dgm, cm, gb))
        stack.append((a, mid, ga, dga, ca, gm))
    return None


def _first_crossing_unforced(pc: _Piece, x0: float, v0: float, length: float, xtol: float
                             ) -> float | None:
    """``_first_crossing()`` without a transmission error: the motion about each contact
    state's equilibrium is a damped oscillation (or, in the gap, has one extremum at most), so
    samples a quarter damped period apart hold at most one extremum each; a sign change is
    closed by :func:`find_root`, an extremum below the boundary by the root of the velocity
    first. Kept for the unforced model: it needs fewer evaluations than the bounded search,
    and trajectories through chaotic transients depend on the roots' last bits."""
    if pc.stays_inside(x0, v0):
        return None
    n = max(2, math.ceil(length / pc.h)) if math.isfinite(pc.h) else 4
    s = np.linspace(0.0, length, n + 1)
    x, v = pc.at(x0, v0, s)
    best: float | None = None
    for level in pc.levels():
        inside = 1.0 if pc.state == DRIVE or (pc.state == GAP and level < 0) else -1.0
        g = (x - level) * inside  # >= 0 while in this state
        g[0] = abs(g[0])  # the piece starts on or inside the boundary
        hit = _bracket_unforced(pc, x0, v0, s, g, v * inside, level, inside, xtol)
        if hit is not None and (best is None or hit < best):
            best = hit
    return best


def _bracket_unforced(pc: _Piece, x0: float, v0: float, s: FloatArray, g: FloatArray,
                      dg: FloatArray, level: float, inside: float, xtol: float) -> float | None:
    """First zero of ``g`` (sampled on ``s``, slope ``dg``) by sign change or by extremum."""
    def gf(t: float) -> float:
        x = _flow(math, pc.state, pc.k, pc.m, pc.c, pc.w, pc.b, x0, v0, t)[0]
        return (x - level) * inside

    def dgf(t: float) -> float:
        return _flow(math, pc.state, pc.k, pc.m, pc.c, pc.w, pc.b, x0, v0, t)[1] * inside

    neg = np.flatnonzero(g[1:] < 0.0)
    turn = np.flatnonzero((dg[:-1] < 0.0) & (dg[1:] > 0.0))  # a minimum of g inside
    j_cross = int(neg[0]) if neg.size else None
    for j in turn:
        if j_cross is not None and j >= j_cross:
            break
        sm = find_root(dgf, float(s[j]), float(s[j + 1]), float(dg[j]), float(dg[j + 1]),
                       xtol)
        gm = gf(sm)
        if gm < 0.0:  # dips below the boundary and returns inside the interval
            return find_root(gf, float(s[j]), sm, float(g[j]), gm, xtol)
    if j_cross is None:
        return None
    lo, hi = float(s[j_cross]), float(s[j_cross + 1])
    return find_root(gf, lo, hi, float(g[j_cross]), float(g[j_cross + 1]), xtol)


def _state_at(x: float, v: float, b: float) -> int:
    if x > b or (x == b and v > 0):
        return DRIVE
    if x < -b or (x == -b and v < 0):
        return BACK
    return GAP


def _next_state(state: int, x: float, v: float, b: float) -> int:
    """Contact state entered at a located event (on a boundary, by the velocity's sign)."""
    if state == GAP:
        return DRIVE if v > 0 or x > 0 else BACK
    return GAP


class _Segment(NamedTuple):
    """One closed-form piece of a trajectory: a contact state between two changes."""

    t: float  #: start time (s)
    piece: _Piece
    x: float  #: state at the start (m, m/s)
    v: float
    s: float  #: duration (s)
    event: bool  #: ends at a contact change (else at a stiffness switch or the end time)


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
    event_times : ndarray
        Times of the located contact changes (s), in order.
    n_segments : int
        Closed-form pieces.
    """

    def __init__(self, model: Any, t0: float, t1: float, start: tuple[float, float],
                 segments: list[_Segment], end: tuple[float, float]) -> None:
        self.model, self.t0, self.t1 = model, t0, t1
        self.start = np.array(start)
        self._segs = segments
        self.end = np.array(end)
        self.event_times = np.array([sg.t + sg.s for sg in segments if sg.event])
        self.n_segments = len(segments)

    def sensitivity(self) -> FloatArray:
        """``d y(t1) / d y(t0)`` (entries dimensionless, s and 1/s): the product, in time
        order, of each piece's ``exp(A_j s_j)`` (``_Piece.transition``) and, at each
        contact change, the :func:`saltation` matrix of the surface ``x = +-b``: the identity
        where the field is continuous (the dead zone's ends; a field with a jump gets the
        general formula). A stiffness switch is a fixed instant, not a state surface: the
        sensitivity carries over unchanged.

        Raises
        ------
        SolverError
            Non-finite end state or sensitivity (a diverging response).
        """
        segs = self._segs
        mats = np.empty((len(segs), 2, 2))
        by_piece: dict[int, list[int]] = {}
        for i, sg in enumerate(segs):
            by_piece.setdefault(id(sg.piece), []).append(i)
        for idx in by_piece.values():
            mats[idx] = segs[idx[0]].piece.transition(np.array([segs[i].s for i in idx]))
        phi = np.eye(2)
        for i, sg in enumerate(segs):
            phi = mats[i] @ phi
            if sg.event:  # the next segment starts on the boundary, in the new contact state
                nxt = segs[i + 1]
                f_minus = sg.piece.field(nxt.x, nxt.v, nxt.t)
                f_plus = nxt.piece.field(nxt.x, nxt.v, nxt.t)
                if np.any(f_plus != f_minus):  # else S = I (the dead zone's ends): phi stays
                    phi = saltation(f_minus, f_plus, _CONTACT_NORMAL) @ phi
        if not (np.all(np.isfinite(self.end)) and np.all(np.isfinite(phi))):
            raise SolverError("exact_contact produced non-finite states: the response diverges")
        return phi

    def on_grid(self, t_grid: FloatArray) -> FloatArray:
        """States ``[x, v]`` (m, m/s), shape ``(2, len(t_grid))``, at times ``t_grid`` (s)
        within ``[t0, t1]``, each from the closed form of the piece it falls in.

        Raises
        ------
        SolverError
            Non-finite states (a diverging response).
        """
        t_grid = np.asarray(t_grid, dtype=float)
        starts = np.array([sg.t for sg in self._segs])
        out = _on_grid(t_grid, starts, [(sg.piece, sg.x, sg.v) for sg in self._segs])
        out += np.asarray(_te_shift(self.model, t_grid))  # back from u = x - e to x
        if not np.all(np.isfinite(out)):
            raise SolverError("exact_contact produced non-finite states: the response diverges")
        return out


def walk(model: Model, y0: FloatArray, t1: float, t0: float = 0.0) -> Walk:
    """The exact propagation of ``model`` from ``y(t0) = y0`` to ``t1``, kept as its pieces.

    :func:`propagate_contact_exact` and :func:`flow_with_sensitivity` are its states on a grid
    and its end state with :meth:`Walk.sensitivity`; a caller that needs both (a shooting
    point and its response measures) walks once. The pieces are in ``u = x - e(t)``, ``u'``,
    cut at the stiffness switches; within a stiffness piece each located contact change ends a
    segment, its state put exactly on the boundary it crossed, where the next state starts.

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

    Raises
    ------
    InputError
        The model is not of that kind.
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
    x0, v0 = (float(u) for u in y0)
    cuts = np.concatenate([[t0], mm.switching_times(t0, t1), [t1]])
    kts = mm.stiffness(mm.phase(0.5 * (cuts[:-1] + cuts[1:])))
    b = float(mm.backlash)
    xtol = 4 * float(np.spacing(max(abs(t0), abs(t1), 1e-300)))
    forcing = Forcing.of(mm)
    cache: dict[tuple[float, int], _Piece] = {}
    segs: list[_Segment] = []
    e0, ed0 = _te_shift(mm, np.array([t0]))
    x, v = x0 - float(e0[0]), v0 - float(ed0[0])
    state = _state_at(x, v, b)
    for ta, tb, kt in zip(cuts[:-1].tolist(), cuts[1:].tolist(), kts.tolist(), strict=True):
        t, n_ev = ta, 0
        while t < tb:
            pc = cache.get((kt, state)) or cache.setdefault((kt, state),
                                                            _Piece(mm, kt, state, forcing))
            hit = _first_crossing(pc, t, x, v, tb - t, xtol)
            if hit is None or t + hit >= tb:
                segs.append(_Segment(t, pc, x, v, tb - t, False))
                xs, vs = pc.at(x, v, np.array([tb - t]), t)
                x, v, t = float(xs[0]), float(vs[0]), tb
                break
            segs.append(_Segment(t, pc, x, v, hit, True))
            xs, vs = pc.at(x, v, np.array([hit]), t)
            x, v, t = float(xs[0]), float(vs[0]), t + hit
            x = b if abs(x - b) < abs(x + b) else -b  # exactly on the boundary it crossed
            state = _next_state(state, x, v, b)
            n_ev += 1
            if n_ev > MAX_EVENTS_PER_PIECE:
                raise SolverError(
                    f"exact_contact: more than {MAX_EVENTS_PER_PIECE} contact changes in one "
                    f"stiffness piece at t = {t:.6g} s (a chattering graze); use LSODA")
    e1, ed1 = _te_shift(mm, np.array([t1]))
    return Walk(model, t0, t1, (x0, v0), segs, (x + float(e1[0]), v + float(ed1[0])))


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


#: gradient of the contact switching functions ``x -+ b`` with respect to ``[x, v]``
_CONTACT_NORMAL = np.array([1.0, 0.0])


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


def _on_grid(t_grid: FloatArray, starts: FloatArray, rows: list[tuple[_Piece, float, float]]
             ) -> FloatArray:
    """``u, u'`` on ``t_grid``: each grid point's piece, evaluated piece group by piece group."""
    owner = np.clip(np.searchsorted(starts, t_grid, side="right") - 1, 0, len(rows) - 1)
    tau = t_grid - starts[owner]
    out = np.empty((2, t_grid.size))
    pcs = [r[0] for r in rows]
    ids = {id(p): p for p in pcs}
    pid = np.array([id(p) for p in pcs])[owner]
    z0 = np.empty(len(rows))
    zv0 = np.empty(len(rows))
    for i, (pc, u0, v0) in enumerate(rows):  # the state of z = u - u_p at each piece start
        z0[i], zv0[i] = pc._z(u0, v0, float(starts[i]))
    z0, zv0 = z0[owner], zv0[owner]
    for key, pc in ids.items():
        sel = np.flatnonzero(pid == key)
        if sel.size:
            zx, zv = _flow_many(pc, z0[sel], zv0[sel], tau[sel])
            pu, pv = pc.part.at(t_grid[sel])
            out[0, sel], out[1, sel] = zx + pu, zv + pv
    return out


def _flow_many(pc: _Piece, x0: FloatArray, v0: FloatArray, s: FloatArray
               ) -> tuple[FloatArray, FloatArray]:
    """:func:`flow` for many start states at once (the closed form is linear in them)."""
    xa, va = flow(pc.state, pc.k, pc.m, pc.c, pc.w, pc.b, 0.0, 0.0, s)  # affine part
    xx, vx = flow(pc.state, pc.k, pc.m, pc.c, 0.0, 0.0, 1.0, 0.0, s)  # response to x0
    xv, vv = flow(pc.state, pc.k, pc.m, pc.c, 0.0, 0.0, 0.0, 1.0, s)  # response to v0
    return xa + xx * x0 + xv * v0, va + vx * x0 + vv * v0


def rounding_bound(y: FloatArray, scale: FloatArray, n_segments: int) -> float:
    """Stated error of :func:`propagate_contact_exact`, relative to ``scale[0]``.

    Rounding of the closed form and of the carried state, ``eps`` per piece relative to the
    state magnitude, taken linear in the number of pieces with a safety factor of 1000 (the
    event times are located to 4 ulps; the dead zone is continuous, so an event-time error
    dt changes the state by O(k dt^2 / m) only): ``1000 eps (n_segments + 1) max|x| / scale``.
    """
    amp = float(np.max(np.abs(y[0]))) / float(scale[0])
    return float(1000 * np.finfo(float).eps * (n_segments + 1) * max(amp, 1.0))
