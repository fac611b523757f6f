"""Result objects of a continuation: points of a branch, located bifurcations, the branch.

A :class:`Branch` is a sequence of :class:`OrbitPoint` (each with its Floquet multipliers,
stability verdict, Liouville check and contact pattern) and the :class:`Bifurcation` points
located on it; branches switched to at period doublings are its ``children``. Rows for CSV
and JSON come from :meth:`Branch.rows`; the figure is
:func:`~gear_dyn.plots.continuation.plot_branch` (``branch.plot(ax=None)``, which looks the plots
module up by name when called:
importing this module loads no matplotlib, and the analysis layer imports no plots).
"""

from __future__ import annotations

import importlib
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.stability import OrbitShape, PeriodicSolution

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: the module that draws a branch; looked up by name at call time
PLOTS_MODULE = "gear_dyn.plots.continuation"
#: kinds of located points
KINDS = ("fold", "period_doubling", "branch_point", "grazing")
#: rpm per rad/s (a pinion speed of 1 rad/s is 60 / (2 pi) rpm)
RPM_PER_RAD_S = 60 / (2 * math.pi)


@dataclass(frozen=True, eq=False)
class OrbitPoint:
    """One periodic orbit on a branch: the orbit
    (:class:`~gear_dyn.analysis.stability.PeriodicSolution`, with its shape) and where on the
    branch it lies. The orbit's fields read through (``point.state``, ``point.stable`` ...).

    Parameters
    ----------
    parameter : float
        Value of the continuation parameter (SI: rad/s, N m, -, m).
    orbit : PeriodicSolution
        The orbit: ``y0``, ``periods``, ``monodromy``, ``multipliers``, the corrector's
        ``iterations`` and scaled ``residual`` (``how`` is ``continuation``) and its
        ``shape`` (contact pattern, shares, DTE measures).
    liouville : float
        ``|det M / exp(-c n T / m_e) - 1|`` (-).
    liouville_ok : bool
        ``liouville`` within the run's ``liouville_tol``; False flags a doubtful monodromy.
    mesh_frequency : float
        Mesh frequency f_m of the model at this point (Hz).
    arclength : float
        Scaled arclength from the branch start.
    tangent_p : float
        Parameter component of the unit tangent (its sign change marks a fold).
    dp_error : float
        Estimated relative error of the parameter derivative ``dP/dp`` the tangent was built
        from (the exact speed column's rounding bound, secant columns' agreement, or the
        central difference's one-sided disagreement; nan where not computed).

    Attributes
    ----------
    state : ndarray (2,)
        Orbit state [x (m), v (m/s)] at t = 0 (mesh phase ``phase0``).
    periods : int
        Mesh periods n of the orbit (period-n).
    multipliers : ndarray of complex (2,)
        Floquet multipliers of the n-period map.
    stable : bool
        All multipliers inside the unit circle
        (:func:`gear_dyn.analysis.stability.floquet_stable`).
    spectral_radius : float
        Largest multiplier modulus.
    residual : float
        Scaled closing residual of the shooting equations.
    iterations : int
        Corrector iterations.
    pattern : str
        Contact pattern (``D`` drive, ``G`` gap, ``B`` back flank), e.g. ``DGD``.
    separation, back : float
        Shares of the period with the teeth apart and on the back flank.
    dte_rms, dte_ptp, dte_mean : float
        Standard deviation, peak-to-peak and mean of the DTE over the orbit (m).
    """

    parameter: float
    orbit: PeriodicSolution
    liouville: float
    liouville_ok: bool
    mesh_frequency: float
    arclength: float
    tangent_p: float
    dp_error: float = float("nan")

    @property
    def state(self) -> FloatArray:
        """Orbit state [x (m), v (m/s)] at t = 0."""
        return self.orbit.y0

    @property
    def periods(self) -> int:
        """Mesh periods n of the orbit."""
        return self.orbit.periods

    @property
    def multipliers(self) -> ComplexArray:
        """Floquet multipliers of the n-period map."""
        return self.orbit.multipliers

    @property
    def stable(self) -> bool:
        """All multipliers inside the unit circle (the orbit's verdict)."""
        return self.orbit.stable

    @property
    def spectral_radius(self) -> float:
        """Largest multiplier modulus."""
        return self.orbit.spectral_radius

    @property
    def residual(self) -> float:
        """Scaled closing residual of the shooting equations."""
        return self.orbit.residual

    @property
    def iterations(self) -> int:
        """Corrector iterations."""
        return self.orbit.iterations

    @property
    def shape(self) -> OrbitShape:
        """Contact pattern, contact shares and DTE measures of the orbit."""
        if self.orbit.shape is None:
            raise ValueError("OrbitPoint: the orbit has no shape")  # made with one always
        return self.orbit.shape

    @property
    def pattern(self) -> str:
        """Contact pattern, e.g. ``DGD``."""
        return self.shape.pattern

    @property
    def separation(self) -> float:
        """Share of the period with the teeth apart."""
        return self.shape.separation

    @property
    def back(self) -> float:
        """Share of the period on the back flank."""
        return self.shape.back

    @property
    def dte_rms(self) -> float:
        """Standard deviation of the DTE over the orbit (m)."""
        return self.shape.dte_rms

    @property
    def dte_ptp(self) -> float:
        """Peak-to-peak DTE over the orbit (m)."""
        return self.shape.dte_ptp

    @property
    def dte_mean(self) -> float:
        """Mean DTE over the orbit (m)."""
        return self.shape.dte_mean

    def row(self) -> dict[str, Any]:
        """Flat, JSON- and CSV-able fields (multipliers as real and imaginary parts)."""
        mu = np.asarray(self.multipliers)
        return {
            "parameter": self.parameter, "mesh_frequency_hz": self.mesh_frequency,
            "periods": self.periods, "x0_m": float(self.state[0]),
            "v0_m_per_s": float(self.state[1]),
            "mu1_re": float(mu[0].real), "mu1_im": float(mu[0].imag),
            "mu2_re": float(mu[1].real), "mu2_im": float(mu[1].imag),
            "spectral_radius": self.spectral_radius, "stable": self.stable,
            "liouville_residual": self.liouville, "liouville_ok": self.liouville_ok,
            "residual": self.residual, "pattern": self.pattern,
            "separation_share": self.separation, "back_share": self.back,
            "dte_rms_m": self.dte_rms, "dte_ptp_m": self.dte_ptp, "dte_mean_m": self.dte_mean,
            "arclength": self.arclength, "tangent_p": self.tangent_p,
            "iterations": self.iterations, "dp_error": self.dp_error,
        }


