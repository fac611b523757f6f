"""Figures of simulation results (pyplot-free matplotlib Figures; no window, no backend choice).

The spectrum shows the physics a gear engineer looks for: its range covers the natural frequency
f_n and the mesh harmonics up to the first above f_n; f_n, the mesh harmonics and (eccentric
models) the shaft frequencies and the sidebands f_m +- f_shaft are marked with their frequency in
Hz; the analysis window is stated; the run's stated error is drawn as a noise floor, so nothing
below it is read as physics.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from gear_dyn.analysis.report import DTE_DEFINITION, model_kind
from gear_dyn.analysis.spectrum import amplitude_spectrum
from gear_dyn.errors import InputError
from gear_dyn.plots._axes import axes_of, fixed_layout
from gear_dyn.plots._decimate import draw_band, envelope
from gear_dyn.solvers import Result

#: a whole run of at least this many mesh periods is drawn as its envelope (max/min per mesh
#: period, filled); shorter runs as lines
BAND_PERIODS = 40

_BOX = {"facecolor": "white", "edgecolor": "none", "alpha": 0.8, "pad": 0.5}


@dataclass(frozen=True)
class Marks:
    """Frequencies (Hz) a run's spectrum is read by."""

    mesh: float
    natural: float | None
    shafts: tuple[tuple[str, float], ...]  # ("f1", 25.0), ("f2", 6.4): eccentric models only

    @property
    def top_harmonic(self) -> int:
        """The mesh harmonic the range reaches: the first above f_n, at least 3."""
        if self.natural is None:
            return 5
        return max(3, math.floor(self.natural / self.mesh) + 1)


def spectrum_marks(result: Result) -> Marks:
    """f_m, f_n (from the model's summary facts) and, for eccentric models, the shaft
    frequencies f1 = f_m / z1 and f2 = f_m / z2."""
    fn = result.extra.get("natural_frequency_hz")
    shafts: tuple[tuple[str, float], ...] = ()
    scene = result.scene
    if result.extra.get("eccentric") and scene is not None and hasattr(scene, "tables"):
        g = scene.tables["gear"]
        shafts = (("f1", result.mesh_frequency / g["teeth_pinion"]),
                  ("f2", result.mesh_frequency / g["teeth_gear"]))
    return Marks(result.mesh_frequency, float(fn) if fn else None, shafts)


def noise_floor(result: Result) -> float | None:
    """The run's stated error in m (``estimated_error.max_rel`` x static deflection W/k_m)."""
    est = result.extra.get("estimated_error")
    k = result.outputs.get("stiffness")
    if not isinstance(est, dict) or est.get("max_rel") is None or k is None:
        return None
    km = float(np.mean(k[result.steady]))
    rel = float(est["max_rel"])
    if km <= 0 or not math.isfinite(rel):
        return None
    return rel * result.static_load / km


def time_history_size(result: Result, periods: float | None = 10.0) -> tuple[float, float]:
    """Size (width, height) in inches of a new :func:`plot_time_history` figure: 6.5 x 3 per
    panel, rows DTE[, elastic part], force; columns whole run[, zoom]."""
    return 6.5 * (2 if periods else 1), 3.0 * (3 if "e_ecc" in result.outputs else 2)


