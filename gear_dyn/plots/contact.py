"""Figures of the loaded-contact analysis with tip relief (pyplot-free matplotlib)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import matplotlib as mpl
import numpy as np

from gear_dyn.analysis.spectrum import amplitude_spectrum
from gear_dyn.modification.analysis import ReliefCase
from gear_dyn.plots._axes import axes_of, tidy
from gear_dyn.solvers import Result


def _styles(n: int) -> list[dict[str, Any]]:
    cycle = mpl.rcParams["axes.prop_cycle"].by_key()["color"]
    return [{"color": "k" if i == 0 else cycle[(i - 1) % len(cycle)],
             "lw": 1.6 if i == 0 else 1.1, "ls": "--" if i == 0 else "-"} for i in range(n)]


def _two_panels(axes: Sequence[Any] | None, ax: Any, name: str) -> tuple[Any, Any]:
    """(figure, 2 axes) from ``ax`` or its older alias ``axes`` (at most one of them)."""
    if axes is not None and ax is not None:
        raise ValueError(f"{name}: pass ax or axes (the same thing), not both")
    return axes_of(ax if ax is not None else axes, 2, 1, figsize=(8, 7), name=name, sharex=True)


def _labelled(fig: Any, axs: Any, ylabels: tuple[str, str], xlabel: str) -> Any:
    """``fig`` with its two panels labelled and gridded, the legend on the top one, tidied."""
    for a, label in zip(axs, ylabels, strict=True):
        a.set_ylabel(label)
        a.grid(alpha=0.3)
    axs[1].set_xlabel(xlabel)
    axs[0].legend(fontsize=8, ncol=2)
    tidy(fig)
    return fig


def plot_load_sharing(cases: Mapping[str, ReliefCase], axes: Sequence[Any] | None = None,
                      ax: Any = None) -> Any:
    """Load-sharing factor and Hertz contact stress along the path of contact, all cases.

    The abscissa is the roll distance from the start of contact A in mm; the dotted lines mark
    the unmodified single-contact zone (B and D). ``ax`` (or its alias ``axes``): 2 Axes.
    """
    fig, axs = _two_panels(axes, ax, "plot_load_sharing")
    first = next(iter(cases.values()))
    pair = first.contact.pair
    s_a = pair.start_of_contact
    for (name, case), st in zip(cases.items(), _styles(len(cases)), strict=True):
        x = (case.path.position - s_a) * 1e3
        axs[0].plot(x, case.path.sharing, label=name, **st)
        axs[1].plot(x, case.stress / 1e6, label=name, **st)
    for v in (pair.end_of_contact - pair.base_pitch - s_a, pair.base_pitch):
        for ax in axs:
            ax.axvline(v * 1e3, color="0.5", ls=":", lw=0.8)
    axs[0].set_ylim(-0.03, 1.05)
    return _labelled(fig, axs, ("load-sharing factor S = F_i / F", "Hertz contact stress (MPa)"),
                     "roll distance from start of contact A (mm)")


def plot_loaded_stiffness(cases: Mapping[str, ReliefCase],
                          axes: Sequence[Any] | None = None, ax: Any = None) -> Any:
    """Loaded mesh stiffness K_TPM and loaded static transmission error over one mesh cycle.

    ``ax`` (or its alias ``axes``): 2 Axes.
    """
    fig, axs = _two_panels(axes, ax, "plot_loaded_stiffness")
    ph = np.append(np.linspace(0.0, 1.0, 2001)[:-1], 1.0 - 1e-9)  # the cycle, open at 1
    for (name, case), st in zip(cases.items(), _styles(len(cases)), strict=True):
        lc = case.contact
        axs[0].plot(ph, lc.mesh_stiffness()(ph) / 1e6, label=name, **st)
        axs[1].plot(ph, lc.static_transmission_error().value(ph) * 1e6, label=name, **st)
    return _labelled(fig, axs, ("loaded mesh stiffness K_TPM (N/µm)", "loaded static TE (µm)"),
                     "mesh phase (cycles; 0 = a pair enters at A)")


def plot_dynamic_comparison(results: Mapping[str, Result], periods: float = 4.0,
                            harmonics: int = 5, ax: Any = None) -> Any:
    """DTE over the last ``periods`` mesh periods and its spectrum, one line per case.

    ``ax``: 2 Axes (time history, spectrum) or None.
    """
    fig, (a0, a1) = axes_of(ax, 2, 1, figsize=(8, 7), name="plot_dynamic_comparison")
    for (name, res), st in zip(results.items(), _styles(len(results)), strict=True):
        fm = res.mesh_frequency
        t = res.t
        sel = t >= t[-1] - periods / fm
        x = res.series("dte")
        a0.plot((t[sel] - t[sel][0]) * fm, x[sel] * 1e6,
                label=f"{name} (F_max / W = {res.peak_force_ratio:.3f})", **st)
        mask = res.steady
        f, amp = amplitude_spectrum(t[mask], x[mask])
        a1.semilogy(f, np.maximum(amp * 1e6, 1e-6), label=name, **st)
    fm = next(iter(results.values())).mesh_frequency
    a1.set_xlim(0, (harmonics + 0.5) * fm)
    for n in range(1, harmonics + 1):
        a1.axvline(n * fm, color="tab:red", ls=":", lw=0.7)
    a0.set_xlabel("time (mesh periods)")
    a0.set_ylabel("dynamic TE x (µm)")
    a1.set_xlabel("frequency (Hz)")
    a1.set_ylabel("DTE amplitude (µm)")
    a0.legend(fontsize=8)
    for ax in (a0, a1):
        ax.grid(alpha=0.3, which="both")
    tidy(fig)
    return fig
