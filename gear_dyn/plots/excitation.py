"""Figures of the excitations of Liu et al. (2017): time histories and labelled spectra
(matplotlib).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.spectrum_labels import Basis
from gear_dyn.plots._axes import axes_of, tidy
from gear_dyn.plots._decimate import draw_band
from gear_dyn.plots._labels import place_labels

FloatArray = NDArray[np.float64]

#: (key, axis label, scale factor to the plotted unit)
SIGNALS: tuple[tuple[str, str, float], ...] = (
    ("w2", "driven speed w2 (rad/s)", 1.0),
    ("contact_length", "contact-line length L (mm)", 1e3),
    ("friction_force", "friction force F_f (N)", 1.0),
    ("friction_torque_pinion", "friction torque on pinion (N m)", 1.0),
)


def plot_excitation_time(t: FloatArray, series: Mapping[str, FloatArray], basis: Basis,
                         zoom_periods: float = 5.0, ax: Any = None) -> Any:
    """Each signal against time: the whole span (left; from 40 mesh periods on as its envelope,
    the largest and smallest value in each mesh period) and the first mesh periods (right).

    Parameters
    ----------
    t : ndarray
        Times in s.
    series : mapping
        Signal name -> values, names from :data:`SIGNALS` (missing ones are skipped).
    basis : Basis
        Frequencies (the zoom spans ``zoom_periods / f_m``).
    zoom_periods : float
        Mesh periods in the zoom.
    ax : sequence of Axes or None
        2 Axes per signal drawn (row-major: whole span, zoom; signals in :data:`SIGNALS`
        order).
    """
    rows = [s for s in SIGNALS if s[0] in series]
    fig, axes = axes_of(ax, len(rows), 2, figsize=(12, 2.3 * len(rows)),
                        name="plot_excitation_time", squeeze=False, sharex="col")
    zoom = t <= t[0] + zoom_periods / basis.mesh
    for i, (key, label, scale) in enumerate(rows):
        y = np.asarray(series[key]) * scale
        if (t[-1] - t[0]) * basis.mesh >= 40:  # thousands of mesh cycles: their envelope
            draw_band(axes[i, 0], t, y, 1.0 / basis.mesh)
        else:
            axes[i, 0].plot(t, y, lw=0.5)
        axes[i, 1].plot(t[zoom] * 1e3, y[zoom], lw=0.9)
        axes[i, 0].set_ylabel(label, fontsize=8)
        for ax in axes[i]:
            ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("time (s)")
    axes[-1, 1].set_xlabel("time (ms)")
    whole = (t[-1] - t[0]) * basis.mesh >= 40
    axes[0, 0].set_title("whole span" + (": max / min per mesh period" if whole else ""))
    axes[0, 1].set_title(f"first {zoom_periods:g} mesh periods")
    tidy(fig)
    return fig


def plot_excitation_spectra(spectra: Mapping[str, tuple[FloatArray, FloatArray]],
                            peaks: Mapping[str, Sequence[Mapping[str, Any]]], basis: Basis,
                            f_max: float | None = None, n_labels: int = 6,
                            ax: Any = None) -> Any:
    """Amplitude spectra with shaft frequencies, mesh harmonics and labelled peaks.

    Parameters
    ----------
    spectra : mapping
        Signal name -> (f in Hz, amplitude in the signal's unit).
    peaks : mapping
        Signal name -> peak dicts from :func:`gear_dyn.analysis.spectrum_labels.labelled_peaks`.
    basis : Basis
    f_max : float or None
        Upper frequency shown (default 2.2 f_m).
    n_labels : int
        Largest labelled peaks annotated per panel (each label placed where it covers no other
        label: ``gear_dyn.plots._labels.place_labels()``).
    ax : Axes, sequence of Axes or None
        One Axes per signal drawn (in :data:`SIGNALS` order).
    """
    rows = [s for s in SIGNALS if s[0] in spectra]
    f_max = 2.2 * basis.mesh if f_max is None else f_max
    labels: list[tuple[Any, list[tuple[float, float, str]]]] = []
    fig, axes = axes_of(ax, len(rows), 1, figsize=(12, 2.6 * len(rows)),
                        name="plot_excitation_spectra", squeeze=False)
    for i, (key, label, scale) in enumerate(rows):
        ax = axes[i, 0]
        f, a = spectra[key]
        sel = f <= f_max
        ax.semilogy(f[sel], np.maximum(a[sel] * scale, 1e-300), lw=0.7)
        top = max(float(np.max(a[sel] * scale)), 1e-300)
        ax.set_ylim(top * 1e-6, top * 40)  # room for the labels above the peaks
        for fx, style in ((basis.shaft1, "tab:red"), (basis.shaft2, "tab:green")):
            ax.axvline(fx, color=style, ls=":", lw=0.8)
        n = 1
        while n * basis.mesh <= f_max:
            ax.axvline(n * basis.mesh, color="k", ls="--", lw=0.5, alpha=0.5)
            n += 1
        # the strongest labelled peaks (peaks come sorted by decreasing amplitude), each label
        # where it covers no other
        shown = [p for p in peaks.get(key, []) if p["label"] and p["frequency_hz"] <= f_max]
        marks = [(p["frequency_hz"], p["amplitude"] * scale, p["label"]) for p in
                 shown[:n_labels]]
        if marks:
            ax.plot([m[0] for m in marks], [m[1] for m in marks], "v", ms=4, color="tab:blue",
                    ls="none")
            ax.set_xlim(-0.02 * f_max, 1.02 * f_max)
            labels.append((ax, marks))
        ax.set_ylabel(label.replace(" (", "\namplitude ("), fontsize=9)
        ax.grid(alpha=0.3, which="major")
    axes[-1, 0].set_xlabel(
        f"frequency (Hz)   f1 = {basis.shaft1:.4g} Hz (red), f2 = {basis.shaft2:.4g} Hz (green),"
        f" f_m = {basis.mesh:.4g} Hz and harmonics (dashed)")
    tidy(fig)
    for axis, marks in labels:  # once the layout is settled: the extents are final
        place_labels(axis, marks, fontsize=8, color="tab:blue", box=True)
    return fig
