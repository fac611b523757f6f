"""Loaded contact of a spur pair with tip relief (Wang et al. 2024, eqs. 7-26).

At mesh phase ``p`` pair j sits at ``s_j = s_A + (p + j) p_bt`` from T1, with the unmodified
single-pair stiffness ``K_j = K(s_j)`` and the unloaded gap ``g_j`` the reliefs open. All pairs
share one approach ``delta`` (the loaded static transmission error), solved exactly from

    F_j = K_j max(0, delta - g_j),        sum_j F_j = F = T1 / r_b1.

From it: the secant mesh stiffness ``K_TPM = F / delta`` (eqs. 8-12), the load-sharing factors
``S_j = F_j / F`` (eqs. 17-26), and for dynamics (decision) the tangent stiffness ``k_t`` (sum of
``K_j`` over loaded pairs) with the relief's transmission error ``e = sum K_j g_j / k_t``.
Spur pairs only (helical pairs: :func:`~gear_dyn.modification.slice_contact`, which equals this
at helix angle 0).
docs/modification.md, "Loaded contact", gives the reasoning and the tests.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gear_dyn.errors import InputError, check_range
from gear_dyn.excitation import SampledSignal
from gear_dyn.geometry import GearPair, check_torque
from gear_dyn.modification.relief import ProfileModification
from gear_dyn.stiffness.periodic import PiecewiseStiffness, distinct_phases

FloatArray = NDArray[np.float64]
PairStiffnessFn = Callable[[FloatArray], FloatArray]

_NUDGE = 1e-9  # cycles: one-sided limits at switching phases


def _check_spur(pair: GearPair) -> None:
    if pair.helix_angle != 0.0:
        raise InputError(
            f"helix_angle = {math.degrees(pair.helix_angle):.6g} deg: this exact loaded contact "
            "is for spur pairs only (helix_angle = 0); use the slice loaded contact "
            "(gear_dyn.modification.slice_contact) for helical pairs"
        )


def _pair_count(pair: GearPair) -> int:
    return int(math.ceil(pair.contact_ratio)) + 1


@dataclass(frozen=True)
class ContactState:
    """Loaded contact at a set of mesh phases (arrays shaped (m,) or (m, n_pairs)).

    Attributes
    ----------
    phase : ndarray (m,)
        Mesh phase in cycles.
    position : ndarray (m, n)
        Contact position s_j of each pair in m from T1 (NaN when out of contact).
    stiffness : ndarray (m, n)
        Unmodified single-pair stiffness K_j in N/m (0 when out of contact).
    gap : ndarray (m, n)
        Unloaded gap g_j opened by the reliefs in m (inf when out of contact).
    force : ndarray (m, n)
        Pair load F_j in N.
    deflection : ndarray (m,)
        Common approach delta in m (the loaded static transmission error).
    """

    phase: FloatArray
    position: FloatArray
    stiffness: FloatArray
    gap: FloatArray
    force: FloatArray
    deflection: FloatArray

    @property
    def loaded(self) -> NDArray[np.bool_]:
        """Which pairs carry load (m, n)."""
        return self.force > 0.0

    @property
    def secant_stiffness(self) -> FloatArray:
        """K_TPM = F / delta in N/m."""
        return self.force.sum(axis=1) / self.deflection

    @property
    def tangent_stiffness(self) -> FloatArray:
        """Sum of K_j over the loaded pairs in N/m."""
        return np.where(self.loaded, self.stiffness, 0.0).sum(axis=1)

    @property
    def relief_error(self) -> FloatArray:
        """Transmission error the relief adds, e = sum K_j g_j / k_t over loaded pairs, in m."""
        kg = np.where(self.loaded, self.stiffness * np.where(self.loaded, self.gap, 0.0), 0.0)
        return kg.sum(axis=1) / self.tangent_stiffness

    @property
    def geometric_stiffness(self) -> FloatArray:
        """Unmodified mesh stiffness: sum of K_j over all pairs in geometric contact, N/m."""
        return self.stiffness.sum(axis=1)

    @property
    def sharing(self) -> FloatArray:
        """Load-sharing factor S_j = F_j / F of each pair (m, n)."""
        return self.force / self.force.sum(axis=1, keepdims=True)


def contact_state(
    pair: GearPair,
    pair_stiffness: PairStiffnessFn,
    load: float,
    phase: ArrayLike,
    modification: ProfileModification | None = None,
) -> ContactState:
    """Solve the loaded contact at given mesh phases.

    Parameters
    ----------
    pair : GearPair
        Spur pair.
    pair_stiffness : callable
        ``K(s)``: unmodified single-pair stiffness in N/m at contact position ``s`` (m from T1
        along the line of action), vectorised.
    load : float
        Total normal load along the line of action in N (> 0), ``T1 / r_b1``.
    phase : array_like
        Mesh phases in cycles.
    modification : ProfileModification or None
        Tip reliefs; None for unmodified teeth.

    Returns
    -------
    ContactState

    Raises
    ------
    InputError
        Helical pair, load not positive, a stiffness that is not finite and positive, a relief
        longer than the tooth allows.
    """
    _check_spur(pair)
    check_range("load", load, "N", low=0.0, high=1e9, low_open=True)
    if modification is not None:
        modification.check(pair)
    p = np.mod(np.atleast_1d(np.asarray(phase, dtype=float)), 1.0)
    n = _pair_count(pair)
    s_a, s_e, pb = pair.start_of_contact, pair.end_of_contact, pair.base_pitch
    s = s_a + (p[:, None] + np.arange(n)[None, :]) * pb
    inside = s <= s_e + 1e-12 * pb
    s_eval = np.where(inside, s, s_e)
    k = np.asarray(pair_stiffness(s_eval), dtype=float) * np.ones_like(s_eval)
    if not np.all(np.isfinite(k[inside]) & (k[inside] > 0)):
        bad = k[inside][~(np.isfinite(k[inside]) & (k[inside] > 0))][0]
        raise InputError(f"single-pair stiffness = {bad:.6g} N/m: valid range > 0 N/m")
    if modification is None or modification.is_zero:
        g = np.zeros_like(s_eval)
    else:
        g = modification.separation(pair, s_eval)
    k = np.where(inside, k, 0.0)
    g = np.where(inside, g, np.inf)
    delta = _solve_approach(k, g, load)
    force = np.where(inside, k * np.maximum(delta[:, None] - g, 0.0), 0.0)
    # rescale to remove rounding so the loads sum to F exactly (relative change ~1e-16)
    force *= load / force.sum(axis=1, keepdims=True)
    return ContactState(p, np.where(inside, s, np.nan), k, g, force, delta)


def _solve_approach(k: FloatArray, g: FloatArray, load: float) -> FloatArray:
    """delta with sum_j k_j max(0, delta - g_j) = load, row by row (g = inf: not in contact)."""
    order = np.argsort(g, axis=1)
    gs = np.take_along_axis(g, order, axis=1)
    ks = np.take_along_axis(k, order, axis=1)
    finite = np.isfinite(gs)
    cum_k = np.cumsum(np.where(finite, ks, 0.0), axis=1)
    cum_kg = np.cumsum(np.where(finite, ks * np.where(finite, gs, 0.0), 0.0), axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        cand = (load + cum_kg) / cum_k
    g_next = np.concatenate([gs[:, 1:], np.full((gs.shape[0], 1), np.inf)], axis=1)
    tol = 1e-12 * np.maximum(np.abs(cand), 1e-12)
    valid = finite & (cand >= gs - tol) & (cand <= g_next + tol)
    first = np.argmax(valid, axis=1)
    return cand[np.arange(cand.shape[0]), first]


@dataclass(frozen=True, eq=False)
class LoadedContact:
    """Loaded contact over one mesh cycle and along the path of contact.

    Build it with :func:`loaded_contact`.

    Attributes
    ----------
    pair : GearPair
    load : float
        Normal load F in N.
    modification : ProfileModification or None
    edges : ndarray
        Switching phases plus 1: geometric entry/exit and the loaded pick-up/shed points.
    cycle : ContactState
        Solution at the sample phases (segment by segment, one-sided at the edges).
    segment : ndarray of int
        Segment index of each sample of ``cycle``.
    """

    pair: GearPair
    load: float
    modification: ProfileModification | None
    pair_stiffness: PairStiffnessFn = field(repr=False)
    edges: FloatArray = field(repr=False)
    cycle: ContactState = field(repr=False)
    segment: NDArray[np.int_] = field(repr=False)

    # ------------------------------------------------------------------ over one mesh cycle
    def _piecewise(self, values: FloatArray, name: str) -> PiecewiseStiffness:
        samples = _segment_samples(self.edges, self.segment, self.cycle.phase, values)
        return PiecewiseStiffness(self.edges, tuple(samples), name=name)

    def mesh_stiffness(self) -> PiecewiseStiffness:
        """Load-dependent mesh stiffness K_TPM = F / delta (Wang et al. 2024, eq. 12), N/m."""
        return self._piecewise(self.cycle.secant_stiffness, "loaded K_TPM (secant)")

    def tangent_stiffness(self) -> PiecewiseStiffness:
        """Sum of the loaded pairs' stiffnesses, N/m (the stiffness for dynamics)."""
        return self._piecewise(self.cycle.tangent_stiffness, "loaded (tangent)")

    def unmodified_stiffness(self) -> PiecewiseStiffness:
        """Mesh stiffness of the unmodified pair (all pairs in geometric contact), N/m."""
        return self._piecewise(self.cycle.geometric_stiffness, "unmodified")

    def transmission_error(self) -> PiecewiseSignal:
        """Transmission error e(p) the relief adds (m), to pair with :meth:`tangent_stiffness`."""
        return self._signal(self.cycle.relief_error)

    def static_transmission_error(self) -> PiecewiseSignal:
        """Loaded static transmission error delta(p) = F / k_t + e (m)."""
        return self._signal(self.cycle.deflection)

    def _signal(self, values: FloatArray) -> PiecewiseSignal:
        return PiecewiseSignal.from_segments(self.edges, self.segment, self.cycle.phase, values)

    @property
    def peak_to_peak_error(self) -> float:
        """Peak-to-peak loaded static transmission error over a cycle in m."""
        return float(np.ptp(self.cycle.deflection))

    # ------------------------------------------------------------------ along the path
    def along_path(self, n: int = 801) -> PathView:
        """Load sharing, pair load and positions of one tooth pair travelling from A to E.

        Parameters
        ----------
        n : int
            Number of uniform positions (the switching positions are added, one-sided).
        """
        pair = self.pair
        s_a, s_e, pb = pair.start_of_contact, pair.end_of_contact, pair.base_pitch
        nn = _pair_count(pair)
        sw = self.edges[:-1]
        extra = (sw[:, None] + np.arange(nn)[None, :]).ravel() * pb + s_a
        extra = extra[(extra >= s_a) & (extra <= s_e)]
        d = _NUDGE * pb
        s = np.unique(np.clip(np.concatenate([np.linspace(s_a, s_e, n), extra - d, extra + d,
                                              [s_a, s_e]]), s_a, s_e))
        u = (s - s_a) / pb
        j = np.minimum(np.floor(u).astype(int), nn - 1)
        ph = u - j
        st = contact_state(pair, self.pair_stiffness, self.load, ph, self.modification)
        rows = np.arange(s.size)
        force = st.force[rows, j]
        return PathView(s, force, force / self.load, st.stiffness[rows, j])

    def single_contact_zone(self) -> tuple[float, float] | None:
        """Start and end (m from T1) of the zone where one pair carries the whole load.

        None if the pair never runs in single contact.
        """
        view = self.along_path(401)
        single = view.sharing >= 1.0 - 1e-9
        if not np.any(single):
            return None
        return float(view.position[single].min()), float(view.position[single].max())


