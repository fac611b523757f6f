"""The one periodic mesh-stiffness type that every stiffness method returns.

Stiffness is a function of the *mesh phase* ``p`` in mesh cycles (one cycle = one base pitch of
roll = one mesh period ``1/f_m``); phase 0 is the instant a new tooth pair enters contact, and a
model maps time to phase with ``p = f_m t + p0``. Two forms: :class:`PiecewiseStiffness`
(piecewise linear, jumps allowed at the switching phases; the rectangular wave has constant
pieces) and :class:`FourierStiffness` (``k0 + sum a_n cos(2 pi n p) + b_n sin(2 pi n p)``,
Jiang et al. 2018, eq. 13, its printed second ``cos`` read as ``sin``).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from bisect import bisect_right
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gear_dyn.errors import InputError, check_range

FloatArray = NDArray[np.float64]


class PeriodicStiffness(ABC):
    """Mesh stiffness k(p) in N/m, periodic in the mesh phase p (cycles) with period 1.

    The abstract base of every stiffness method: call it with phases (cycles) to get N/m.

    Attributes
    ----------
    name : str
        The method, reported in summaries.
    mean : float
        Mean stiffness k_m over one mesh cycle in N/m.
    min, max : float
        Least and largest stiffness over a cycle in N/m.
    switching_phases : ndarray
        Phases in [0, 1) where k jumps.

    See Also
    --------
    :class:`~gear_dyn.stiffness.periodic.PiecewiseStiffness` : Piecewise-linear with jumps.
    :class:`~gear_dyn.stiffness.periodic.FourierStiffness` : A truncated Fourier series.
    :func:`~gear_dyn.stiffness.select.build_stiffness` : The stiffness of a gear pair by any method.

    Examples
    --------
    >>> from gear_dyn import rectangular_stiffness
    >>> k = rectangular_stiffness(1.6, 1e8, 1.5e8)
    >>> isinstance(k, PeriodicStiffness)
    True
    >>> k([0.1, 0.7])  # two pairs, then one pair in contact (N/m)
    array([1.5e+08, 1.0e+08])
    >>> k.mean  # 0.6 * 1.5e8 + 0.4 * 1e8 (N/m)
    130000000.0
    """

    name: str

    @abstractmethod
    def __call__(self, phase: ArrayLike) -> FloatArray:
        """Stiffness in N/m at mesh phase ``phase`` (cycles, any real value)."""

    @property
    @abstractmethod
    def switching_phases(self) -> FloatArray:
        """Phases in [0, 1) where k jumps (teeth enter or leave contact); empty if smooth."""

    @abstractmethod
    def fourier_coefficients(self, n: int) -> tuple[float, FloatArray, FloatArray]:
        """Return ``(k0, a, b)``: mean and cosine/sine coefficients for harmonics 1..n in N/m.

        Parameters
        ----------
        n : int
            Number of harmonics (>= 0).

        Returns
        -------
        k0 : float
            Mean stiffness in N/m.
        a, b : ndarray
            Cosine and sine coefficients of harmonics 1..n in N/m, each of length n.

        See Also
        --------
        :meth:`~gear_dyn.stiffness.periodic.PeriodicStiffness.truncated`
            The series as a stiffness.

        Examples
        --------
        >>> from gear_dyn import rectangular_stiffness
        >>> k0, a, b = rectangular_stiffness(1.6, 1e8, 1.5e8).fourier_coefficients(2)
        >>> k0, a.shape
        (130000000.0, (2,))
        """

    def segments(self) -> tuple[FloatArray, FloatArray] | None:
        """``(edges, values)`` if k is piecewise constant over one cycle, else None.

        ``edges`` has length S+1 from 0 to 1, ``values`` length S.

        Returns
        -------
        (ndarray, ndarray) or None
            Segment edges in cycles and the stiffness of each segment in N/m; None where k is
            not piecewise constant.

        See Also
        --------
        :attr:`~gear_dyn.stiffness.periodic.PeriodicStiffness.switching_phases` : Where k jumps.

        Examples
        --------
        >>> from gear_dyn import rectangular_stiffness
        >>> rectangular_stiffness(1.6, 1e8, 1.5e8).segments()
        (array([0. , 0.6, 1. ]), array([1.5e+08, 1.0e+08]))
        """
        return None

    @cached_property
    def mean(self) -> float:
        """Mean stiffness k_m over one mesh cycle in N/m (computed once per object: the
        stiffness objects are immutable, and a sweep asks for it thousands of times)."""
        return float(self.fourier_coefficients(0)[0])

    def _dense(self) -> FloatArray:
        p = np.linspace(0.0, 1.0, 4097)
        extra = np.concatenate([self.switching_phases, self.switching_phases - 1e-12])
        return np.asarray(self(np.concatenate([p, np.mod(extra, 1.0)])))

    @property
    def min(self) -> float:
        """Minimum stiffness over a cycle in N/m."""
        return float(np.min(self._dense()))

    @property
    def max(self) -> float:
        """Maximum stiffness over a cycle in N/m."""
        return float(np.max(self._dense()))

    def truncated(self, n: int) -> FourierStiffness:
        """The Fourier series of this stiffness truncated at ``n`` harmonics (1..MAX_TERMS).

        Parameters
        ----------
        n : int
            Harmonics kept, 1..10000 (``MAX_FOURIER_TERMS``).

        Returns
        -------
        FourierStiffness
            Same mean; named after this stiffness.

        Raises
        ------
        InputError
            ``n`` not a whole number in range.

        See Also
        --------
        :meth:`~gear_dyn.stiffness.periodic.PeriodicStiffness.fourier_coefficients`
            The coefficients.

        Examples
        --------
        >>> from gear_dyn import rectangular_stiffness
        >>> f = rectangular_stiffness(1.6, 1e8, 1.5e8).truncated(2)
        >>> f.name, f.mean
        ('rectangular (Fourier, 2 terms)', 130000000.0)
        """
        if isinstance(n, bool) or not isinstance(n, int | np.integer):
            raise InputError(f"fourier_terms = {n!r}: expected a whole number of harmonics")
        check_range("fourier_terms", n, "harmonics", low=1, high=MAX_FOURIER_TERMS)
        k0, a, b = self.fourier_coefficients(int(n))
        return FourierStiffness(k0, a, b, name=f"{self.name} (Fourier, {n} terms)")

    def switching_times(self, t0: float, t1: float, mesh_frequency: float,
                        phase0: float = 0.0) -> FloatArray:
        """Times in the open interval (t0, t1) at which k jumps, for ``p = f_m t + phase0``.

        Parameters
        ----------
        t0, t1 : float
            The interval in s.
        mesh_frequency : float
            f_m in Hz.
        phase0 : float
            Mesh phase at t = 0 in cycles.

        Returns
        -------
        ndarray
            Sorted switching times in s (empty for a smooth stiffness).

        See Also
        --------
        :attr:`~gear_dyn.stiffness.periodic.PeriodicStiffness.switching_phases`
            The same in mesh phase.

        Examples
        --------
        >>> from gear_dyn import rectangular_stiffness
        >>> k = rectangular_stiffness(1.6, 1e8, 1.5e8)
        >>> k.switching_times(0.0, 0.01, 200.0)  # jumps at p = 0.6, 1, 1.6 (s)
        array([0.003, 0.005, 0.008])
        """
        sw = self.switching_phases
        if sw.size == 0 or t1 <= t0:
            return np.empty(0)
        p0 = mesh_frequency * t0 + phase0
        p1 = mesh_frequency * t1 + phase0
        c0 = math.floor(p0)
        c1 = math.floor(p1)
        cycles = np.arange(c0, c1 + 1, dtype=float)
        ph = (cycles[:, None] + sw[None, :]).ravel()
        ph = ph[(ph > p0) & (ph < p1)]
        t = (ph - phase0) / mesh_frequency
        # guard against rounding putting an instant on an end point
        tol = 1e-12 * max(abs(t0), abs(t1), 1.0 / mesh_frequency)
        return np.sort(t[(t > t0 + tol) & (t < t1 - tol)])


def distinct_phases(phases: ArrayLike, tol: float) -> FloatArray:
    """``phases`` reduced to [0, 1) and sorted, one of each run closer than ``tol`` (cycles);
    a phase within ``tol`` below 1 is the phase 0 of the next cycle."""
    p = np.sort(np.mod(np.asarray(phases, dtype=float), 1.0))
    p = p[np.concatenate([[True], np.diff(p) > tol])]
    return p[:-1] if p.size > 1 and p[-1] > 1.0 - tol else p


#: most harmonics a truncated series may keep (the scene allows 200)
MAX_FOURIER_TERMS = 10_000


def _check_k(name: str, values: FloatArray) -> None:
    if not np.all(np.isfinite(values)) or np.any(values < 0):
        bad = values[~np.isfinite(values) | (values < 0)][0]
        raise InputError(f"{name}: stiffness value {bad:.6g} N/m is invalid; valid range >= 0 N/m")


@dataclass(frozen=True, eq=False)
class PiecewiseStiffness(PeriodicStiffness):
    """Piecewise-linear periodic stiffness with jumps at the switching phases.

    Parameters
    ----------
    edges : array_like
        Segment edges in mesh cycles, strictly increasing from 0 to 1 (length S+1). Every interior
        edge is a switching phase (a possible jump); phase 0 is one as well.
    samples : sequence of (phase, value) array pairs
        For each of the S segments, sample phases (spanning exactly the segment, increasing) and
        stiffness values in N/m. Constant segments need only their two end points.
    name : str
        Method name, reported in summaries.

    Raises
    ------
    InputError
        Non-increasing edges, samples outside their segment, negative or non-finite values.

    See Also
    --------
    :func:`~gear_dyn.stiffness.periodic.rectangular_stiffness`
        The rectangular wave from the contact ratio.
    :class:`~gear_dyn.stiffness.periodic.PeriodicStiffness` : The common face of every stiffness.

    Examples
    --------
    >>> import numpy as np
    >>> k = PiecewiseStiffness(np.array([0.0, 0.5, 1.0]),
    ...                        ((np.array([0.0, 0.5]), np.array([2e8, 2e8])),
    ...                         (np.array([0.5, 1.0]), np.array([1e8, 2e8]))))
    >>> float(k(0.75))  # halfway up the ramp of the second segment (N/m)
    150000000.0
    >>> k.switching_phases
    array([0. , 0.5])
    """

    edges: FloatArray
    samples: tuple[tuple[FloatArray, FloatArray], ...]
    name: str = "piecewise"
    _u: FloatArray = field(init=False, repr=False)
    _v: FloatArray = field(init=False, repr=False)
    _lists: tuple[list[float], list[float], list[float]] = field(init=False, repr=False)
    _levels: FloatArray | None = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        try:
            e = np.asarray(self.edges, dtype=float)
            samples = [(np.asarray(ph, dtype=float), np.asarray(val, dtype=float))
                       for ph, val in self.samples]
        except (TypeError, ValueError):
            raise InputError(f"{self.name}: edges must be numbers and samples (phases, values "
                             "in N/m) pairs of number lists") from None
        if e.ndim != 1 or e.size < 2 or not np.all(np.isfinite(e)) or e[0] != 0.0 or (
                e[-1] != 1.0 or np.any(np.diff(e) <= 0)):
            raise InputError(f"{self.name}: segment edges must rise strictly from 0 to 1, got {e}")
        if len(samples) != e.size - 1:
            raise InputError(
                f"{self.name}: {len(samples)} sample sets for {e.size - 1} segments"
            )
        us, vs = [], []
        for i, (ph, val) in enumerate(samples):
            if ph.shape != val.shape or ph.ndim != 1 or ph.size < 2 or not np.all(
                    np.isfinite(ph)):
                raise InputError(f"{self.name}: segment {i} needs >= 2 finite samples of equal "
                                 "length")
            _check_k(self.name, val)
            width = e[i + 1] - e[i]
            u = (ph - e[i]) / width
            if abs(u[0]) > 1e-9 or abs(u[-1] - 1) > 1e-9 or np.any(np.diff(u) <= 0):
                raise InputError(f"{self.name}: samples of segment {i} must span it increasingly")
            u = np.clip(u, 0.0, 1.0)
            us.append(2 * i + u)
            vs.append(val)
        object.__setattr__(self, "edges", e)
        object.__setattr__(self, "_u", np.concatenate(us))
        object.__setattr__(self, "_v", np.concatenate(vs))
        # plain lists for the scalar fast path of __call__ (the solver's right-hand side)
        object.__setattr__(self, "_lists", (e.tolist(), self._u.tolist(), self._v.tolist()))
        # every segment constant (a rectangular wave): the array path looks the level up, the
        # same value np.interp gives between equal samples, in a third of the time
        const = all(np.ptp(val) == 0 for val in vs)
        object.__setattr__(self, "_levels",
                           np.array([float(val[0]) for val in vs]) if const else None)

    @property
    def switching_phases(self) -> FloatArray:
        return self.edges[:-1].copy()

    def __call__(self, phase: ArrayLike) -> FloatArray:
        if isinstance(phase, float | int) and not isinstance(phase, bool):
            return np.float64(self._scalar(float(phase)))
        p = np.mod(np.asarray(phase, dtype=float), 1.0)
        e = self.edges
        idx = np.clip(np.searchsorted(e, p, side="right") - 1, 0, e.size - 2)
        if self._levels is not None:
            k = self._levels[idx]
            k[np.isnan(p)] = np.nan  # nan propagates as through np.interp
            return k
        u = 2 * idx + (p - e[idx]) / (e[idx + 1] - e[idx])
        return np.interp(u, self._u, self._v)

    def _scalar(self, phase: float) -> float:
        """Same value as the array path (np.searchsorted + np.interp), in plain Python (~1 us)."""
        e, u_list, v_list = self._lists
        p = phase % 1.0
        if p != p:  # nan propagates like np.interp
            return p
        i = min(max(bisect_right(e, p) - 1, 0), len(e) - 2)
        u = 2 * i + (p - e[i]) / (e[i + 1] - e[i])
        j = bisect_right(u_list, u) - 1
        if j < 0:
            return v_list[0]
        if j >= len(u_list) - 1:
            return v_list[-1]
        u0, u1 = u_list[j], u_list[j + 1]
        return v_list[j] + (v_list[j + 1] - v_list[j]) * (u - u0) / (u1 - u0)

    def segments(self) -> tuple[FloatArray, FloatArray] | None:
        if self._levels is None:
            return None
        return self.edges.copy(), self._levels.copy()

    def fourier_coefficients(self, n: int) -> tuple[float, FloatArray, FloatArray]:
        e = self.edges
        # linear pieces in absolute phase: from (p0, v0) to (p1, v1)
        ph = [np.clip(np.asarray(p, dtype=float), e[i], e[i + 1])
              for i, (p, _v) in enumerate(self.samples)]
        v = [np.asarray(v, dtype=float) for _p, v in self.samples]
        p0, p1 = np.concatenate([q[:-1] for q in ph]), np.concatenate([q[1:] for q in ph])
        v0, v1 = np.concatenate([q[:-1] for q in v]), np.concatenate([q[1:] for q in v])
        w = p1 - p0
        keep = w > 0
        p0, p1, v0, v1, w = p0[keep], p1[keep], v0[keep], v1[keep], w[keep]
        k0 = float(np.sum(0.5 * (v0 + v1) * w))
        if n <= 0:
            return k0, np.empty(0), np.empty(0)
        s = (v1 - v0) / w
        om = 2 * np.pi * np.arange(1, n + 1)[:, None]

        def prim(p: FloatArray, v: FloatArray) -> NDArray[np.complex128]:
            ex = np.exp(-1j * om * p[None, :])
            return v[None, :] * ex / (-1j * om) + s[None, :] * ex / om**2

        c = np.sum(prim(p1, v1) - prim(p0, v0), axis=1)
        return k0, 2 * c.real, -2 * c.imag


@dataclass(frozen=True, eq=False)
class FourierStiffness(PeriodicStiffness):
    """Truncated Fourier series stiffness ``k0 + sum_n a_n cos(2 pi n p) + b_n sin(2 pi n p)``.

    Parameters
    ----------
    k0 : float
        Mean stiffness in N/m.
    a, b : array_like
        Cosine and sine coefficients for harmonics 1..N in N/m.
    name : str
        Method name for reports.

    See Also
    --------
    :meth:`~gear_dyn.stiffness.periodic.PeriodicStiffness.truncated` : The series of any stiffness.
    :class:`~gear_dyn.stiffness.periodic.PiecewiseStiffness` : Stiffness with jumps.

    Examples
    --------
    >>> k = FourierStiffness(1e8, [1e7], [0.0])
    >>> float(k(0.0)), float(k(0.5))  # N/m
    (110000000.0, 90000000.0)
    >>> k.min, k.max
    (90000000.0, 110000000.0)
    """

    k0: float
    a: FloatArray
    b: FloatArray
    name: str = "fourier"

    def __post_init__(self) -> None:
        try:
            a = np.atleast_1d(np.asarray(self.a, dtype=float))
            b = np.atleast_1d(np.asarray(self.b, dtype=float))
        except (TypeError, ValueError):
            raise InputError(f"{self.name}: a and b must be lists of numbers in N/m") from None
        if a.shape != b.shape or a.ndim != 1:
            raise InputError(f"{self.name}: a and b must have the same length")
        if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
            raise InputError(f"{self.name}: harmonic amplitudes must be finite numbers in N/m")
        object.__setattr__(self, "a", a)
        object.__setattr__(self, "b", b)
        check_range(f"{self.name}: mean stiffness", self.k0, "N/m", low=0.0, low_open=True)

    @property
    def switching_phases(self) -> FloatArray:
        return np.empty(0)

    def _powers(self, phase: ArrayLike) -> FloatArray:
        """``exp(2 pi i n p)`` for n = 1..N, shape ``phase.shape + (N,)``: one complex
        exponential per phase (of the phase reduced to [0, 1)) and its powers by a cumulative
        product, N times cheaper than N cosines and sines; the product's rounding grows like
        n ulps (5e-15 relative at N = 50), far below any solver tolerance."""
        p = np.asarray(phase, dtype=float)
        z = np.exp(2j * np.pi * (p - np.floor(p)))
        shape = (*p.shape, self.a.size)
        return np.cumprod(np.broadcast_to(z[..., None], shape), axis=-1)

    def __call__(self, phase: ArrayLike) -> FloatArray:
        # k0 + sum a_n cos + b_n sin = k0 + Re(sum z^n (a_n - i b_n)); einsum's own loop, not
        # a BLAS product: a handful of terms per phase gains nothing from BLAS threads, which
        # cost more than the sum on a loaded machine
        return self.k0 + np.einsum("...n,n->...", self._powers(phase),
                                   self.a - 1j * self.b).real

    def derivative(self, phase: ArrayLike) -> FloatArray:
        """dk/dp in N/m per cycle.

        Parameters
        ----------
        phase : array_like
            Mesh phase p in cycles.

        Returns
        -------
        ndarray
            dk/dp in N/m per cycle, the shape of ``phase``.

        See Also
        --------
        :class:`~gear_dyn.stiffness.periodic.FourierStiffness` : The series.

        Examples
        --------
        >>> import math
        >>> k = FourierStiffness(1e8, [1e7], [0.0])
        >>> bool(abs(k.derivative(0.25) + 2 * math.pi * 1e7) < 1e-6)  # -2 pi a_1 at p = 1/4
        True
        """
        w = 2 * np.pi * np.arange(1, self.a.size + 1)
        # sum n w (-a_n sin + b_n cos) = Re(sum z^n w_n (b_n + i a_n))
        return np.einsum("...n,n->...", self._powers(phase), w * (self.b + 1j * self.a)).real

    def fourier_coefficients(self, n: int) -> tuple[float, FloatArray, FloatArray]:
        n = max(n, 0)  # the first n harmonics, zeros beyond the series
        a, b = (np.pad(c[:n], (0, n - min(n, c.size))) for c in (self.a, self.b))
        return float(self.k0), a, b


def rectangular_stiffness(contact_ratio: float, k_single: float, k_double: float,
                          name: str = "rectangular") -> PiecewiseStiffness:
    """Rectangular-wave mesh stiffness from the transverse contact ratio.

    With ``n = floor(eps)`` and ``f = eps - n``, ``n + 1`` pairs are in contact during the first
    ``f`` of each mesh cycle (phase 0 = a new pair enters) and ``n`` pairs for the rest.
    One pair has ``k_single``, two pairs ``k_double``; for high contact ratio (eps >= 2) each pair
    beyond the second adds ``k_double / 2`` (decision: pairs share equally).

    Parameters
    ----------
    contact_ratio : float
        Transverse contact ratio eps_a >= 1.
    k_single, k_double : float
        Single- and double-pair stiffness in N/m, 0 < k_single <= k_double.
    name : str
        Method name, reported in summaries.

    Returns
    -------
    PiecewiseStiffness
        Piecewise constant, with jumps at phase 0 and ``f``.

    Raises
    ------
    InputError
        eps < 1 or inconsistent stiffness values.

    See Also
    --------
    :func:`~gear_dyn.stiffness.select.build_stiffness` : The stiffness of a gear pair by any method.
    :func:`~gear_dyn.stiffness.iso6336.iso6336_stiffness` : ISO 6336-1 single and mesh stiffness.

    Examples
    --------
    >>> k = rectangular_stiffness(1.6, 1e8, 1.5e8)
    >>> k.switching_phases  # a new pair enters at 0, one leaves at 0.6 (cycles)
    array([0. , 0.6])
    >>> k.mean  # N/m
    130000000.0
    """
    contact_ratio = check_range("contact_ratio", contact_ratio, "", low=1.0)
    k_single = check_range("k_single", k_single, "N/m", low=0.0, low_open=True)
    k_double = check_range("k_double", k_double, "N/m", low=k_single)

    def k_of(pairs: int) -> float:
        if pairs <= 1:
            return k_single
        return k_double + (pairs - 2) * k_double / 2

    return stepped_stiffness(contact_ratio, k_of, name)


def contact_segments(contact_ratio: float) -> list[tuple[float, float, int]]:
    """``(start, end, pairs in contact)`` of the pieces of one mesh cycle (phase 0: a new pair
    enters): ``n + 1`` pairs on ``[0, f)`` and ``n`` on ``[f, 1)``, ``n = floor(eps_a)``,
    ``f = eps_a - n``; one piece when f is 0 (to 1e-9)."""
    n = int(math.floor(contact_ratio))
    f = contact_ratio - n
    if f < 1e-9 or f > 1 - 1e-9:
        return [(0.0, 1.0, int(round(contact_ratio)))]
    return [(0.0, f, n + 1), (f, 1.0, n)]


def stepped_stiffness(contact_ratio: float, level: Callable[[int], float],
                      name: str) -> PiecewiseStiffness:
    """Piecewise-constant stiffness ``level(pairs)`` (N/m) on the pieces of
    :func:`contact_segments`."""
    pieces = contact_segments(contact_ratio)
    edges = np.array([0.0, *(hi for _lo, hi, _n in pieces)])
    return PiecewiseStiffness(edges, tuple((np.array([lo, hi]), np.full(2, level(pairs)))
                                           for lo, hi, pairs in pieces), name=name)
