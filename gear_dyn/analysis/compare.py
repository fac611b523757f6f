"""Design comparison: several sweeps over the same speeds, ranked by physical figures.

Designs of one pair (two tip reliefs, two accuracy grades, two backlash values) are ranked by
the peak dynamic mesh force over the static load, F_max / W, the figure the teeth carry. The
dynamic factor K_dyn = F_max / F_qs,max is kept as a column, but it is divided by each design's
own quasi-static peak, so it does not rank designs: a tip relief lowers F_qs,max and may raise
K_dyn while lowering F_max. Beside the peak force: the RMS DTE and, where the scene's loaded
contact gives it, the peak Hertz contact stress. Each figure is given at the design's operating
speed and as its peak over the range (value, speed in rpm, direction), with its difference from
the first design (the baseline), absolute and in per cent. Flags say where a peak cannot be
trusted as the design's peak: at an end of the range (the true peak may lie beyond), or where a
linear model's mesh force goes negative (the teeth would separate: the model is invalid there).

The scene layer sweeps the scenes (:func:`gear_dyn.scene.compare.compare_scenes`); here the
figures are taken from the sweeps. The figure is :func:`gear_dyn.plots.compare.plot_comparison`
(``comparison.plot(ax=None)``; the plots module is looked up by name when called, so the
analysis layer imports no plots).
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.dynamic_factor import DYNAMIC_FACTOR_DEFINITION
from gear_dyn.analysis.sweep.types import RPM, SweepCurve, SweepResult
from gear_dyn.errors import InputError

FloatArray = NDArray[np.float64]

#: the module that draws a Comparison; looked up by name at call time
PLOTS_MODULE = "gear_dyn.plots.compare"

#: what each figure of the table is
DEFINITIONS: dict[str, str] = {
    "peak_force_ratio": "F_max / W: peak dynamic mesh force over the static load W = T1 / r_b1 "
                        "(ranks the designs: lower is better)",
    "dynamic_factor": DYNAMIC_FACTOR_DEFINITION + "; divided by each design's own quasi-static "
                      "peak, so it does not rank designs",
    "rms_dte_m": "RMS of the dynamic transmission error (mean removed), m",
    "contact_stress_pa": "peak Hertz contact stress, Pa: the quasi-static peak of the loaded "
                         "contact times sqrt(K_dyn) (the dynamic factor multiplies the load "
                         "under the square root, as K_v does in ISO 6336-2:2019 sigma_H); NaN "
                         "where the scene's loaded contact is not known",
    "delta": "value minus the baseline's (the first design); delta_pct = 100 (value / "
             "baseline - 1)",
    "operating": "at the design's own operating speed ([operating] speed); the larger of the "
                 "sweep directions where orbits coexist",
    "peak": "largest over the swept speeds and directions, with its speed (rpm) and direction",
}

#: flag code -> what it means (the flags a row can carry)
FLAGS: dict[str, str] = {
    "peak_at_range_end": "the peak F_max / W lies at an end of the swept range: the design's "
                         "peak may lie beyond it; widen the range",
    "linear_model_invalid_at_peak": "the mesh force of this linear model goes negative at its "
                                    "peak (the teeth would separate): the model is invalid "
                                    "there; add [backlash]",
    "linear_model_invalid_in_range": "the mesh force of this linear model goes negative at some "
                                     "swept speeds (not at the peak): the model is invalid "
                                     "there; add [backlash]",
    "teeth_separate_at_peak": "the teeth leave contact at the peak (backlash model: "
                              "vibro-impact, sensitive to the gap and the damping)",
    "unstable_speeds": "parametric instability at some speeds (no bounded response there)",
    "operating_speed_outside_range": "the operating speed lies outside the swept range (its "
                                     "values come from a separate one-speed sweep)",
}

#: (quantity of the row, SweepCurve attribute) for the figures compared
_QUANTITIES = (("peak_force_ratio", "peak_force_ratio"), ("dynamic_factor", "dynamic_factor"),
               ("rms_dte_m", "rms_dte"))


def _delta(value: float, base: float) -> tuple[float, float]:
    """(value - base, 100 (value / base - 1)); the per cent NaN where base is 0 or NaN."""
    d = value - base
    pct = 100.0 * (value / base - 1.0) if base != 0 and math.isfinite(base) else math.nan
    return d, pct


def _at_speed(curves: Sequence[SweepCurve], attr: str, speed: float) -> float:
    """The largest finite value of ``attr`` over ``curves`` at pinion ``speed`` (rad/s);
    NaN where no curve has that speed."""
    vals = []
    for c in curves:
        hit = np.flatnonzero(np.isclose(c.speed, speed, rtol=1e-9, atol=0.0))
        vals += [float(getattr(c, attr)[i]) for i in hit]
    vals = [v for v in vals if math.isfinite(v)]
    return max(vals) if vals else math.nan


def _peak_index(result: SweepResult) -> tuple[SweepCurve | None, int]:
    """The curve and index of the largest finite F_max / W (None, -1 without one)."""
    best: tuple[SweepCurve | None, int] = (None, -1)
    top = -math.inf
    for c in result.curves:
        y = np.where(np.isfinite(c.peak_force_ratio), c.peak_force_ratio, -np.inf)
        if y.size and np.max(y) > top:
            top, best = float(np.max(y)), (c, int(np.argmax(y)))
    return best


def _flags(result: SweepResult, operating_in_range: bool) -> list[str]:
    """The flag codes (:data:`FLAGS`) of one design's sweep."""
    out = []
    c, i = _peak_index(result)
    speeds = np.concatenate([cv.speed for cv in result.curves])
    sep_any = any(np.any(np.nan_to_num(cv.separation) > 0) for cv in result.curves)
    if c is not None:
        if speeds.size > 1 and (np.isclose(c.speed[i], speeds.min(), rtol=1e-12, atol=0.0)
                                or np.isclose(c.speed[i], speeds.max(), rtol=1e-12, atol=0.0)):
            out.append("peak_at_range_end")
        sep = float(np.nan_to_num(c.separation[i])) > 0
        if sep and not result.nonlinear:
            out.append("linear_model_invalid_at_peak")
        elif sep:
            out.append("teeth_separate_at_peak")
        elif sep_any and not result.nonlinear:
            out.append("linear_model_invalid_in_range")
    if any(s == "unstable" for cv in result.curves for s in cv.status):
        out.append("unstable_speeds")
    if not operating_in_range:
        out.append("operating_speed_outside_range")
    return out