def plot_time_history(result: Result, periods: float | None = 10.0, ax: Any = None,
                      blocks: int | None = None) -> Any:
    """DTE and dynamic mesh force against time, the steady-state window shaded.

    A whole run of :data:`BAND_PERIODS` mesh periods or more is drawn as its envelope: the band
    between the smallest and largest value in each mesh period (drawn as a line, thousands of
    mesh cycles would fill the panel); the zoom column shows the last ``periods`` as lines, and
    its span is marked on the whole run.

    In the eccentric torsional model the DTE holds the eccentricity's kinematic error (rigid
    teeth, -e_ecc, hundreds of um) and the elastic mesh deflection delta (a few um): a middle row
    shows the elastic part on its own scale, and the DTE row names both parts.

    Parameters
    ----------
    result : Result
    periods : float or None
        Also draws a zoom on the last ``periods`` mesh periods (None: no zoom).
    ax : Axes sequence or None
        One Axes per panel. Panels: rows DTE[, elastic part], mesh force (the middle row only
        for eccentric models); columns whole run[, zoom on the last ``periods``]. Give 2 Axes
        (3 for eccentric models: one per row) for the whole run alone, or 4 (6) in row-major
        order, e.g. a 2 x 2 array, for the whole run and the zoom. None: a new figure with the
        zoom column when ``periods`` is given. On the caller's Axes nothing is written outside
        them: no figure title, no layout change.

    Returns
    -------
    Figure
        The new figure, or the figure of the caller's Axes.

    Raises
    ------
    ValueError
        ``ax`` is not one of the Axes counts above (the message names them).
    blocks : int or None
        At most this many bins in a whole-run band (a bin then spans several mesh periods;
        ``gear_dyn.plots._decimate.period_envelope()``); a whole run drawn as lines is drawn
        as the first, smallest, largest and last sample of this many blocks
        (``gear_dyn.plots._decimate.envelope()``): for a file, about 2 per pixel column give
        the same picture from fewer points. None: every mesh period, every sample.
    """
    split = "e_ecc" in result.outputs
    nrows = 3 if split else 2
    ncols = 2 if periods else 1
    if ax is not None:
        n = 1 if hasattr(ax, "plot") else len(list(np.ravel(np.asarray(ax, dtype=object))))
        if n not in (nrows, 2 * nrows):
            raise ValueError(
                f"plot_time_history: expected {nrows} Axes (whole run: "
                f"{'DTE, elastic part, force' if split else 'DTE, force'}) or {2 * nrows} "
                f"(whole run and zoom, row-major), got {n}")
        ncols = n // nrows
        if ncols == 2 and not periods:
            periods = 10.0  # the zoom column the caller asked for
    fig, axes = axes_of(ax, nrows, ncols, figsize=time_history_size(result, periods),
                        name="plot_time_history", squeeze=False, sharex="col")
    t = result.t
    rows: list[list[tuple[Any, str, str]]] = [[(result.outputs["dte"] * 1e6, "DTE", "tab:blue")]]
    ylabels = ["DTE (µm)"]
    if split:
        rows[0].append((-result.outputs["e_ecc"] * 1e6, "kinematic part -e_ecc (eccentricity)",
                        "tab:orange"))
        rows.append([(result.outputs["delta"] * 1e6, "elastic part delta (mesh deflection)",
                      "tab:purple")])
        ylabels.append("elastic part (µm)")
    rows.append([(result.outputs["mesh_force"] / 1e3, "mesh force", "tab:blue")])
    ylabels.append("mesh force (kN)")
    period = 1.0 / result.mesh_frequency
    band = (t[-1] - t[0]) / period >= BAND_PERIODS  # the whole run as its envelope
    zoom_start = t[-1] - (periods or 0.0) * period
    for col in range(ncols):
        sel = slice(None)
        if col == 1 and periods:
            sel = t >= zoom_start
        for r, series in enumerate(rows):
            a = axes[r, col]
            for y, label, color in series:
                if col == 0 and band:
                    _draw_band(a, t, y, period, blocks, label, color)
                    continue
                xs, ys = t[sel] * 1e3, y[sel]
                if col == 0 and blocks:
                    xs, ys = envelope(xs, ys, blocks)
                a.plot(xs, ys, lw=0.8, color=color, label=label)
                if label == "mesh force" and np.any(ys < 0):
                    _mark_negative(a, xs, ys, col == 0)
            a.set_ylabel(ylabels[r])
            a.grid(alpha=0.3)
            if col == 0:
                a.axvspan(result.steady_start * 1e3, t[-1] * 1e3, color="tab:green", alpha=0.12,
                          lw=0, label="steady-state window" if r == 0 else None)
                a.axvline(result.steady_start * 1e3, color="tab:green", lw=0.8)
                if ncols == 2 and periods:  # where the zoom on the right is
                    a.axvspan(zoom_start * 1e3, t[-1] * 1e3, color="0.4", alpha=0.25, lw=0,
                              label=f"last {periods:g} mesh periods (right)" if r == 0 else None)
        axes[-1, col].set_xlabel("time (ms)")
    axes[-1, 0].axhline(result.static_load / 1e3, color="k", ls="--", lw=0.7,
                        label=f"static load W = {result.static_load / 1e3:.4g} kN")
    for r in range(nrows):
        _legend_headroom(axes[r, 0])
        axes[r, 0].legend(loc="upper right", fontsize=7)
    if ax is not None:
        return fig  # the caller's figure: its titles and layout are the caller's
    if ncols == 2 and periods:
        span_ms = periods / result.mesh_frequency * 1e3
        axes[0, 1].set_title(f"last {periods:g} mesh periods ({span_ms:.3g} ms)", fontsize=10)
    axes[0, 0].set_title("whole run" + (": max / min per mesh period" if band else ""),
                         fontsize=10)
    fig.suptitle(DTE_DEFINITION[model_kind(result)], fontsize=8)
    # margins in inches: the look of tight_layout without measuring twice
    fixed_layout(fig, left=0.72, right=0.15, top=0.62, bottom=0.55, wgap=0.75, hgap=0.25)
    return fig


