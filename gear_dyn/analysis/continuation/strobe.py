"""Stroboscopic samples of a branch's orbits: the bifurcation diagram of the continuation.

A period-n orbit crosses the section ``t = 0 mod T_m`` (T_m = 1/f_m) at n states: its start
state ``y(0)``, which every :class:`~.branch.OrbitPoint` holds, and ``y(T_m), ...,
y((n-1) T_m)``, which are not stored. :func:`branch_samples` gets them by one run of the orbit's
flow over n-1 mesh periods per point of a period-n branch (n > 1), sampled once per mesh period
(:func:`gear_dyn.analysis.motion.flow_periods`: the exact flow where it applies, else DOP853 at
``rtol``); period-1 points cost nothing. Drawn against the parameter, these are the samples of a
brute-force bifurcation diagram (:mod:`gear_dyn.analysis.motion.diagram`) for the stable
orbits, and also show the unstable ones that no integration settles on (Kahraman & Singh 1990;
Parker & Chua 1989, ch. 6).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.continuation.branch import Branch, OrbitPoint
from gear_dyn.analysis.motion.samples import flow_periods
from gear_dyn.errors import check_range

FloatArray = NDArray[np.float64]

#: the module that draws :class:`BranchSamples`, looked up by name when plotted
PLOTS_MODULE = "gear_dyn.plots.bifurcation"


def orbit_samples(point: OrbitPoint, family: Callable[[float], Any], rtol: float = 1e-10
                  ) -> FloatArray:
    """The n stroboscopic samples of a period-n orbit point: states at t = k T_m, k < n.

    Parameters
    ----------
    point : OrbitPoint
        A converged orbit (its ``state`` at t = 0 and its ``periods`` n).
    family : callable
        ``value -> model``, the family the branch was continued in (the model at
        ``point.parameter`` is built from it; unused for period 1).
    rtol : float
        Relative tolerance of DOP853 where the exact flow does not apply (1e-13..1e-4).

    Returns
    -------
    ndarray (n, n_states)
        Row k: the state at t = k T_m (SI: m, m/s); row 0 is ``point.state``. The map over one
        mesh period sends row k to row k + 1 and the last row back to row 0, to the shooting
        tolerance of the branch.

    Raises
    ------
    InputError
        ``rtol`` out of range.
    SolverError
        The run failed.
    """
    check_range("rtol", rtol, "", low=1e-13, high=1e-4)
    y0 = np.asarray(point.state, dtype=float)
    if point.periods == 1:
        return y0[None, :].copy()
    return flow_periods(family(point.parameter), y0, point.periods - 1, rtol).T.copy()


@dataclass(frozen=True, eq=False)
class BranchCurve:
    """One branch's stroboscopic samples, in branch order.

    Attributes
    ----------
    branch : Branch
        The branch (its own points; children are separate curves).
    samples : ndarray (n_points, n, n_states)
        ``samples[i, k]``: state of point i at t = k T_m (SI).
    marks : tuple of (str, float, ndarray (n, n_states))
        Its folds and period doublings: kind, parameter (SI) and the located orbit's samples.
    """

    branch: Branch
    samples: FloatArray
    marks: tuple[tuple[str, float, FloatArray], ...]

    @property
    def parameter(self) -> FloatArray:
        """Parameter of each point (SI)."""
        return self.branch.array("parameter")


@dataclass(frozen=True, eq=False)
class BranchSamples:
    """Stroboscopic samples of a branch and its children (:func:`branch_samples`).

    Attributes
    ----------
    parameter_name, unit : str
        The continuation parameter and its SI unit (from the branch).
    curves : tuple of BranchCurve
        The branch and its children, depth first (as
        :meth:`~gear_dyn.analysis.continuation.branch.Branch.walk`).
    n_maps : int
        Runs of the flow made for the samples (one per point and located point of a period-n
        branch, n > 1), a cost measure.
    """

    parameter_name: str
    unit: str
    curves: tuple[BranchCurve, ...]
    n_maps: int

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """Draw the samples against the parameter
        (:func:`gear_dyn.plots.bifurcation.plot_branch_samples`; ``kwargs`` as there, e.g.
        ``diagram``, ``state``). Returns the Figure."""
        plots = importlib.import_module(PLOTS_MODULE)
        return plots.plot_branch_samples(self, ax=ax, **kwargs)

    def _columns(self) -> dict[str, FloatArray]:
        cols: dict[str, list[FloatArray]] = {"branch": [], "point": [], "parameter": [],
                                             "stable": [], "sample": []}
        for i, c in enumerate(self.curves):
            n_p, n_s, n_y = c.samples.shape
            stable = np.array([p.stable for p in c.branch.points], dtype=float)
            cols["branch"].append(np.full(n_p * n_s, float(i)))
            cols["point"].append(np.repeat(np.arange(n_p, dtype=float), n_s))
            cols["parameter"].append(np.repeat(c.parameter, n_s))
            cols["stable"].append(np.repeat(stable, n_s))
            cols["sample"].append(np.tile(np.arange(n_s, dtype=float), n_p))
            for k in range(n_y):
                cols.setdefault(f"state_{k}", []).append(c.samples[:, :, k].ravel())
        return {k: np.concatenate(v) if v else np.zeros(0) for k, v in cols.items()}

    def rows(self) -> list[dict[str, float]]:
        """One row per branch, point and sample: ``branch`` (index, depth first), ``point``,
        ``parameter`` (SI, in ``unit``), ``stable`` (1 or 0), ``sample`` (k: t = k T_m) and
        each state component ``state_0``, ``state_1`` ... (SI: m, m/s).

        Returns
        -------
        list of dict
            Plain floats.
        """
        from gear_dyn.io import column_rows

        return column_rows(self._columns())

    def to_csv(self, path: str | Path) -> Path:
        """Write :meth:`rows` as CSV atomically; returns the file written."""
        from gear_dyn.io import write_csv

        return write_csv(path, self._columns())

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: the parameter and its unit, the flow runs made, per branch its period,
        points and located folds and period doublings (with the located orbit's samples), and
        :meth:`rows`.

        Returns
        -------
        dict
            Plain numbers, lists and strings; SI values.
        """
        return {"parameter": self.parameter_name, "unit": self.unit, "n_maps": self.n_maps,
                "branches": [{"index": i, "periods": c.branch.periods,
                              "n_points": int(c.samples.shape[0]),
                              "marks": [{"kind": kind, "parameter": float(par),
                                         "samples": np.asarray(at, dtype=float).tolist()}
                                        for kind, par, at in c.marks]}
                             for i, c in enumerate(self.curves)],
                "rows": self.rows()}