def _ranks(values: Sequence[float]) -> list[int | None]:
    """1 for the lowest finite value, 2 for the next ...; None for NaN."""
    finite = [(v, k) for k, v in enumerate(values) if math.isfinite(v)]
    out: list[int | None] = [None] * len(values)
    for r, (_, k) in enumerate(sorted(finite), start=1):
        out[k] = r
    return out


def design_row(name: str, result: SweepResult, operating_speed: float,
               operating: SweepResult | None = None, static_stress: float = math.nan,
               iso_kv_at_peak: float = math.nan) -> dict[str, Any]:
    """The figures of one design (no deltas, no ranks:
    :func:`~gear_dyn.analysis.compare.compare_sweeps` adds them).

    Parameters
    ----------
    name : str
    result : SweepResult
        The design's sweep.
    operating_speed : float
        Its operating pinion speed in rad/s.
    operating : SweepResult or None
        A sweep that holds ``operating_speed`` where ``result`` does not (outside its range).
    static_stress : float
        Quasi-static peak Hertz contact stress in Pa (NaN: unknown).
    iso_kv_at_peak : float
        ISO 6336-1 K_v at the speed of the peak force (NaN: none).

    Returns
    -------
    dict
        Keys with their units; ``flags`` a list of :data:`FLAGS` codes.
    """
    row: dict[str, Any] = {"scene": name, "operating_speed_rpm": operating_speed / RPM,
                           "static_load_n": result.static_load,
                           "stiffness_jump_factor": result.stiffness_jump_factor}
    in_range = any(np.any(np.isclose(c.speed, operating_speed, rtol=1e-9, atol=0.0))
                   for c in result.curves)
    at_op = result if in_range or operating is None else operating
    k_op = _at_speed(at_op.curves, "dynamic_factor", operating_speed)
    for key, attr in _QUANTITIES:
        row[f"operating_{key}"] = _at_speed(at_op.curves, attr, operating_speed)
        p = result.peak(attr)
        row[f"peak_{key}"] = p.value
        row[f"peak_{key}_speed_rpm"] = p.speed_rpm
        row[f"peak_{key}_direction"] = p.direction
    # K_dyn at the speed of the peak force (the same speed: one constant apart)
    c, i = _peak_index(result)
    row["dynamic_factor_at_peak_force"] = (float(c.dynamic_factor[i]) if c is not None
                                           else math.nan)
    row["iso_6336_kv_at_peak_force"] = iso_kv_at_peak
    row["static_contact_stress_pa"] = static_stress
    # sigma_H ~ sqrt(F): the dynamic peak where K_dyn peaks (ISO 6336-2 form)
    row["operating_contact_stress_pa"] = static_stress * math.sqrt(k_op) if k_op >= 0 \
        else math.nan
    kmax = row["peak_dynamic_factor"]
    row["peak_contact_stress_pa"] = (static_stress * math.sqrt(kmax) if kmax >= 0
                                     else math.nan)
    row["peak_contact_stress_pa_speed_rpm"] = row["peak_dynamic_factor_speed_rpm"]
    row["flags"] = _flags(result, in_range or operating is None)
    return row