def _draw_band(ax: Any, t: Any, y: Any, period: float, blocks: int | None, label: str,
               color: str) -> None:
    """The whole run of ``y`` as the band between its smallest and largest value per mesh
    period (at most ``blocks`` bins), filled, edged; a negative mesh force shaded red."""
    edges, lo, hi = draw_band(ax, t, y, period, blocks, color=color, label=label, t_scale=1e3)
    ms = edges * 1e3
    if label == "mesh force" and np.any(lo < 0):
        ax.stairs(np.minimum(lo, 0.0), ms, baseline=0.0, fill=True, color="tab:red", alpha=0.5,
                  lw=0, label="F < 0: teeth would separate (model invalid: add [backlash])")
        ax.axhline(0.0, color="tab:red", lw=0.6)


def _legend_headroom(ax: Any) -> None:
    """Raise the top of ``ax`` so its upper-right legend sits above the curves, not on them
    (a whole run fills its panel from end to end): about 7 % of the panel per legend entry."""
    n = len(ax.get_legend_handles_labels()[1])
    lo, hi = ax.get_ylim()
    ax.set_ylim(lo, hi + (hi - lo) * (0.05 + 0.1 * n) / (0.95 - 0.1 * n))


def _mark_negative(ax: Any, xs: Any, ys: Any, label: bool) -> None:
    """Shade where the mesh force is negative: the teeth would pull (in a model without
    backlash: the model does not hold there; with backlash the force is never negative)."""
    ax.fill_between(xs, ys, 0.0, where=ys < 0, color="tab:red", alpha=0.5, lw=0,
                    label="F < 0: teeth would separate (model invalid: add [backlash])"
                    if label else None)
    ax.axhline(0.0, color="tab:red", lw=0.6)


