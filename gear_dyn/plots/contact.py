"""Figures of the loaded-contact analysis with tip relief, spur and slice method (pyplot-free
matplotlib)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import matplotlib as mpl
import numpy as np

from gear_dyn.analysis.spectrum import amplitude_spectrum
from gear_dyn.modification.analysis import ReliefCase, ReliefStudy, SliceCase
from gear_dyn.modification.slice_contact import SliceContact
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


def plot_face_load(contact: SliceContact, index: int = 0, title: str | None = None,
                   ax: Any = None) -> Any:
    """Slice loaded contact: line load over the field of contact, and the static TE.

    Top: the slices of every mesh position at their place in the plane of action (roll
    distance from the start of contact A against the face position), their normal line load
    in N/mm averaged over the cells of a grid; the contact lines of the first position are
    drawn over it. Bottom: the
    loaded and unloaded static transmission error over the mesh cycle. ``index``: the torque
    of a ladder. ``ax``: 2 Axes or None.
    """
    fig, (a0, a1) = axes_of(ax, 2, 1, figsize=(8, 7.5), name="plot_face_load",
                            gridspec_kw={"height_ratios": [1.6, 1.0]})
    c = contact.at(index)
    pair = c.pair
    s_a = pair.start_of_contact
    load = c.line_load[0] / 1e3  # N/mm, (P, J, S)
    inside = np.isfinite(c.position)
    yy = np.broadcast_to(c.face[None, None, :], inside.shape)
    x = (c.position[inside] - s_a) * 1e3
    # the mean line load of the samples falling in each cell of a grid over the field
    n_s = c.face.size
    # a cell per mesh-position step along the path at most: no empty cells inside the field
    n_x = max(4, int(0.8 * c.options.positions * pair.contact_ratio))
    x_edges = np.linspace(0.0, pair.path_of_contact * 1e3, n_x + 1)
    y_edges = np.linspace(0.0, pair.face_width * 1e3, n_s + 1)
    total, _, _ = np.histogram2d(x, yy[inside] * 1e3, [x_edges, y_edges], weights=load[inside])
    count, _, _ = np.histogram2d(x, yy[inside] * 1e3, [x_edges, y_edges])
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(count > 0, total / count, np.nan)
    mesh = a0.pcolormesh(x_edges, y_edges, mean.T, cmap="viridis", shading="flat")
    fig.colorbar(mesh, ax=a0, label="normal line load (N/mm)")
    first = inside[0]
    for j in range(first.shape[0]):
        sel = first[j]
        if sel.any():
            a0.plot((c.position[0, j, sel] - s_a) * 1e3, c.face[sel] * 1e3, color="tab:red",
                    lw=1.2, ls="--", label="contact lines at phase 0" if j == 0 else None)
    a0.set_xlim(0.0, pair.path_of_contact * 1e3)
    a0.set_ylim(0.0, pair.face_width * 1e3)
    a0.set_xlabel("roll distance from start of contact A (mm)")
    a0.set_ylabel("face position (mm)")
    head = f"{title}: " if title else ""
    a0.set_title(f"{head}T1 = {c.torque[0]:.6g} N m, eps_alpha = {pair.contact_ratio:.3f}, "
                 f"eps_beta = {pair.overlap_ratio:.3f}; peak {c.max_pressure[0] / 1e6:.0f} MPa",
                 fontsize=9)
    a1.plot(c.phase, c.deflection[0] * 1e6, "-o", ms=2.5, label="loaded static TE")
    a1.plot(c.phase, c.unloaded * 1e6, "--", label="unloaded (gap of the modifications)")
    a1.set_xlabel("mesh phase (cycles; 0 = a contact line enters at A on the front face)")
    a1.set_ylabel("static TE (µm)")
    a1.legend(fontsize=8)
    a1.grid(alpha=0.3)
    tidy(fig)
    return fig


def plot_slice_stiffness(cases: Mapping[str, SliceCase], ax: Any = None) -> Any:
    """Secant mesh stiffness F_t / delta and loaded static TE over one mesh cycle, all cases
    (slice loaded contact). ``ax``: 2 Axes or None."""
    fig, axs = axes_of(ax, 2, 1, figsize=(8, 7), name="plot_slice_stiffness", sharex=True)
    for (name, case), st in zip(cases.items(), _styles(len(cases)), strict=True):
        c = case.contact
        axs[0].plot(c.phase, c.secant_stiffness[0] / 1e6, label=name, **st)
        axs[1].plot(c.phase, c.deflection[0] * 1e6, label=name, **st)
    return _labelled(fig, axs, ("loaded mesh stiffness F_t / delta (N/µm)",
                                "loaded static TE (µm)"),
                     "mesh phase (cycles; 0 = a contact line enters at A on the front face)")


def plot_relief_study(study: ReliefStudy, ax: Any = None) -> Any:
    """PPTE and peak Hertz pressure of every design against torque; the best design (lowest
    PPTE over the range) drawn bold. With the study's dynamics, a right-hand column: peak mesh
    force F_max / W and p-p DTE against speed (rpm), the design with the lowest peak force over
    the range drawn bold. ``ax``: 2 Axes (4 with dynamics, row-major) or None."""
    dyn = study.dynamics
    if dyn is None:
        fig, axs = axes_of(ax, 2, 1, figsize=(8, 7), name="plot_relief_study", sharex=True)
        left = axs
    else:
        fig, grid = axes_of(ax, 2, 2, figsize=(14, 7), name="plot_relief_study", sharex="col")
        grid = np.asarray(grid).reshape(2, 2)
        left, right = grid[:, 0], grid[:, 1]
    best = study.best
    styles = _styles(len(study.names))
    for (i, name), st in zip(enumerate(study.names), styles, strict=True):
        style = {**st, "lw": 2.6} if name == best else st
        label = f"{name} (best)" if name == best else name
        left[0].plot(study.torque, study.ppte[i] * 1e6, marker="o", ms=3, label=label, **style)
        left[1].plot(study.torque, study.peak_pressure[i] / 1e6, marker="o", ms=3, label=label,
                     **style)
    if dyn is not None:
        rpm = dyn.speed * 30 / np.pi
        for (i, name), st in zip(enumerate(dyn.names), styles, strict=True):
            top = name == dyn.best
            style = {**st, "lw": 2.6} if top else st
            label = f"{name} (lowest peak force)" if top else name
            right[0].plot(rpm, dyn.peak_force_ratio[i], label=label, **style)
            right[1].plot(rpm, dyn.ptp_dte[i] * 1e6, label=label, **style)
        right[0].set_title(f"single-DOF steady state at T1 = {dyn.torque:.6g} N m", fontsize=9)
        _labelled(fig, right, ("peak mesh force F_max / W", "p-p dynamic TE (µm)"),
                  "pinion speed (rpm)")
    return _labelled(fig, left, ("p-p loaded static TE (µm)", "peak Hertz pressure (MPa)"),
                     "pinion torque T1 (N m)")