#: the figures that get deltas against the baseline and ranks
COMPARED = ("operating_peak_force_ratio", "peak_peak_force_ratio", "operating_rms_dte_m",
            "peak_rms_dte_m", "operating_contact_stress_pa", "peak_contact_stress_pa")


@dataclass(frozen=True, eq=False, repr=False)
class Comparison:
    """Designs compared by physical figures (:func:`~gear_dyn.analysis.compare.compare_sweeps`).

    Made by :func:`~gear_dyn.scene.compare.compare_scenes`; each parameter is kept as the attribute
    of that name.

    Parameters
    ----------
    names : tuple of str
        The designs, the first is the baseline.
    sweeps : tuple of SweepResult
        One per design, over the same speeds (each with its own operating speed added where it
        lies inside the range).
    designs : tuple of dict
        One per design, in input order: the figures at the operating speed
        (``operating_*``) and over the range (``peak_*`` with ``*_speed_rpm`` and
        ``*_direction``), ``*_delta`` and ``*_delta_pct`` against the baseline, ``rank``
        (by peak F_max / W, 1 = lowest), ``rank_rms_dte`` and ``rank_contact_stress``, and
        ``flags`` (codes of :data:`FLAGS`). :data:`DEFINITIONS` says what each figure is.
    speed_range_rpm : (float, float)
        The swept range.
    warnings : tuple of str
        The sweeps' warnings and one line per flag, for the terminal.

    Attributes
    ----------
    baseline : str
        The first design's name.
    ranking : tuple of str
        The designs by peak F_max / W, lowest first.

    See Also
    --------
    :func:`~gear_dyn.scene.compare.compare_scenes` : Makes it from scenes.
    :class:`~gear_dyn.analysis.sweep.types.SweepResult` : One design's sweep.

    Examples
    --------
    >>> import gear_dyn as gd
    >>> def design(ratio):  # the helicopter tail pair at damping ratio ``ratio``
    ...     return gd.parse_scene({
    ...         "scene": {"name": f"xi={ratio}", "model": "sdof"},
    ...         "gear": {"teeth_pinion": 23, "teeth_gear": 64, "module": "6 mm",
    ...                  "pressure_angle": "22.5 deg", "face_width": "50 mm"},
    ...         "operating": {"speed": "3319 rpm", "torque": "1474.4 N*m"},
    ...         "damping": {"ratio": ratio}})
    >>> cmp = gd.compare_scenes([design(0.06), design(0.1)], "3000 rpm:3600 rpm:3")
    >>> cmp.baseline, cmp.ranking  # more damping, lower peak force
    ('xi=0.06', ('xi=0.1', 'xi=0.06'))
    """

    names: tuple[str, ...]
    sweeps: tuple[SweepResult, ...]
    designs: tuple[dict[str, Any], ...]
    speed_range_rpm: tuple[float, float]
    warnings: tuple[str, ...] = ()

    @property
    def baseline(self) -> str:
        """The first design's name."""
        return self.names[0]

    @property
    def ranking(self) -> tuple[str, ...]:
        """The designs by peak F_max / W, lowest first (designs without a finite peak last)."""
        rank = [d["rank"] for d in self.designs]
        order = sorted(range(len(rank)), key=lambda k: (rank[k] is None, rank[k] or 0))
        return tuple(self.names[k] for k in order)

    def rows(self) -> list[dict[str, Any]]:
        """The rows in rank order, flags joined by ``;`` (what :meth:`to_csv` writes).

        Returns
        -------
        list of dict
            One per design, best first; SI units (and rpm) in the key names.

        See Also
        --------
        :meth:`~gear_dyn.analysis.compare.Comparison.to_csv` : Writes it.

        Examples
        --------
        >>> import gear_dyn as gd
        >>> def design(ratio):  # the helicopter tail pair at damping ratio ``ratio``
        ...     return gd.parse_scene({
        ...         "scene": {"name": f"xi={ratio}", "model": "sdof"},
        ...         "gear": {"teeth_pinion": 23, "teeth_gear": 64, "module": "6 mm",
        ...                  "pressure_angle": "22.5 deg", "face_width": "50 mm"},
        ...         "operating": {"speed": "3319 rpm", "torque": "1474.4 N*m"},
        ...         "damping": {"ratio": ratio}})
        >>> cmp = gd.compare_scenes([design(0.06), design(0.1)], "3000 rpm:3600 rpm:3")
        >>> [row["scene"] for row in cmp.rows()]
        ['xi=0.1', 'xi=0.06']
        """
        by_name = {r["scene"]: r for r in self.designs}
        return [{**by_name[n], "flags": ";".join(by_name[n]["flags"])} for n in self.ranking]

    def to_dict(self) -> dict[str, Any]:
        """Everything for compare.json: designs, baseline, ranking, rows, definitions, flags
        with their meaning, warnings (numbers in SI, speeds in rpm).

        Returns
        -------
        dict
            JSON-able.

        See Also
        --------
        :meth:`~gear_dyn.analysis.compare.Comparison.rows` : The rows in rank order.

        Examples
        --------
        >>> import gear_dyn as gd
        >>> def design(ratio):  # the helicopter tail pair at damping ratio ``ratio``
        ...     return gd.parse_scene({
        ...         "scene": {"name": f"xi={ratio}", "model": "sdof"},
        ...         "gear": {"teeth_pinion": 23, "teeth_gear": 64, "module": "6 mm",
        ...                  "pressure_angle": "22.5 deg", "face_width": "50 mm"},
        ...         "operating": {"speed": "3319 rpm", "torque": "1474.4 N*m"},
        ...         "damping": {"ratio": ratio}})
        >>> cmp = gd.compare_scenes([design(0.06), design(0.1)], "3000 rpm:3600 rpm:3")
        >>> cmp.to_dict()["baseline"]
        'xi=0.06'
        """
        return {"scenes": list(self.names), "baseline": self.baseline,
                "ranking": list(self.ranking), "ranked_by": "peak_peak_force_ratio",
                "speed_range_rpm": list(self.speed_range_rpm),
                "n_speeds": int(self.sweeps[0].curves[0].speed.size),
                "designs": [dict(r) for r in self.designs],
                "definitions": DEFINITIONS,
                "flags": {code: FLAGS[code] for code in
                          dict.fromkeys(f for r in self.designs for f in r["flags"])},
                "warnings": list(self.warnings)}

    def to_csv(self, path: str | Path) -> Path:
        """Write :meth:`rows` as CSV (one row per design, rank order) atomically.

        Parameters
        ----------
        path : str or Path
            The file to write (replaced if it exists).

        Returns
        -------
        Path
            The file written.

        See Also
        --------
        :meth:`~gear_dyn.analysis.compare.Comparison.to_dict` : The same for JSON.

        Examples
        --------
        >>> import tempfile
        >>> from pathlib import Path
        >>> import gear_dyn as gd
        >>> def design(ratio):  # the helicopter tail pair at damping ratio ``ratio``
        ...     return gd.parse_scene({
        ...         "scene": {"name": f"xi={ratio}", "model": "sdof"},
        ...         "gear": {"teeth_pinion": 23, "teeth_gear": 64, "module": "6 mm",
        ...                  "pressure_angle": "22.5 deg", "face_width": "50 mm"},
        ...         "operating": {"speed": "3319 rpm", "torque": "1474.4 N*m"},
        ...         "damping": {"ratio": ratio}})
        >>> cmp = gd.compare_scenes([design(0.06), design(0.1)], "3000 rpm:3600 rpm:3")
        >>> with tempfile.TemporaryDirectory() as folder:
        ...     path = cmp.to_csv(Path(folder) / "compare.csv")
        ...     len(path.read_text().splitlines())  # header and two designs
        3
        """
        from gear_dyn.io import write_rows

        return write_rows(path, self.rows())

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """The comparison figure (:func:`gear_dyn.plots.compare.plot_comparison`: ``ax`` None
        or its 3 Axes); returns the Figure.

        Parameters
        ----------
        ax : sequence of 3 matplotlib.axes.Axes or None
            Where to draw; None makes a new figure.
        **kwargs
            Passed to :func:`gear_dyn.plots.compare.plot_comparison`.

        Returns
        -------
        matplotlib.figure.Figure
            The figure drawn on.

        See Also
        --------
        :attr:`~gear_dyn.analysis.sweep.types.SweepResult.plot` : One design's sweep.

        Examples
        --------
        >>> import matplotlib.pyplot as plt
        >>> import gear_dyn as gd
        >>> def design(ratio):  # the helicopter tail pair at damping ratio ``ratio``
        ...     return gd.parse_scene({
        ...         "scene": {"name": f"xi={ratio}", "model": "sdof"},
        ...         "gear": {"teeth_pinion": 23, "teeth_gear": 64, "module": "6 mm",
        ...                  "pressure_angle": "22.5 deg", "face_width": "50 mm"},
        ...         "operating": {"speed": "3319 rpm", "torque": "1474.4 N*m"},
        ...         "damping": {"ratio": ratio}})
        >>> cmp = gd.compare_scenes([design(0.06), design(0.1)], "3000 rpm:3600 rpm:3")
        >>> fig = cmp.plot()
        >>> plt.close(fig)
        """
        plots = importlib.import_module(PLOTS_MODULE)
        return plots.plot_comparison(self, ax=ax, **kwargs)

    def __repr__(self) -> str:
        lines = [f"Comparison of {len(self.names)} designs over {self.speed_range_rpm[0]:.0f}-"
                 f"{self.speed_range_rpm[1]:.0f} rpm, baseline {self.baseline!r}, by peak F/W:"]
        by_name = {r["scene"]: r for r in self.designs}
        for n in self.ranking:
            r = by_name[n]
            lines.append(f"  {r['rank']}. {n}: F/W {r['peak_peak_force_ratio']:.4g} at "
                         f"{r['peak_peak_force_ratio_speed_rpm']:.0f} rpm "
                         f"({r['peak_peak_force_ratio_delta_pct']:+.1f} %)"
                         + (f" [{', '.join(r['flags'])}]" if r["flags"] else ""))
        return "\n".join(lines)