@dataclass(frozen=True, eq=False)
class Bifurcation:
    """A located special point of a branch.

    Attributes
    ----------
    kind : str
        ``fold`` (a real multiplier through +1 where the branch turns back in the
        parameter), ``period_doubling`` (a multiplier through -1), ``branch_point`` (through
        +1 without turning) or ``grazing`` (the contact pattern changes).
    point : OrbitPoint
        The orbit at the located point.
    parameter_error : float
        Stated error of ``point.parameter`` (SI): the parameter's largest change over the
        final bracket of the root finder plus the corrector's remaining Newton step
        (:meth:`.detect.StepCurve.located_error`); at most about ``locate_tol`` relative.
    before, after : str
        Contact patterns on either side (grazing), else the stability before and after
        (``stable`` / ``unstable``).
    """

    kind: str
    point: OrbitPoint
    parameter_error: float
    before: str = ""
    after: str = ""

    @property
    def parameter(self) -> float:
        """Located parameter value (SI)."""
        return self.point.parameter

    def row(self) -> dict[str, Any]:
        """Flat fields for JSON/CSV (the multipliers as in :meth:`OrbitPoint.row`)."""
        mu = self.point.row()
        return {"kind": self.kind, "parameter": self.parameter,
                "parameter_error": self.parameter_error, "periods": self.point.periods,
                "before": self.before, "after": self.after,
                **{k: mu[k] for k in ("mu1_re", "mu1_im", "mu2_re", "mu2_im")}}


