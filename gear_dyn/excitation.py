"""Periodic excitation signals of the mesh phase: static transmission error e(p).

A signal is a function of the mesh phase ``p`` (cycles, period 1) with its slope ``de/dp``, so a
model can form ``e'(t) = f_m de/dp``. Two forms:

- :class:`HarmonicSignal`: ``sum_n c_n cos(2 pi n p) + s_n sin(2 pi n p)`` (+ mean), e.g. a
  measured transmission-error spectrum at mesh harmonics.
- :class:`SampledSignal`: linear interpolation of samples over one cycle (e.g. the transmission
  error a tip relief adds, from the loaded-contact analysis).
"""

from __future__ import annotations

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
        Coefficients of harmonics 1..N (same unit as ``mean``).
    """

    mean: float
    cos: FloatArray
    sin: FloatArray

    def __post_init__(self) -> None:
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
        ang = 2 * np.pi * p[..., None] * np.arange(1, self.cos.size + 1)
        return self.mean + np.cos(ang) @ self.cos + np.sin(ang) @ self.sin

    def slope(self, phase: ArrayLike) -> FloatArray:
        """de/dp at mesh phase ``phase`` (unit per cycle)."""
        p = np.asarray(phase, dtype=float)
        w = 2 * np.pi * np.arange(1, self.cos.size + 1)
        ang = p[..., None] * w
        return np.cos(ang) @ (self.sin * w) - np.sin(ang) @ (self.cos * w)


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