def _segment_samples(edges: FloatArray, segment: NDArray[np.int_], phase: FloatArray,
                     values: FloatArray) -> list[tuple[FloatArray, FloatArray]]:
    """(phases, values) of each segment, its first and last phase moved onto its edges."""
    out = []
    for i in range(edges.size - 1):
        sel = segment == i
        ph = phase[sel].copy()
        ph[0], ph[-1] = edges[i], edges[i + 1]
        out.append((ph, np.asarray(values[sel], dtype=float)))
    return out


@dataclass(frozen=True)
class PathView:
    """Quantities of one tooth pair as its contact point travels from A to E.

    Attributes
    ----------
    position : ndarray
        Contact position s in m from T1.
    force : ndarray
        Pair load in N.
    sharing : ndarray
        Load-sharing factor F_pair / F.
    pair_stiffness : ndarray
        Unmodified single-pair stiffness in N/m.
    """

    position: FloatArray
    force: FloatArray
    sharing: FloatArray
    pair_stiffness: FloatArray


#: how close (in a piece's normalised phase) to a sample a phase counts as at it: well above
#: the rounding of a phase f_m t mod 1 after thousands of mesh cycles (~1e-13), well below any
#: sample spacing (>= 1e-9)
NODE_TOL = 1e-11


@dataclass(frozen=True, eq=False)
class PiecewiseSignal(SampledSignal):
    """A :class:`.SampledSignal` that may jump at given phases.

    ``value`` interpolates within each segment; ``slope`` is the piecewise slope (a jump carries
    no slope). Build with :meth:`from_segments`.
    """

    edges: FloatArray = field(default_factory=lambda: np.array([0.0, 1.0]))
    seg_phase: tuple[FloatArray, ...] = ()
    seg_values: tuple[FloatArray, ...] = ()
    _u: FloatArray = field(init=False, repr=False)
    _v: FloatArray = field(init=False, repr=False)
    _slope: FloatArray = field(init=False, repr=False)
    #: edges, u, values and slopes as plain lists (the scalar path)
    _lists: tuple[list[float], ...] = field(init=False, repr=False)
    _last: list[float] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        super().__post_init__()
        e = np.asarray(self.edges, dtype=float)
        if len(self.seg_phase) != e.size - 1 or len(self.seg_values) != e.size - 1:
            raise InputError("piecewise signal: one sample set per segment is needed")
        us = [2 * i + (ph - e[i]) / (e[i + 1] - e[i]) for i, ph in enumerate(self.seg_phase)]
        ss = [np.append(np.diff(v) / np.diff(ph), 0.0)
              for ph, v in zip(self.seg_phase, self.seg_values, strict=True)]
        object.__setattr__(self, "_u", np.concatenate(us))
        object.__setattr__(self, "_v", np.concatenate(self.seg_values))
        object.__setattr__(self, "_slope", np.concatenate(ss))
        object.__setattr__(self, "_lists", tuple(a.tolist() for a in (e, self._u, self._v,
                                                                        self._slope)))
        object.__setattr__(self, "_last", [math.nan, 0.0, 0.0])

    @classmethod
    def from_segments(cls, edges: FloatArray, segment: NDArray[np.int_], phase: FloatArray,
                      values: FloatArray) -> PiecewiseSignal:
        """Build from samples tagged with their segment (samples span each segment)."""
        sp, sv = zip(*_segment_samples(edges, segment, phase, values), strict=True)
        allp = np.concatenate([p[:-1] for p in sp])
        allv = np.concatenate([v[:-1] for v in sv])
        keep = np.concatenate([[True], np.diff(allp) > 0])
        return cls(allp[keep], allv[keep], edges=np.asarray(edges, dtype=float),
                   seg_phase=tuple(sp), seg_values=tuple(sv))

    def _u_of(self, phase: ArrayLike) -> FloatArray:
        e = self.edges
        p = np.mod(np.asarray(phase, dtype=float), 1.0)
        idx = np.minimum(np.maximum(np.searchsorted(e, p, side="right") - 1, 0), e.size - 2)
        return 2 * idx + (p - e[idx]) / (e[idx + 1] - e[idx])

    def _scalar(self, phase: float) -> tuple[float, float]:
        """(value, slope) at one phase, without array overhead (the solver's hot path; the
        last phase is remembered because a model asks for value and slope at the same phase)."""
        last = self._last
        if phase == last[0]:
            return last[1], last[2]
        e, us, v, slopes = self._lists
        p = phase % 1.0
        i = min(max(bisect.bisect_right(e, p) - 1, 0), len(e) - 2)
        u = 2 * i + (p - e[i]) / (e[i + 1] - e[i])
        # a phase within rounding of a sample belongs to the piece that starts there (the
        # slope is right-continuous there, whichever side a time's rounding puts its phase)
        k = min(max(bisect.bisect_right(us, u + NODE_TOL) - 1, 0), len(us) - 2)
        if us[k + 1] > us[k]:
            val = v[k] + (v[k + 1] - v[k]) * (u - us[k]) / (us[k + 1] - us[k])
        else:
            val = v[k]
        last[0], last[1], last[2] = phase, val, slopes[k]
        return val, last[2]

    def value(self, phase: ArrayLike) -> FloatArray:
        """e(p) at mesh phase ``phase`` (right-continuous at jumps)."""
        if isinstance(phase, float | int):
            return self._scalar(float(phase))[0]
        return np.interp(self._u_of(phase), self._u, self._v)

    def slope(self, phase: ArrayLike) -> FloatArray:
        """de/dp, piecewise, in unit per cycle."""
        if isinstance(phase, float | int):
            return self._scalar(float(phase))[1]
        u = self._u_of(phase)
        k = np.minimum(np.maximum(np.searchsorted(self._u, u + NODE_TOL, side="right") - 1, 0),
                       self._u.size - 1)
        return self._slope[k]

    @property
    def jumps(self) -> FloatArray:
        """Phases in [0, 1) where the signal may jump."""
        return self.edges[:-1].copy()


