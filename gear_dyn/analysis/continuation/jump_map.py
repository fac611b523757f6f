"""Result objects of the two-parameter fold continuation: the jump region in (speed, torque).

A :class:`JumpRegion` is the band of speeds between the two folds that bound one unstable
stretch of the response curve (the two ends of a hysteresis loop), followed over torque; where
the two folds meet (a cusp) the band and the jumps end. A :class:`FoldMap` holds the regions
and the folds found at every torque. The figure is :func:`~gear_dyn.plots.fold_map.plot_fold_map`
(``fold_map.plot(ax=None)``; the plots module is looked up by name when called,
so the analysis layer imports no plots).
"""

from __future__ import annotations

import importlib
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: the module that draws a fold map; looked up by name at call time
PLOTS_MODULE = "gear_dyn.plots.fold_map"


@dataclass(frozen=True)
class Cusp:
    """Where the two fold curves of a region meet and the jumps end.

    Attributes
    ----------
    speed : float
        Pinion speed (rad/s): the mean of the two folds at the last torque that has them.
    torque : float
        Pinion torque (N m): the middle of the final bracket.
    torque_error : float
        Half the final torque bracket (N m): the cusp lies within ``torque +- torque_error``
        (a bound, from the bisection).
    half_gap : float
        Half the speed gap between the two folds at the bracket's end that has them (rad/s).
        Not a bound on the error of ``speed``: the fold curves move with torque across the
        bracket, so the cusp's speed can lie further from ``speed`` than this (no speed error
        is stated for a cusp).
    """

    speed: float
    torque: float
    torque_error: float
    half_gap: float


@dataclass(frozen=True, eq=False)
class JumpRegion:
    """One band of coexisting orbits over torque, bounded by two fold curves.

    Attributes
    ----------
    torque : ndarray (N,)
        Torques (N m) at which the band was found, increasing.
    low, high : ndarray (N,)
        Speeds (rad/s) of its lower and upper fold at each torque, each located on the speed
        branch at that torque to the continuation's ``locate_tol``.
    low_error, high_error : ndarray (N,)
        Stated speed errors of the two folds (rad/s).
    cusps : tuple of Cusp
        Cusps ending the band at its lower or upper torque end (none where it reaches the end
        of the torque range).
    low_stability, high_stability : tuple of str (N,)
        Stability of the speed branch before and after each fold, in order along the branch
        (``stable->unstable`` or ``unstable->stable``); empty where not recorded.
    """

    torque: FloatArray
    low: FloatArray
    high: FloatArray
    low_error: FloatArray
    high_error: FloatArray
    cusps: tuple[Cusp, ...] = ()
    low_stability: tuple[str, ...] = ()
    high_stability: tuple[str, ...] = ()

    def contains(self, speed: float, torque: float) -> bool:
        """True where ``(speed, torque)`` lies between the two fold curves (linear
        interpolation in torque between the computed torques)."""
        if not self.torque[0] <= torque <= self.torque[-1]:
            return False
        lo = float(np.interp(torque, self.torque, self.low))
        hi = float(np.interp(torque, self.torque, self.high))
        return lo <= speed <= hi