@dataclass(frozen=True, eq=False)
class Branch:
    """A branch of period-n orbits followed by pseudo-arclength continuation.

    Made by :func:`~gear_dyn.analysis.continuation.arclength.continue_orbits`; each parameter is
    kept as the attribute of that name.

    Parameters
    ----------
    parameter_name : str
        ``speed`` (rad/s), ``torque`` (N m), ``damping_ratio`` or ``backlash`` (m), or the name
        given for a custom family.
    unit : str
        SI unit of the parameter.
    points : tuple of OrbitPoint
        The orbits along the branch, in order (parameter, state, Floquet multipliers,
        stability, DTE figures in m).
    bifurcations : tuple of Bifurcation
        In order along the branch.
    children : tuple of Branch
        Period-2n branches switched to at this branch's period doublings.
    route : str
        ``exact`` or ``variational``: how the monodromy matrices were computed.
    stop_reason : str
        Why the continuation ended (``left the range at ...``, ``max_points``, ...).
    n_maps : int
        n-period maps computed (with or without sensitivity), a cost measure.
    natural_frequency : float
        f_n = sqrt(k_m / m_e) / (2 pi) of the model at the branch's start (Hz; NaN where
        unknown): the rows' ``frequency_ratio`` is f_m / f_n.

    Attributes
    ----------
    periods : int
        Mesh periods n of the branch's orbits.
    liouville_failures : int
        Points whose monodromy matrix fails the Liouville check.

    See Also
    --------
    :func:`~gear_dyn.analysis.continuation.arclength.continue_orbits` : Makes it.
    :class:`~gear_dyn.analysis.continuation.jump_map.FoldMap` : Fold points followed over torque.

    Examples
    --------
    >>> from gear_dyn import SDOFModel, continue_orbits, rectangular_stiffness, sdof_family
    >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
    ...               backlash=1e-3)
    >>> branch = continue_orbits(sdof_family(m, "speed", teeth=20), 43.0, 44.5)
    >>> branch.periods, branch.parameter_name, branch.unit
    (1, 'speed', 'rad/s')
    >>> branch.stop_reason  # past the fold, back down to the start speed
    'left the range at speed = 43'
    >>> [b.kind for b in branch.bifurcations]
    ['grazing', 'fold']
    """

    parameter_name: str
    unit: str
    points: tuple[OrbitPoint, ...]
    bifurcations: tuple[Bifurcation, ...]
    children: tuple[Branch, ...] = ()
    route: str = "exact"
    stop_reason: str = ""
    n_maps: int = 0
    natural_frequency: float = float("nan")

    def __len__(self) -> int:
        return len(self.points)

    @property
    def periods(self) -> int:
        """Mesh periods n of the branch's orbits."""
        return self.points[0].periods if self.points else 0

    def array(self, name: str) -> FloatArray:
        """One field of every point as an array, e.g. ``branch.array("parameter")``.

        Parameters
        ----------
        name : str
            A field of :class:`~gear_dyn.analysis.continuation.branch.OrbitPoint`
            (``parameter`` in the branch's unit, ``dte_rms`` in m, ``stable`` ...).

        Returns
        -------
        ndarray
            One value per point, in order along the branch.

        See Also
        --------
        :meth:`~gear_dyn.analysis.continuation.branch.Branch.rows`
            Every field of every point, as dicts.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, continue_orbits, rectangular_stiffness, sdof_family
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
        ...               backlash=1e-3)
        >>> branch = continue_orbits(sdof_family(m, "speed", teeth=20), 43.0, 44.5)
        >>> p = branch.array("parameter")  # rad/s
        >>> float(p[0]), float(p.max()) < 43.96  # from the start up to the fold
        (43.0, True)
        """
        return np.array([getattr(p, name) for p in self.points], dtype=float)

    def of_kind(self, kind: str) -> list[Bifurcation]:
        """The located points of one kind (:data:`~gear_dyn.analysis.continuation.branch.KINDS`).

        Parameters
        ----------
        kind : str
            ``fold``, ``period_doubling``, ``grazing`` ... (the bifurcations' ``kind``).

        Returns
        -------
        list of Bifurcation
            In order along the branch (empty if none).

        See Also
        --------
        :meth:`~gear_dyn.analysis.continuation.branch.Branch.array` : One field of every point.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, continue_orbits, rectangular_stiffness, sdof_family
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
        ...               backlash=1e-3)
        >>> branch = continue_orbits(sdof_family(m, "speed", teeth=20), 43.0, 44.5)
        >>> [round(b.point.parameter, 4) for b in branch.of_kind("fold")]  # rad/s
        [43.9572]
        """
        return [b for b in self.bifurcations if b.kind == kind]

    @property
    def liouville_failures(self) -> int:
        """Points whose monodromy matrix fails the Liouville check."""
        return sum(not p.liouville_ok for p in self.points)

    def __repr__(self) -> str:
        if not self.points:
            return f"Branch({self.parameter_name}, no points; {self.stop_reason})"
        p = self.array("parameter")
        counts = ", ".join(f"{k} {len(self.of_kind(k))}" for k in KINDS if self.of_kind(k))
        return (f"Branch(period-{self.periods}, {self.parameter_name} {p.min():.6g}.."
                f"{p.max():.6g} {self.unit}, {len(self.points)} points, "
                f"{sum(x.stable for x in self.points)} stable"
                f"{', ' + counts if counts else ''}"
                f"{', ' + str(len(self.children)) + ' child branches' if self.children else ''}"
                f", route {self.route}; {self.stop_reason})")

    def rows(self, recursive: bool = True) -> list[dict[str, Any]]:
        """One row per point (children's after this branch's with ``recursive``), with the
        branch's index in ``branch``, f_m / f_n in ``frequency_ratio`` and, for a speed
        branch, the speed in both units (``speed_rad_s``, ``speed_rpm``).

        Parameters
        ----------
        recursive : bool
            Include the rows of the children (depth first).

        Returns
        -------
        list of dict
            For CSV and JSON; SI units in the key names.

        See Also
        --------
        :meth:`~gear_dyn.analysis.continuation.branch.Branch.to_dict`
            The rows with the branch's summary.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, continue_orbits, rectangular_stiffness, sdof_family
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
        ...               backlash=1e-3)
        >>> branch = continue_orbits(sdof_family(m, "speed", teeth=20), 43.0, 44.5)
        >>> round(branch.rows()[0]["speed_rpm"], 1)
        410.6
        """
        out: list[dict[str, Any]] = []
        for i, b in enumerate(self.walk() if recursive else [self]):
            out.extend({"branch": i, **p.row(), **self._units(p)} for p in b.points)
        return out

    def _units(self, point: OrbitPoint) -> dict[str, float]:
        """f_m / f_n of a point, and its speed in rad/s and rpm on a speed branch."""
        out = {"frequency_ratio": point.mesh_frequency / self.natural_frequency}
        if self.parameter_name == "speed":
            out |= {"speed_rad_s": point.parameter, "speed_rpm": point.parameter * RPM_PER_RAD_S}
        return out

    def walk(self) -> list[Branch]:
        """This branch and its children, depth first.

        Returns
        -------
        list of Branch
            This branch first.

        See Also
        --------
        :meth:`~gear_dyn.analysis.continuation.branch.Branch.rows`
            The rows of this branch and its children.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, continue_orbits, rectangular_stiffness, sdof_family
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
        ...               backlash=1e-3)
        >>> branch = continue_orbits(sdof_family(m, "speed", teeth=20), 43.0, 44.5)
        >>> len(branch.walk())  # no period doubling here: no children
        1
        """
        out = [self]
        for c in self.children:
            out.extend(c.walk())
        return out

    def to_dict(self) -> dict[str, Any]:
        """JSON-able summary: parameter, f_n, route, stop reason, located points (with
        f_m / f_n and, on a speed branch, the speed in rad/s and rpm) and all rows.

        Returns
        -------
        dict
            Plain numbers and strings, SI units in the key names.

        See Also
        --------
        :meth:`~gear_dyn.analysis.continuation.branch.Branch.rows` : The rows alone.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, continue_orbits, rectangular_stiffness, sdof_family
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
        ...               backlash=1e-3)
        >>> branch = continue_orbits(sdof_family(m, "speed", teeth=20), 43.0, 44.5)
        >>> branch.to_dict()["parameter"]
        'speed'
        """
        return {
            "parameter": self.parameter_name, "unit": self.unit,
            "natural_frequency_hz": self.natural_frequency,
            "branches": [
                {"index": i, "periods": b.periods, "route": b.route,
                 "stop_reason": b.stop_reason, "n_points": len(b.points),
                 "liouville_failures": b.liouville_failures,
                 "bifurcations": [{**x.row(), **self._units(x.point)} for x in b.bifurcations]}
                for i, b in enumerate(self.walk())],
            "points": self.rows(),
        }

    def to_csv(self, path: str | Path) -> Path:
        """Write :meth:`rows` (this branch and its children) as CSV (branch.csv) atomically.

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
        :meth:`~gear_dyn.analysis.continuation.branch.Branch.to_dict` : The same for JSON.

        Examples
        --------
        >>> import tempfile
        >>> from pathlib import Path
        >>> from gear_dyn import SDOFModel, continue_orbits, rectangular_stiffness, sdof_family
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
        ...               backlash=1e-3)
        >>> branch = continue_orbits(sdof_family(m, "speed", teeth=20), 43.0, 44.5)
        >>> with tempfile.TemporaryDirectory() as folder:
        ...     text = branch.to_csv(Path(folder) / "branch.csv").read_text()
        >>> len(text.splitlines()) == len(branch.rows()) + 1  # header and one line per point
        True
        """
        from gear_dyn.io import write_rows

        return write_rows(path, self.rows())

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """The response curve (:func:`gear_dyn.plots.continuation.plot_branch`): stable
        solid, unstable dashed, folds and period doublings marked with their parameter value;
        returns the Figure.

        Parameters
        ----------
        ax : matplotlib.axes.Axes or None
            Where to draw; None makes a new figure.
        **kwargs
            Passed to :func:`gear_dyn.plots.continuation.plot_branch`.

        Returns
        -------
        matplotlib.figure.Figure
            The figure drawn on.

        See Also
        --------
        :meth:`~gear_dyn.analysis.continuation.jump_map.FoldMap.plot` : The jump map.

        Examples
        --------
        >>> import matplotlib.pyplot as plt
        >>> from gear_dyn import SDOFModel, continue_orbits, rectangular_stiffness, sdof_family
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
        ...               backlash=1e-3)
        >>> branch = continue_orbits(sdof_family(m, "speed", teeth=20), 43.0, 44.5)
        >>> fig = branch.plot()
        >>> plt.close(fig)
        """
        return importlib.import_module(PLOTS_MODULE).plot_branch(self, ax=ax, **kwargs)