def _loaded_switches(pair: GearPair, fn: PairStiffnessFn, load: float,
                     mod: ProfileModification | None, geo_edges: FloatArray,
                     grid: int) -> list[float]:
    """Phases where a pair picks up or sheds load: roots of delta(p) - g_j(p)."""
    if mod is None or mod.is_zero:
        return []
    from scipy.optimize import brentq  # on use: scipy.optimize costs ~0.25 s to import

    roots: list[float] = []
    n = _pair_count(pair)
    for a, b in zip(geo_edges[:-1], geo_edges[1:], strict=True):
        lo, hi = a + _NUDGE, b - _NUDGE
        if hi <= lo:
            continue
        ph = np.linspace(lo, hi, grid)
        st = contact_state(pair, fn, load, ph, mod)
        h = st.deflection[:, None] - st.gap
        for j in range(n):
            hj = h[:, j]
            ok = np.isfinite(hj)
            sign = np.sign(hj)
            change = np.nonzero(ok[:-1] & ok[1:] & (sign[:-1] * sign[1:] < 0))[0]
            for c in change:
                def f(x: float, jj: int = j) -> float:
                    s1 = contact_state(pair, fn, load, np.array([x]), mod)
                    return float(s1.deflection[0] - s1.gap[0, jj])
                roots.append(float(brentq(f, ph[c], ph[c + 1], xtol=1e-13, rtol=1e-12)))
    return roots