def plot_spectrum(result: Result, name: str = "dte", harmonics: int | None = None,
                  ax: Any = None, scale: str = "log", floor: float | None = None) -> Any:
    """Amplitude spectrum of a series over the steady window, with the physics marked.

    Parameters
    ----------
    result : Result
    name : str
        Series (``dte`` in µm by default; any output or state).
    harmonics : int or None
        Mesh harmonics shown (default: up to the first above f_n, at least 3).
    ax : Axes, sequence of 2 Axes, or None
        One Axes: the spectrum. Two: the spectrum and a zoom on the sidebands around f_m
        (eccentric models). None: a new figure (two panels for eccentric models), titled. On
        the caller's Axes nothing is written outside them: no titles, no layout change.

    Returns
    -------
    Figure
        The new figure, or the figure of the caller's Axes.

    Raises
    ------
    InputError
        An unknown ``scale``.
    ValueError
        ``ax`` is neither one Axes nor two of one figure.
    scale : {"log", "linear"}
        Amplitude axis.
    floor : float or None
        Noise floor in the series' SI unit (default for DTE: the run's stated error,
        :func:`noise_floor`); drawn as a line, the band below it shaded.
    """
    if scale not in ("log", "linear"):
        raise InputError(f"spectrum scale = {scale!r}: valid choices are 'log', 'linear'")
    marks = spectrum_marks(result)
    zoom = bool(marks.shafts)
    if ax is not None:
        zoom = not hasattr(ax, "plot") and len(list(np.ravel(ax))) == 2
    fig, axes = axes_of(ax, 2 if zoom else 1, 1, figsize=(10, 7 if zoom else 4.5),
                        name="plot_spectrum", squeeze=False)
    mask = result.steady
    t = result.t[mask]
    f, amp = amplitude_spectrum(t, result.series(name)[mask])
    dte_like = name in ("dte", "x", "delta", "e_ecc")
    factor, unit = (1e6, "µm") if dte_like else (1.0, "SI")
    amp = amp * factor
    if floor is None and dte_like:
        floor = noise_floor(result)
    top = harmonics or marks.top_harmonic
    fmax = min(f[-1], max((top + 0.5) * marks.mesh, 1.1 * (marks.natural or 0.0)))
    main = axes[0, 0]
    _draw_amplitude(main, f, amp, scale, floor * factor if floor else None, fmax, unit)
    _mark_physics(main, marks, top, fmax)
    if marks.natural is not None and marks.natural > f[-1]:
        main.text(0.5, 0.5, f"f_n = {marks.natural:.0f} Hz is above the Nyquist frequency "
                  f"{f[-1]:.0f} Hz: raise samples_per_period", transform=main.transAxes,
                  ha="center", color="tab:red")
    main.set_xlim(0, fmax)
    main.set_ylabel(f"amplitude of {name} ({unit})")
    df = 1.0 / (t[-1] - t[0] + (t[1] - t[0]))
    if ax is None:  # the caller's Axes get no title (their figure is theirs to label)
        main.set_title(f"{name} spectrum, steady window {t[0] * 1e3:.4g}-{t[-1] * 1e3:.4g} ms "
                       f"({(t[-1] - t[0]) * marks.mesh:.0f} mesh periods), Hann window, "
                       f"resolution {df:.3g} Hz", fontsize=9)
    if zoom:
        _sideband_zoom(axes[1, 0], f, amp, marks, scale, floor * factor if floor else None, unit,
                       title=ax is None)
        axes[1, 0].set_ylabel(f"amplitude ({unit})")
    axes[-1, 0].set_xlabel("frequency (Hz)")
    if ax is None:  # margins in inches: the look of tight_layout without measuring twice
        fixed_layout(fig, left=0.85, right=0.15, top=0.35, bottom=0.55, hgap=0.65)
    return fig


def _draw_amplitude(ax: Any, f: Any, amp: Any, scale: str, floor: float | None,
                    fmax: float, unit: str) -> None:
    sel = f <= fmax
    peak = float(np.max(amp[sel][1:])) if np.count_nonzero(sel) > 1 else 1.0
    if scale == "log":
        ax.set_yscale("log")
        low = peak * 1e-8
        if floor:
            low = max(min(low, floor / 10), peak * 1e-12)
        ax.plot(f[sel], np.maximum(amp[sel], low), lw=0.7, color="tab:blue")
        ax.set_ylim(low, peak * 300)  # room for the harmonic labels above the peaks
    else:
        ax.plot(f[sel], amp[sel], lw=0.8, color="tab:blue")
        ax.set_ylim(0, peak * 1.25)
    if floor:
        ax.axhline(floor, color="0.3", ls="--", lw=0.8)
        ax.axhspan(ax.get_ylim()[0], floor, color="0.5", alpha=0.15,
                   label=f"below the run's stated error ({floor:.2g} {unit}): not physics")
        ax.legend(loc="lower right", fontsize=7)
    ax.grid(alpha=0.3, which="major")