@dataclass(frozen=True, eq=False)
class FoldMap:
    """The jump regions of a scene or model in the (speed, torque) plane.

    Made by :func:`~gear_dyn.analysis.continuation.fold_curve.fold_map`; each parameter is kept as
    the attribute of that name.

    Parameters
    ----------
    regions : tuple of JumpRegion
        Each region of coexisting orbits: its fold curves (rad/s against N m) and its cusp.
    torques : ndarray
        Every torque (N m) at which a speed branch was followed, increasing (the requested
        ones and those added to bracket cusps).
    speed_range : (float, float)
        The speed window (rad/s) of the branches.
    folds : tuple of tuple of float
        The fold speeds (rad/s) found at each of ``torques``, in order along the branch.
    reference_torque : float or None
        The scene's own torque (N m), marked on the figure.
    n_maps : int
        n-period maps computed over all branches (cost).
    natural_frequency : float
        f_n of the model (Hz; the stiffness and mass do not change with torque); NaN where
        unknown.
    mesh_per_speed : float
        Mesh frequency per pinion speed, f_m / omega = z1 / (2 pi) (Hz per rad/s).
    locate_tol : float
        Relative tolerance to which each fold's speed was located (the continuation's).

    Attributes
    ----------
    cusps : list of Cusp
        All cusps, in order of the regions.

    See Also
    --------
    :func:`~gear_dyn.analysis.continuation.fold_curve.fold_map` : Makes it.
    :class:`~gear_dyn.analysis.continuation.branch.Branch` : One speed branch.

    Examples
    --------
    >>> from gear_dyn import (SDOFModel, SpeedTorqueFamily, fold_map, rectangular_stiffness,
    ...                       sdof_family)
    >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
    ...               backlash=1e-3)
    >>> fam = SpeedTorqueFamily(sdof_family(m, "speed", teeth=20), torque_ref=52.0)
    >>> fmap = fold_map(fam, (43.0, 44.5), [50.0, 52.0], cusp_bisections=0)
    >>> fmap.torques  # N m
    array([50., 52.])
    >>> len(fmap.folds)  # one tuple of fold speeds per torque
    2
    """

    regions: tuple[JumpRegion, ...]
    torques: FloatArray
    speed_range: tuple[float, float]
    folds: tuple[tuple[float, ...], ...]
    reference_torque: float | None = None
    n_maps: int = 0
    natural_frequency: float = float("nan")
    mesh_per_speed: float = float("nan")
    locate_tol: float = float("nan")

    @property
    def cusps(self) -> list[Cusp]:
        """All cusps, in order of the regions."""
        return [c for r in self.regions for c in r.cusps]

    def coexisting(self, speed: float, torque: float) -> bool:
        """True where two or more orbits coexist (inside any region): a sweep jumps there.

        Parameters
        ----------
        speed : float
            Pinion speed in rad/s.
        torque : float
            Pinion torque in N m.

        Returns
        -------
        bool
            Inside a jump region.

        See Also
        --------
        :meth:`~gear_dyn.analysis.continuation.jump_map.FoldMap.plot` : The regions drawn.

        Examples
        --------
        >>> from gear_dyn import (SDOFModel, SpeedTorqueFamily, fold_map, rectangular_stiffness,
        ...                       sdof_family)
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
        ...               backlash=1e-3)
        >>> fam = SpeedTorqueFamily(sdof_family(m, "speed", teeth=20), torque_ref=52.0)
        >>> fmap = fold_map(fam, (43.0, 44.5), [50.0, 52.0], cusp_bisections=0)
        >>> fmap.coexisting(43.5, 51.0)  # one fold in the window: no closed region
        False
        """
        return any(r.contains(speed, torque) for r in self.regions)

    def __repr__(self) -> str:
        t = self.torques
        cusp = "; ".join(f"cusp at {c.speed:.6g} rad/s, {c.torque:.6g} N*m" for c in self.cusps)
        return (f"FoldMap({len(self.regions)} jump regions, torque {t.min():.6g}.."
                f"{t.max():.6g} N*m at {t.size} torques, speed {self.speed_range[0]:.6g}.."
                f"{self.speed_range[1]:.6g} rad/s{'; ' + cusp if cusp else ''})")

    def _speed(self, speed: float) -> dict[str, float]:
        """A speed in rad/s and rpm, and its f_m / f_n."""
        return {"speed_rad_s": speed, "speed_rpm": speed * 60 / (2 * math.pi),
                "frequency_ratio": speed * self.mesh_per_speed / self.natural_frequency}

    def rows(self) -> list[dict[str, Any]]:
        """One row per fold (``kind`` ``low``/``high``: the region's lower or upper fold) and
        per cusp (``kind`` ``cusp``), for CSV and JSON: the speed in rad/s and rpm, f_m / f_n
        (``frequency_ratio``), the fold's stated speed error and the relative tolerance it was
        located to (``locate_tol``), the stability of the branch before and after it, and for
        a cusp its torque error (a bound) and the half gap of the folds at the last torque
        with the loop (``fold_half_gap_rad_s``; not a bound on the cusp's speed error, which
        is not stated: NaN).

        Returns
        -------
        list of dict
            SI units (and rpm) in the key names.

        See Also
        --------
        :meth:`~gear_dyn.analysis.continuation.jump_map.FoldMap.to_dict`
            The rows with the map's summary.

        Examples
        --------
        >>> from gear_dyn import (SDOFModel, SpeedTorqueFamily, fold_map, rectangular_stiffness,
        ...                       sdof_family)
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
        ...               backlash=1e-3)
        >>> fam = SpeedTorqueFamily(sdof_family(m, "speed", teeth=20), torque_ref=52.0)
        >>> fmap = fold_map(fam, (43.0, 44.5), [50.0, 52.0], cusp_bisections=0)
        >>> fmap.rows()  # no closed jump region in this window
        []
        """
        nan = math.nan
        out: list[dict[str, Any]] = []
        for i, r in enumerate(self.regions):
            for k, t in enumerate(r.torque):
                for kind, speed, err, stab in (("low", r.low, r.low_error, r.low_stability),
                                               ("high", r.high, r.high_error,
                                                r.high_stability)):
                    out.append({"region": i, "kind": kind, "torque_n_m": float(t),
                                **self._speed(float(speed[k])),
                                "speed_error_rad_s": float(err[k]),
                                "locate_tol": self.locate_tol,
                                "stability": stab[k] if stab else "",
                                "torque_error_n_m": 0.0, "fold_half_gap_rad_s": nan})
            for c in r.cusps:
                out.append({"region": i, "kind": "cusp", "torque_n_m": c.torque,
                            **self._speed(c.speed), "speed_error_rad_s": nan,
                            "locate_tol": self.locate_tol, "stability": "",
                            "torque_error_n_m": c.torque_error,
                            "fold_half_gap_rad_s": c.half_gap})
        return out

    def to_csv(self, path: str | Path) -> Path:
        """Write :meth:`rows` as CSV (fold_curve.csv) atomically; with no fold, the header
        ``region`` alone.

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
        :meth:`~gear_dyn.analysis.continuation.jump_map.FoldMap.to_dict` : The same for JSON.

        Examples
        --------
        >>> import tempfile
        >>> from pathlib import Path
        >>> from gear_dyn import (SDOFModel, SpeedTorqueFamily, fold_map, rectangular_stiffness,
        ...                       sdof_family)
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
        ...               backlash=1e-3)
        >>> fam = SpeedTorqueFamily(sdof_family(m, "speed", teeth=20), torque_ref=52.0)
        >>> fmap = fold_map(fam, (43.0, 44.5), [50.0, 52.0], cusp_bisections=0)
        >>> with tempfile.TemporaryDirectory() as folder:
        ...     text = fmap.to_csv(Path(folder) / "fold_curve.csv").read_text()
        >>> len(text.splitlines()) == len(fmap.rows()) + 1  # header and one line per fold
        True
        """
        from gear_dyn.io import write_rows

        return write_rows(path, self.rows(), empty=["region"])

    def to_dict(self) -> dict[str, Any]:
        """JSON-able: the speed window, f_n, torques, folds per torque, cusps and rows.

        Returns
        -------
        dict
            Plain numbers and strings, SI units (and rpm) in the key names.

        See Also
        --------
        :meth:`~gear_dyn.analysis.continuation.jump_map.FoldMap.rows` : The rows alone.

        Examples
        --------
        >>> from gear_dyn import (SDOFModel, SpeedTorqueFamily, fold_map, rectangular_stiffness,
        ...                       sdof_family)
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
        ...               backlash=1e-3)
        >>> fam = SpeedTorqueFamily(sdof_family(m, "speed", teeth=20), torque_ref=52.0)
        >>> fmap = fold_map(fam, (43.0, 44.5), [50.0, 52.0], cusp_bisections=0)
        >>> fmap.to_dict()["torques_n_m"]
        [50.0, 52.0]
        """
        return {"speed_range_rad_s": list(self.speed_range),
                "speed_range_rpm": [s * 60 / (2 * math.pi) for s in self.speed_range],
                "natural_frequency_hz": self.natural_frequency,
                "locate_tol": self.locate_tol,
                "torques_n_m": [float(t) for t in self.torques],
                "folds_rad_s": [list(f) for f in self.folds],
                "reference_torque_n_m": self.reference_torque,
                "cusps": [{**c.__dict__, **self._speed(c.speed)} for c in self.cusps],
                "rows": self.rows()}

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """The jump map (:func:`gear_dyn.plots.fold_map.plot_fold_map`): regions shaded, fold
        curves drawn, cusps marked; returns the Figure.

        Parameters
        ----------
        ax : matplotlib.axes.Axes or None
            Where to draw; None makes a new figure.
        **kwargs
            Passed to :func:`gear_dyn.plots.fold_map.plot_fold_map`.

        Returns
        -------
        matplotlib.figure.Figure
            The figure drawn on.

        See Also
        --------
        :meth:`~gear_dyn.analysis.continuation.branch.Branch.plot`
            One speed branch's response curve.

        Examples
        --------
        >>> import matplotlib.pyplot as plt
        >>> from gear_dyn import (SDOFModel, SpeedTorqueFamily, fold_map, rectangular_stiffness,
        ...                       sdof_family)
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
        ...               backlash=1e-3)
        >>> fam = SpeedTorqueFamily(sdof_family(m, "speed", teeth=20), torque_ref=52.0)
        >>> fmap = fold_map(fam, (43.0, 44.5), [50.0, 52.0], cusp_bisections=0)
        >>> fig = fmap.plot()
        >>> plt.close(fig)
        """
        return importlib.import_module(PLOTS_MODULE).plot_fold_map(self, ax=ax, **kwargs)