def loaded_contact(
    pair: GearPair,
    pair_stiffness: PairStiffnessFn,
    torque: float,
    modification: ProfileModification | None = None,
    samples_per_segment: int = 48,
) -> LoadedContact:
    """Loaded contact analysis of a spur pair with tip relief over one mesh cycle.

    Parameters
    ----------
    pair : GearPair
        Spur pair.
    pair_stiffness : callable
        ``K(s)``: unmodified single-pair stiffness in N/m at contact position ``s`` in m from T1
        (e.g. the potential-energy or Weber method), vectorised.
    torque : float
        Pinion torque T1 in N m (> 0); the normal load is ``F = T1 / r_b1``.
    modification : ProfileModification or None
        Tip reliefs; None for unmodified teeth.
    samples_per_segment : int
        Samples in each segment between switching phases (>= 2, <= 10000).

    Returns
    -------
    LoadedContact

    Raises
    ------
    InputError
        Helical pair, torque not positive, bad stiffness values, relief too long.

    Examples
    --------
    >>> import math
    >>> from gear_dyn.geometry import GearPair
    >>> p = GearPair(23, 64, 6e-3, math.radians(22.5), 50e-3)
    >>> lc = loaded_contact(p, lambda s: 3e8 + 0 * s, 1474.4)
    >>> round(lc.mesh_stiffness().max / 3e8, 6)   # two pairs in the double-contact zone
    2.0
    """
    _check_spur(pair)
    check_torque(torque, positive=True)
    check_range("samples_per_segment", samples_per_segment, "", low=2, high=10000)
    load = torque / pair.rb1
    eps = pair.contact_ratio
    geo = np.unique(np.mod(np.array([0.0, eps - math.floor(eps)]), 1.0))
    geo_edges = np.concatenate([geo, [1.0]])
    roots = _loaded_switches(pair, pair_stiffness, load, modification, geo_edges, 512)
    # switching phases closer than a few nudges (tangencies, duplicates) count once
    edges = np.append(distinct_phases(np.concatenate([geo, roots]), 10 * _NUDGE), 1.0)
    m = int(samples_per_segment)
    ph = np.linspace(edges[:-1], edges[1:], m, axis=1)  # (segments, m)
    nudge = _NUDGE * np.minimum(1.0, np.diff(edges) * 1e3)
    ph[:, 0] += nudge
    ph[:, -1] -= nudge
    # contact_state wraps phases into [0, 1); keep the unwrapped sample phases
    st = replace(contact_state(pair, pair_stiffness, load, ph.ravel(), modification),
                 phase=ph.ravel())
    return LoadedContact(pair, load, modification, pair_stiffness, edges, st,
                         np.repeat(np.arange(edges.size - 1), m))