def compare_sweeps(sweeps: Sequence[SweepResult], names: Sequence[str],
                   operating_speeds: Sequence[float],
                   operating: Sequence[SweepResult | None] | None = None,
                   static_stress: Sequence[float] | None = None,
                   iso_kv_at_peak: Sequence[float] | None = None) -> Comparison:
    """Rank designs by their peak F_max / W and compare them with the first (the baseline).

    Parameters
    ----------
    sweeps : sequence of SweepResult
        One per design, over the same speed range.
    names : sequence of str
        Unique names, one per sweep; the first is the baseline.
    operating_speeds : sequence of float
        Each design's operating pinion speed in rad/s.
    operating : sequence of (SweepResult or None), optional
        Per design, a sweep holding its operating speed where its main sweep does not.
    static_stress : sequence of float, optional
        Quasi-static peak Hertz contact stress per design in Pa (NaN: unknown).
    iso_kv_at_peak : sequence of float, optional
        ISO 6336-1 K_v at each design's peak-force speed (NaN: none).

    Returns
    -------
    Comparison

    Raises
    ------
    InputError
        No sweeps, names not unique, or sequences of different lengths.
    """
    n = len(sweeps)
    if n == 0:
        raise InputError("compare: no designs given (at least 1 scene)")
    if len(set(names)) != len(names):
        raise InputError(f"compare: design names must be unique, got {list(names)}")
    nan = [math.nan] * n
    ops = list(operating) if operating is not None else [None] * n
    stress = list(static_stress) if static_stress is not None else nan
    kv = list(iso_kv_at_peak) if iso_kv_at_peak is not None else nan
    if not len(names) == len(operating_speeds) == len(ops) == len(stress) == len(kv) == n:
        raise InputError("compare: one name, operating speed, stress and K_v per sweep")
    rows = [design_row(*args) for args in zip(names, sweeps, operating_speeds, ops, stress, kv,
                                             strict=True)]
    base = rows[0]
    for r in rows:
        for key in COMPARED:
            r[f"{key}_delta"], r[f"{key}_delta_pct"] = _delta(r[key], base[key])
    for key, rank in (("peak_peak_force_ratio", "rank"), ("peak_rms_dte_m", "rank_rms_dte"),
                      ("peak_contact_stress_pa", "rank_contact_stress")):
        for r, k in zip(rows, _ranks([r[key] for r in rows]), strict=True):
            r[rank] = k
    speeds = np.concatenate([c.speed for s in sweeps for c in s.curves]) / RPM
    warnings = [w for s in sweeps for w in s.warnings]
    warnings += [f"{r['scene']}: {FLAGS[f]}" for r in rows for f in r["flags"]]
    return Comparison(tuple(names), tuple(sweeps), tuple(rows),
                      (float(speeds.min()), float(speeds.max())), tuple(warnings))


__all__ = ["COMPARED", "DEFINITIONS", "FLAGS", "Comparison", "compare_sweeps", "design_row"]
