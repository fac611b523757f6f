"""Result objects of the two-parameter fold continuation: the jump region in (speed, torque).

A :class:`JumpRegion` is the band of speeds between the two folds that bound one unstable
stretch of the response curve (the two ends of a hysteresis loop), followed over torque; where
the two folds meet (a cusp) the band and the jumps end. A :class:`FoldMap` holds the regions
and the folds found at every torque. The figure is :func:`gear_dyn.plots.fold_map.
plot_fold_map` (``fold_map.plot(ax=None)``; the plots module is looked up by name when called,
so the analysis layer imports no plots).
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
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
        Half the final torque bracket (N m): the cusp lies within ``torque +- torque_error``.
    speed_error : float
        Half the speed gap between the two folds at the bracket's end that has them (rad/s).
    """

    speed: float
    torque: float
    torque_error: float
    speed_error: float


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
    """

    torque: FloatArray
    low: FloatArray
    high: FloatArray
    low_error: FloatArray
    high_error: FloatArray
    cusps: tuple[Cusp, ...] = ()

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

    Attributes
    ----------
    regions : tuple of JumpRegion
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
    """

    regions: tuple[JumpRegion, ...]
    torques: FloatArray
    speed_range: tuple[float, float]
    folds: tuple[tuple[float, ...], ...]
    reference_torque: float | None = None
    n_maps: int = 0

    @property
    def cusps(self) -> list[Cusp]:
        """All cusps, in order of the regions."""
        return [c for r in self.regions for c in r.cusps]

    def coexisting(self, speed: float, torque: float) -> bool:
        """True where two or more orbits coexist (inside any region): a sweep jumps there."""
        return any(r.contains(speed, torque) for r in self.regions)

    def __repr__(self) -> str:
        t = self.torques
        cusp = "; ".join(f"cusp at {c.speed:.6g} rad/s, {c.torque:.6g} N*m" for c in self.cusps)
        return (f"FoldMap({len(self.regions)} jump regions, torque {t.min():.6g}.."
                f"{t.max():.6g} N*m at {t.size} torques, speed {self.speed_range[0]:.6g}.."
                f"{self.speed_range[1]:.6g} rad/s{'; ' + cusp if cusp else ''})")

    def rows(self) -> list[dict[str, Any]]:
        """One row per fold (``kind`` ``low``/``high``: the region's lower or upper fold) and
        per cusp (``kind`` ``cusp``), SI units, for CSV and JSON."""
        out: list[dict[str, Any]] = []
        for i, r in enumerate(self.regions):
            for k, t in enumerate(r.torque):
                for kind, speed, err in (("low", r.low, r.low_error),
                                         ("high", r.high, r.high_error)):
                    out.append({"region": i, "kind": kind, "torque_n_m": float(t),
                                "speed_rad_s": float(speed[k]),
                                "speed_error_rad_s": float(err[k]), "torque_error_n_m": 0.0})
            for c in r.cusps:
                out.append({"region": i, "kind": "cusp", "torque_n_m": c.torque,
                            "speed_rad_s": c.speed, "speed_error_rad_s": c.speed_error,
                            "torque_error_n_m": c.torque_error})
        return out

    def to_dict(self) -> dict[str, Any]:
        """JSON-able: the speed window, torques, folds per torque, cusps and rows."""
        return {"speed_range_rad_s": list(self.speed_range),
                "torques_n_m": [float(t) for t in self.torques],
                "folds_rad_s": [list(f) for f in self.folds],
                "reference_torque_n_m": self.reference_torque,
                "cusps": [c.__dict__ for c in self.cusps], "rows": self.rows()}

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """The jump map (:func:`gear_dyn.plots.fold_map.plot_fold_map`): regions shaded, fold
        curves drawn, cusps marked; returns the Figure."""
        return importlib.import_module(PLOTS_MODULE).plot_fold_map(self, ax=ax, **kwargs)
