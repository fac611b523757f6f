"""Periodic excitation signals of the mesh phase: static transmission error e(p).

A signal is a function of the mesh phase ``p`` (cycles) with its slope ``de/dp``, so a
model can form ``e'(t) = f_m de/dp``. Each states its ``period`` in mesh cycles: 1 for a signal
of mesh harmonics, more for one with shaft-order content (manufacturing deviations repeat once
per revolution of a gear, ``z`` mesh cycles). Three forms:

- :class:`HarmonicSignal`: ``sum_n c_n cos(2 pi n p / P) + s_n sin(2 pi n p / P)`` (+ mean),
  ``P`` its period (1: a measured transmission-error spectrum at mesh harmonics).
- :class:`SampledSignal`: linear interpolation of samples over one cycle (e.g. the transmission
  error a tip relief adds, from the loaded-contact analysis); period 1.
- :class:`SumSignal`: the sum of signals of different periods (a mesh-order part and each
  gear's once-per-revolution part); its period is the least common multiple of theirs (the
  hunting period when both gears contribute).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gear_dyn.errors import InputError, check_range

FloatArray = NDArray[np.float64]


def _floats(values: object, what: str, atleast_1d: bool = True) -> FloatArray:
    """``values`` as a float array, or an InputError naming ``what`` (not a numpy error)."""
    try:
        a = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{what} = {values!r}: expected a list of numbers") from None
    return np.atleast_1d(a) if atleast_1d else a


@dataclass(frozen=True, eq=False)
class HarmonicSignal:
    """Fourier-series periodic signal of the mesh phase.

    Parameters
    ----------
    mean : float
        Mean value (m for a transmission error).
    cos, sin : array_like
        Coefficients of harmonics 1..N (same unit as ``mean``) of the fundamental
        ``1 / period`` (in mesh orders).
    period : int
        Period in mesh cycles (1..10^7; default 1: mesh harmonics). ``period = z1`` with
        coefficient ``n`` at pinion shaft order ``n``.
    """

    mean: float
    cos: FloatArray
    sin: FloatArray
    period: int = 1

    def __post_init__(self) -> None:
        check_range("transmission error: period", self.period, "mesh cycles", low=1, high=1e7)
        if int(self.period) != self.period:
            raise InputError(f"transmission error: period = {self.period!r} mesh cycles: "
                             "expected a whole number")
        object.__setattr__(self, "period", int(self.period))
        c = _floats(self.cos, "transmission error: cos coefficients")
        s = _floats(self.sin, "transmission error: sin coefficients")
        if c.shape != s.shape or c.ndim != 1:
            raise InputError("transmission error: cos and sin coefficient lists differ in length")
        check_range("transmission error: mean", self.mean, "m")
        if not (np.all(np.isfinite(c)) and np.all(np.isfinite(s))):
            raise InputError("transmission error: coefficients must be finite numbers (m)")
        object.__setattr__(self, "cos", c)
        object.__setattr__(self, "sin", s)

    def value(self, phase: ArrayLike) -> FloatArray:
        """e(p) at mesh phase ``phase``."""
        p = np.asarray(phase, dtype=float)
        if self.period > 1:  # reduced to one period first: no loss of digits in the angle
            p = np.mod(p, self.period) / self.period
        ang = 2 * np.pi * p[..., None] * np.arange(1, self.cos.size + 1)
        return self.mean + np.cos(ang) @ self.cos + np.sin(ang) @ self.sin

    def slope(self, phase: ArrayLike) -> FloatArray:
        """de/dp at mesh phase ``phase`` (unit per cycle)."""
        p = np.asarray(phase, dtype=float)
        w = 2 * np.pi * np.arange(1, self.cos.size + 1)
        if self.period > 1:
            p, w = np.mod(p, self.period), w / self.period
        ang = p[..., None] * w
        return np.cos(ang) @ (self.sin * w) - np.sin(ang) @ (self.cos * w)

    @property
    def orders(self) -> FloatArray:
        """Mesh orders of the coefficients: ``n / period``, n = 1..N."""
        return np.arange(1, self.cos.size + 1) / self.period


@dataclass(frozen=True, eq=False)
class SampledSignal:
    """Periodic signal given by samples over one mesh cycle, linearly interpolated.

    Parameters
    ----------
    phase : array_like
        Sample phases, strictly increasing within [0, 1).
    values : array_like
        Signal values at those phases.
    """

    phase: FloatArray
    values: FloatArray

    def __post_init__(self) -> None:
        p = _floats(self.phase, "sampled signal: phase", atleast_1d=False)
        v = _floats(self.values, "sampled signal: values", atleast_1d=False)
        if p.ndim != 1 or p.shape != v.shape or p.size < 2:
            raise InputError("sampled signal: phase and values must be 1-D of equal length >= 2")
        if not np.all(np.isfinite(p)) or p[0] < 0 or p[-1] >= 1 or np.any(np.diff(p) <= 0):
            raise InputError("sampled signal: phases must increase strictly within [0, 1)")
        if not np.all(np.isfinite(v)):
            raise InputError("sampled signal: values must be finite")
        # close the cycle
        pp = np.concatenate([p[-1:] - 1.0, p, p[:1] + 1.0])
        vv = np.concatenate([v[-1:], v, v[:1]])
        object.__setattr__(self, "phase", pp)
        object.__setattr__(self, "values", vv)

    def value(self, phase: ArrayLike) -> FloatArray:
        """e(p) at mesh phase ``phase``."""
        p = np.mod(np.asarray(phase, dtype=float), 1.0)
        return np.interp(p, self.phase, self.values)

    def slope(self, phase: ArrayLike) -> FloatArray:
        """de/dp (piecewise constant) at mesh phase ``phase``."""
        p = np.mod(np.asarray(phase, dtype=float), 1.0)
        i = np.clip(np.searchsorted(self.phase, p, side="right") - 1, 0, self.phase.size - 2)
        return (self.values[i + 1] - self.values[i]) / (self.phase[i + 1] - self.phase[i])

    @property
    def knots(self) -> FloatArray:
        """Sample phases in [0, 1) (where the slope jumps)."""
        return self.phase[1:-1].copy()

    @property
    def period(self) -> int:
        """Period in mesh cycles: 1."""
        return 1


@dataclass(frozen=True, eq=False)
class SumSignal:
    """The sum of periodic signals of the mesh phase, e.g. of different periods.

    Parameters
    ----------
    parts : tuple of signals
        :class:`HarmonicSignal` or :class:`SampledSignal` (at least one), same unit.
    """

    parts: tuple[HarmonicSignal | SampledSignal, ...]

    def __post_init__(self) -> None:
        parts = tuple(self.parts)
        if not parts or not all(isinstance(q, HarmonicSignal | SampledSignal) for q in parts):
            raise InputError("sum signal: parts must be one or more harmonic or sampled signals")
        object.__setattr__(self, "parts", parts)

    @property
    def period(self) -> int:
        """Period in mesh cycles: the least common multiple of the parts' periods."""
        return math.lcm(*(q.period for q in self.parts))

    def value(self, phase: ArrayLike) -> FloatArray:
        """e(p) at mesh phase ``phase``."""
        return np.sum([q.value(phase) for q in self.parts], axis=0)

    def slope(self, phase: ArrayLike) -> FloatArray:
        """de/dp at mesh phase ``phase`` (unit per cycle)."""
        return np.sum([q.slope(phase) for q in self.parts], axis=0)