def branch_samples(branch: Branch, family: Callable[[float], Any], rtol: float = 1e-10
                   ) -> BranchSamples:
    """The stroboscopic samples of every orbit of ``branch`` and its children.

    Parameters
    ----------
    branch : Branch
        From :func:`gear_dyn.analysis.continuation.continue_orbits`.
    family : callable
        The ``value -> model`` family it was continued in.
    rtol : float
        Relative tolerance where the exact flow does not apply (use the continuation's
        ``ContinuationSettings.rtol``; 1e-13..1e-4).

    Returns
    -------
    BranchSamples

    Raises
    ------
    InputError
        ``rtol`` out of range.
    SolverError
        A run failed.

    Examples
    --------
    >>> import math
    >>> from gear_dyn import SDOFModel, rectangular_stiffness
    >>> from gear_dyn.analysis.continuation import continue_orbits, sdof_family
    >>> k = rectangular_stiffness(1.6, 8e5, 1.2e6)
    >>> fam = sdof_family(SDOFModel(1.0, k, 0.05, 1040.0, 100.0, backlash=1e-3), "speed",
    ...                   teeth=20)
    >>> wn = math.sqrt(k.mean)
    >>> s = branch_samples(continue_orbits(fam, 0.84 * wn / 20, 0.85 * wn / 20), fam)
    >>> s.curves[0].samples.shape[1:]  # one sample per mesh period of a period-1 orbit
    (1, 2)
    """
    check_range("rtol", rtol, "", low=1e-13, high=1e-4)
    curves = []
    n_maps = 0
    for b in branch.walk():
        n = b.periods
        if b.points:
            samples = np.array([orbit_samples(p, family, rtol) for p in b.points])
        else:
            samples = np.zeros((0, max(n, 1), 2))
        marks = tuple((x.kind, x.parameter, orbit_samples(x.point, family, rtol))
                      for x in b.bifurcations if x.kind in ("fold", "period_doubling"))
        if n > 1:
            n_maps += len(b.points) + len(marks)
        curves.append(BranchCurve(b, samples, marks))
    return BranchSamples(branch.parameter_name, branch.unit, tuple(curves), n_maps)
