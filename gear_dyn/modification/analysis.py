"""Relief cases side by side: loaded contact, load sharing and contact stress along the path,
and the table row each case contributes (what ``gear-dyn contact`` and the examples report):
the spur loaded contact (:class:`~gear_dyn.modification.analysis.ReliefCase`) or the slice
method for any pair with lead
modifications and misalignment (:class:`~gear_dyn.modification.analysis.SliceCase`)."""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.geometry import GearPair
from gear_dyn.modification.contact import LoadedContact, PathView, loaded_contact
from gear_dyn.modification.lead import FlankModification
from gear_dyn.modification.relief import (
    RULES,
    ProfileModification,
    height_from_length,
    recommended_relief,
)
from gear_dyn.modification.slice_contact import SliceContact, SliceOptions, slice_contact
from gear_dyn.modification.stress import contact_stress

FloatArray = NDArray[np.float64]

#: the module that draws a ReliefStudy; looked up by name at call time (never imported on load,
#: as :class:`gear_dyn.solvers.result.ResultPlots` does for runs)
PLOTS_MODULE = "gear_dyn.plots.contact"


@dataclass(frozen=True)
class ReliefCase:
    """Loaded-contact results of one relief case.

    Attributes
    ----------
    name : str
    modification : ProfileModification or None
    contact : LoadedContact
    path : PathView
        Load sharing along the path of contact.
    stress, half_width : ndarray
        Hertz contact stress (Pa) and half-width (m) along ``path.position``.
    """

    name: str
    modification: ProfileModification | None
    contact: LoadedContact
    path: PathView
    stress: FloatArray
    half_width: FloatArray

    def row(self) -> dict[str, Any]:
        """Table row: amounts, lengths, heights, peak stress, static TE, single-contact zone.

        Positions are in m from T1 along the line of action (``*_from_a_m``: from the start of
        contact A). Keys carry their SI unit.
        """
        pair = self.contact.pair
        out: dict[str, Any] = {"case": self.name, "method": "spur loaded contact"}
        out |= relief_columns(pair, self.modification)
        out["peak_stress_pa"] = float(np.max(self.stress))
        out["peak_to_peak_static_te_m"] = self.contact.peak_to_peak_error
        out["mean_static_te_m"] = float(np.mean(self.contact.static_transmission_error().value(
            np.linspace(0, 1, 2001, endpoint=False))))
        out["mean_loaded_stiffness_n_per_m"] = self.contact.mesh_stiffness().mean
        zone = self.contact.single_contact_zone()
        s_a = pair.start_of_contact
        out["single_contact_start_m"] = None if zone is None else zone[0]
        out["single_contact_end_m"] = None if zone is None else zone[1]
        out["single_contact_start_from_a_m"] = None if zone is None else zone[0] - s_a
        out["single_contact_end_from_a_m"] = None if zone is None else zone[1] - s_a
        return out

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: :meth:`row` (the case's figures) and the series along the path of
        contact (:meth:`rows` as lists). SI units in the key names."""
        return {**self.row(), "path": {k: v.tolist() for k, v in self.path_columns().items()}}

    def path_columns(self) -> dict[str, FloatArray]:
        """Along the path of contact: ``s_from_a_m`` (m from the start of contact A), the load
        sharing ``sharing`` and the Hertz contact stress ``stress_pa``."""
        s_a = self.contact.pair.start_of_contact
        return {"s_from_a_m": self.path.position - s_a, "sharing": self.path.sharing,
                "stress_pa": self.stress}

    def rows(self) -> list[dict[str, float]]:
        """One row per position along the path of contact (:meth:`path_columns` as dicts of
        plain floats): the case's columns of path.csv."""
        from gear_dyn.io import column_rows

        return column_rows(self.path_columns())

    def to_csv(self, path: str | Path) -> Path:
        """Write :meth:`rows` as CSV atomically; returns the file written."""
        from gear_dyn.io import write_csv

        return write_csv(path, self.path_columns())

    def plot(self, ax: Any = None) -> Any:
        """Load sharing and Hertz stress along the path of contact
        (:func:`gear_dyn.plots.contact.plot_load_sharing` of this case alone, looked up by
        name; ``ax``: None or 2 Axes); returns the Figure."""
        plots = importlib.import_module(PLOTS_MODULE)
        return plots.plot_load_sharing({self.name: self}, ax=ax)


def relief_columns(pair: GearPair, modification: ProfileModification | None) -> dict[str, Any]:
    """Amount, length, height (m) and curve of each gear's tip relief, as table columns."""
    out: dict[str, Any] = {}
    for gear, name in ((1, "pinion"), (2, "gear")):
        r = None if modification is None else getattr(modification, name)
        out[f"amount_{name}_m"] = 0.0 if r is None else r.amount
        out[f"length_{name}_m"] = 0.0 if r is None else r.length
        out[f"height_{name}_m"] = 0.0 if r is None else height_from_length(pair, gear,
                                                                           r.length)
        out[f"curve_{name}"] = None if r is None else r.curve
    return out


@dataclass(frozen=True)
class SliceCase:
    """Slice-method loaded contact of one design (spur or helical pair).

    Attributes
    ----------
    name : str
    modification : FlankModification
        Tip reliefs, lead modifications and misalignment of the case.
    contact : SliceContact
        Result at one torque (or a ladder: :meth:`row` reports the first torque).
    """

    name: str
    modification: FlankModification
    contact: SliceContact

    def row(self, index: int = 0) -> dict[str, Any]:
        """Table row with the keys of :meth:`ReliefCase.row` (the single-contact zone is None:
        the slice analysis reports load sharing per mesh position instead) plus the tangent
        stiffness and the unloaded TE, at torque ``index`` of the ladder."""
        c = self.contact
        summary = c.summary()[index]
        out: dict[str, Any] = {"case": self.name, "method": "slice LTCA"}
        out |= relief_columns(c.pair, self.modification.profile)
        out |= {k: summary[k] for k in ("peak_stress_pa", "peak_to_peak_static_te_m",
                                        "mean_static_te_m", "mean_loaded_stiffness_n_per_m",
                                        "mean_tangent_stiffness_n_per_m",
                                        "peak_to_peak_unloaded_te_m", "max_sharing")}
        for key in ("single_contact_start_m", "single_contact_end_m",
                    "single_contact_start_from_a_m", "single_contact_end_from_a_m"):
            out[key] = None
        return out


def rule_modifications(pair: GearPair, torque: float, curve: str = "linear",
                       extra: Mapping[str, ProfileModification] | None = None,
                       rule_options: Mapping[str, float] | None = None) -> dict[
                           str, ProfileModification | None]:
    """The designs :func:`rule_cases` compares: the unmodified pair (None), ``extra``, then
    every rule of :data:`~gear_dyn.modification.relief.RULES` with ``curve``."""
    mods: dict[str, ProfileModification | None] = {"unmodified": None}
    mods |= dict(extra or {})
    for rule in RULES:
        rec = recommended_relief(pair, torque, rule, **(rule_options or {}))
        mods[rule] = rec.modification(curve)
    return mods


def slice_cases(pair: GearPair, torque: float | FloatArray,
                designs: Mapping[str, ProfileModification | None],
                lead: FlankModification | None = None,
                pair_stiffness: Callable[[FloatArray], FloatArray] | None = None,
                options: SliceOptions | None = None) -> dict[str, SliceCase]:
    """Slice-method loaded contact of every profile design, each with the lead modifications
    and misalignment of ``lead`` (its ``profile`` is replaced by the design's)."""
    base = lead or FlankModification()
    out = {}
    for name, prof in designs.items():
        mod = replace(base, profile=prof)
        out[name] = SliceCase(name, mod, slice_contact(pair, torque, mod, pair_stiffness,
                                                       options))
    return out


def relief_case(name: str, pair: GearPair, pair_stiffness: Callable[[FloatArray], FloatArray],
                torque: float, modification: ProfileModification | None) -> ReliefCase:
    """Loaded contact, load sharing and Hertz stress of one case (see :class:`ReliefCase`).

    Raises
    ------
    InputError
        As :func:`~gear_dyn.modification.contact.loaded_contact`.
    """
    lc = loaded_contact(pair, pair_stiffness, torque, modification)
    view = lc.along_path()
    sigma, half = contact_stress(pair, view.position, view.force, modification)
    return ReliefCase(name, modification, lc, view, sigma, half)


def rule_cases(pair: GearPair, pair_stiffness: Callable[[FloatArray], FloatArray], torque: float,
               curve: str = "linear", extra: Mapping[str, ProfileModification] | None = None,
               rule_options: Mapping[str, float] | None = None) -> dict[str, ReliefCase]:
    """The unmodified pair, any ``extra`` modifications and every rule of
    :data:`~gear_dyn.modification.relief.RULES`, in that order.

    Parameters
    ----------
    curve : str
        Relief curve used with the rules' amounts and lengths.
    rule_options : mapping or None
        ``handbook_a``, ``handbook_b``, ``face_load_factor`` (see
        :func:`~gear_dyn.modification.relief.recommended_relief`).
    """
    mods = rule_modifications(pair, torque, curve, extra, rule_options)
    return {name: relief_case(name, pair, pair_stiffness, torque, mod)
            for name, mod in mods.items()}


@dataclass(frozen=True, eq=False)
class ReliefDynamics:
    """Dynamic consequence of relief designs: the single-DOF periodic steady state of each
    design's slice loaded contact (tangent stiffness and TE at one torque) over a speed range.

    Attributes
    ----------
    torque : float
        Pinion torque in N m at which each design's loaded contact feeds the model.
    speed : ndarray (N,)
        Pinion speeds in rad/s.
    names : tuple of str
        Design names, in the study's order.
    peak_force_ratio : ndarray (designs, N)
        Peak dynamic mesh force over the cycle divided by the static load W = T1 / r_b1.
    ptp_dte : ndarray (designs, N)
        Peak-to-peak dynamic transmission error in m.
    status : tuple of tuple of str
        The sweep's status per design and speed (``periodic``: the orbit solved directly).
    """

    torque: float
    speed: FloatArray
    names: tuple[str, ...]
    peak_force_ratio: FloatArray
    ptp_dte: FloatArray
    status: tuple[tuple[str, ...], ...]

    @property
    def peak_over_range(self) -> FloatArray:
        """Largest F_max / W over the speed range, per design."""
        return np.max(self.peak_force_ratio, axis=1)

    @property
    def best(self) -> str:
        """The design with the lowest peak mesh force over the speed range."""
        return self.names[int(np.argmin(self.peak_over_range))]

    def rows(self) -> list[dict[str, Any]]:
        """One row per design and speed (SI keys, the speed also in rpm)."""
        out = []
        for i, name in enumerate(self.names):
            for k, w in enumerate(self.speed):
                out.append({"design": name, "torque_n_m": self.torque,
                            "speed_rad_s": float(w), "speed_rpm": float(w * 30 / np.pi),
                            "peak_force_ratio": float(self.peak_force_ratio[i, k]),
                            "ptp_dte_m": float(self.ptp_dte[i, k]),
                            "status": self.status[i][k]})
        return out

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: the speeds, each design's series and peak, the best design."""
        return {"torque_n_m": self.torque, "speed_rad_s": self.speed.tolist(),
                "speed_rpm": (self.speed * 30 / np.pi).tolist(),
                "designs": [{"design": n, "peak_force_ratio": self.peak_force_ratio[i].tolist(),
                             "ptp_dte_m": self.ptp_dte[i].tolist(),
                             "max_peak_force_ratio": float(self.peak_over_range[i])}
                            for i, n in enumerate(self.names)],
                "best": self.best,
                "best_rule": "lowest peak dynamic mesh force F_max / W over the speed range"}

    def to_csv(self, path: str | Path) -> Path:
        """Write :meth:`rows` as CSV (dynamics.csv: one row per design and speed) atomically;
        returns the file written."""
        from gear_dyn.io import write_rows

        return write_rows(path, self.rows())


@dataclass(frozen=True, eq=False)
class ReliefStudy:
    """Relief designs compared over a torque range by the slice loaded contact.

    Attributes
    ----------
    torque : ndarray (T,)
        Pinion torques in N m.
    cases : dict of SliceCase
        Each design's loaded contact over the whole ladder.
    dynamics : ReliefDynamics or None
        Each design's single-DOF response over a speed range at one torque (None: not asked
        for; :func:`gear_dyn.analysis.relief_study.relief_study` with ``speeds``).
    """

    torque: FloatArray
    cases: dict[str, SliceCase]
    dynamics: ReliefDynamics | None = None

    @property
    def names(self) -> list[str]:
        """Design names, in order."""
        return list(self.cases)

    @property
    def ppte(self) -> FloatArray:
        """Peak-to-peak loaded static TE in m (designs, torques)."""
        return np.array([c.contact.peak_to_peak_te for c in self.cases.values()])

    @property
    def peak_pressure(self) -> FloatArray:
        """Largest Hertz pressure over the cycle in Pa (designs, torques)."""
        return np.array([c.contact.max_pressure for c in self.cases.values()])

    @property
    def mean_stiffness(self) -> FloatArray:
        """Mean secant mesh stiffness in N/m (designs, torques)."""
        return np.array([c.contact.mean_secant_stiffness for c in self.cases.values()])

    @property
    def best(self) -> str:
        """The design with the lowest PPTE averaged over the torque range (the ladder's points
        weighted equally)."""
        return self.names[int(np.argmin(self.ppte.mean(axis=1)))]

    def rows(self) -> list[dict[str, Any]]:
        """One row per design and torque (SI keys)."""
        out = []
        for i, name in enumerate(self.names):
            for k, t in enumerate(self.torque):
                out.append({"design": name, "torque_n_m": float(t),
                            "peak_to_peak_static_te_m": float(self.ppte[i, k]),
                            "peak_stress_pa": float(self.peak_pressure[i, k]),
                            "mean_loaded_stiffness_n_per_m": float(self.mean_stiffness[i, k])})
        return out

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary: the ladder, each design's amounts and series, the best design."""
        designs = []
        for i, (name, case) in enumerate(self.cases.items()):
            designs.append({"design": name,
                            **relief_columns(case.contact.pair, case.modification.profile),
                            "peak_to_peak_static_te_m": self.ppte[i].tolist(),
                            "peak_stress_pa": self.peak_pressure[i].tolist(),
                            "mean_loaded_stiffness_n_per_m": self.mean_stiffness[i].tolist(),
                            "mean_ppte_m": float(self.ppte[i].mean())})
        out = {"torque_n_m": self.torque.tolist(), "designs": designs, "best": self.best,
               "best_rule": "lowest peak-to-peak static TE averaged over the torque range"}
        if self.dynamics is not None:
            out["dynamics"] = self.dynamics.to_dict()
        return out

    def to_csv(self, path: str | Path) -> Path:
        """Write :meth:`rows` as CSV (study.csv: one row per design and torque) atomically;
        returns the file written."""
        from gear_dyn.io import write_rows

        return write_rows(path, self.rows())

    def plot(self, ax: Any = None) -> Any:
        """PPTE and peak Hertz pressure against torque, with the dynamics a right-hand column
        of F_max / W and p-p DTE against speed (:func:`gear_dyn.plots.contact.plot_relief_study`,
        looked up by name as ``Result.plot`` does); returns the Figure.

        Parameters
        ----------
        ax : sequence of matplotlib.axes.Axes or None
            2 Axes (4 with dynamics, row-major), or None for a new figure.

        Returns
        -------
        matplotlib.figure.Figure
            The figure drawn on.
        """
        plots = importlib.import_module(PLOTS_MODULE)
        return plots.plot_relief_study(self, ax=ax)