def _mark_physics(ax: Any, marks: Marks, top: int, fmax: float) -> None:
    trans = ax.get_xaxis_transform()
    step = max(1, math.ceil(top / 8))  # at most ~8 labelled harmonics
    for n in range(1, top + 1):
        fn = n * marks.mesh
        if fn > fmax:
            break
        ax.axvline(fn, color="tab:red", ls=":", lw=0.8)
        if n % step == 0 or n == 1:
            ax.text(fn, 0.98, f"{n}f_m\n{fn:.0f} Hz", transform=trans, color="tab:red",
                    fontsize=8, ha="center", va="top", bbox=_BOX)
    if marks.natural is not None and marks.natural <= fmax:
        ax.axvline(marks.natural, color="tab:green", ls="--", lw=1.0)
        # beside its line, not across it
        ax.text(marks.natural, 0.75, f" f_n = {marks.natural:.0f} Hz", transform=trans,
                color="tab:green", fontsize=9, ha="left", va="top", bbox=_BOX)
    for _, fs in marks.shafts:
        ax.axvline(fs, color="tab:purple", ls="-.", lw=0.7)
    if marks.shafts:  # one box right of the highest shaft line, above the curve's tail
        ax.text(max(fs for _, fs in marks.shafts), 0.9, "\n".join(
            f" {label} = {fs:.3g} Hz ({'pinion' if label == 'f1' else 'gear'} shaft)"
            for label, fs in marks.shafts), transform=trans, color="tab:purple", fontsize=8,
            va="top", bbox=_BOX)


def _sideband_zoom(ax: Any, f: Any, amp: Any, marks: Marks, scale: str,
                   floor: float | None, unit: str, title: bool = True) -> None:
    """Zoom on f_m +- 3.5 f1: the sidebands f_m +- k f1 and f_m +- k f2, labelled (``title``:
    the shaft frequencies as the panel's title; not on a caller's Axes)."""
    f1 = max(fs for _, fs in marks.shafts)
    lo, hi = marks.mesh - 3.5 * f1, marks.mesh + 3.5 * f1
    sel = (f >= lo) & (f <= hi)
    _draw_amplitude(ax, f[sel], amp[sel], scale, floor, hi, unit)
    ax.set_xlim(lo, hi)
    bottom, top = ax.get_ylim()
    peak = float(np.max(amp[sel])) if np.any(sel) else top
    if scale == "log" and 0 < bottom < peak:  # the highest peak at 60 %: the labels above it
        ax.set_ylim(bottom, bottom * (peak / bottom) ** (1 / 0.6))
    elif scale != "log":
        ax.set_ylim(0, peak / 0.6)
    trans = ax.get_xaxis_transform()
    ax.axvline(marks.mesh, color="tab:red", ls=":", lw=0.8)
    ax.text(marks.mesh, 0.98, f"f_m\n{marks.mesh:.0f} Hz", transform=trans, color="tab:red",
            fontsize=8, ha="center", va="top", bbox=_BOX)
    for label, fs in marks.shafts:
        kmax = 3 if label == "f1" else 2
        for k in range(1, kmax + 1):
            y = 0.98 if label == "f1" else (0.84 if k == 1 else 0.70)
            for sign in (-1, 1):
                fb = marks.mesh + sign * k * fs
                ax.axvline(fb, color="tab:purple", ls=":", lw=0.6)
                kk = "" if k == 1 else str(k)
                ax.text(fb, y, f"f_m{'+' if sign > 0 else '-'}{kk}{label}\n{fb:.1f} Hz",
                        transform=trans, color="tab:purple", fontsize=7.5, ha="center",
                        va="top", bbox=_BOX)
    if title:
        ax.set_title(f"sidebands around f_m: f1 = {marks.shafts[0][1]:.3g} Hz (pinion shaft), "
                     f"f2 = {marks.shafts[1][1]:.3g} Hz (gear shaft)", fontsize=9)
