"""Amplitude spectra of uniformly sampled signals and peak tables."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError

FloatArray = NDArray[np.float64]


def amplitude_spectrum(
    t: FloatArray, x: FloatArray, window: str = "hann", detrend: bool = True
) -> tuple[FloatArray, FloatArray]:
    """One-sided amplitude spectrum of a uniformly sampled signal.

    A sinusoid ``A cos(2 pi f t)`` whose frequency falls on a bin shows amplitude ``A`` at ``f``
    (the window's coherent gain is divided out).

    Parameters
    ----------
    t : ndarray
        Uniform sample times in s (at least 4).
    x : ndarray
        Signal (any unit); the spectrum has the same unit.
    window : {"hann", "rect"}
        Window; Hann by default (leakage control).
    detrend : bool
        Remove the mean first.

    Returns
    -------
    f : ndarray
        Frequencies in Hz.
    amp : ndarray
        Amplitudes.

    Raises
    ------
    InputError
        Fewer than 4 samples, non-uniform times, unknown window.
    """
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    if t.size < 4 or t.shape != x.shape:
        raise InputError("spectrum: need >= 4 samples with matching t and x")
    dt = np.diff(t)
    if np.ptp(dt) > 1e-6 * dt.mean():
        raise InputError("spectrum: samples must be uniform in time")
    if detrend:
        x = x - x.mean()
    n = x.size
    if window == "hann":
        w = np.hanning(n + 1)[:-1]  # periodic Hann: no leakage past +-1 bin for bin-centred tones
    elif window == "rect":
        w = np.ones(n)
    else:
        raise InputError(f"spectrum window = {window!r}: valid choices are 'hann', 'rect'")
    spec = np.fft.rfft(x * w)
    amp = 2 * np.abs(spec) / w.sum()
    amp[0] /= 2
    f = np.fft.rfftfreq(n, d=float(dt.mean())).astype(np.float64)
    return f, amp.astype(np.float64)


def find_peaks(
    f: FloatArray, amp: FloatArray, n: int = 10, min_freq: float = 0.0, rel_height: float = 1e-3
) -> list[tuple[float, float]]:
    """The ``n`` largest local maxima ``(frequency, amplitude)`` above ``min_freq``.

    A peak must exceed ``rel_height`` times the largest one. Frequencies are refined by
    parabolic interpolation of the log amplitude around the maximum bin.
    """
    f = np.asarray(f, dtype=float)
    a = np.asarray(amp, dtype=float)
    if a.size < 3:
        return []
    loc = np.flatnonzero((a[1:-1] > a[:-2]) & (a[1:-1] >= a[2:])) + 1
    loc = loc[f[loc] > min_freq]
    if loc.size == 0:
        return []
    top = a[loc].max()
    loc = loc[a[loc] >= rel_height * top]
    loc = loc[np.argsort(a[loc])[::-1][:n]]
    peaks = []
    df = f[1] - f[0]
    for i in loc:
        la, lb, lc = np.log(np.maximum(a[i - 1 : i + 2], 1e-300))
        den = la - 2 * lb + lc
        d = 0.5 * (la - lc) / den if den != 0 else 0.0
        peaks.append((float(f[i] + d * df), float(a[i])))
    return peaks
