"""What kind of motion a trajectory settles on: period-n, quasi-periodic or chaotic.

From the stroboscopic samples (one per mesh period after settling,
:mod:`gear_dyn.analysis.motion.samples`):

1. a period n = 1..16 after which the samples repeat (:func:`.period.detect_period`) is
   confirmed by shooting over n mesh periods (:func:`gear_dyn.analysis.stability.shoot`):
   Newton closes the orbit and its Floquet multipliers are inside the unit circle. The label
   is ``period-n`` with n the orbit's least period;
2. otherwise the largest Lyapunov exponent (:mod:`.lyapunov`) is computed, the samples after
   its run tried once more for a period (a slow escape from an unstable orbit shows a positive
   exponent while it lasts), and without one the exponent decides (:func:`lyapunov_kind`; a
   zero exponent is ``quasi-periodic``: the motion on a torus neither grows nor shrinks along
   it, Parker & Chua 1989, sec. 6.3). Where the samples nearly repeat to :data:`.TRY_TOL`
   without a stable orbit, or the exponent is not resolved, a second estimate :data:`LONGER`
   times as long decides: a resolved positive exponent is ``chaotic`` (just past a
   period-doubling cascade the attractor lies in narrow bands around an unstable period-n
   orbit, so its samples nearly repeat after n periods) unless the near repeat loosens by
   more than :data:`GROWTH` over that run (an escape from a saddle orbit); samples still
   repeating otherwise sit near an unstable orbit (a slow escape, or with a negative
   exponent an attracting orbit of more than 16 periods): ``not settled``. Samples beyond
   :data:`UNBOUNDED` state scales are ``unbounded`` (a parametric instability that contact
   loss does not limit).
"""

from __future__ import annotations

import importlib
import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.motion.lyapunov import LyapunovEstimate, largest_lyapunov
from gear_dyn.analysis.motion.period import MAX_PERIOD, repeat_errors
from gear_dyn.analysis.motion.samples import flow_periods, stroboscopic
from gear_dyn.analysis.newton import NewtonSettings
from gear_dyn.analysis.stability import PeriodicSolution, shoot
from gear_dyn.analysis.threads import blas_limited
from gear_dyn.errors import check_range
from gear_dyn.models.base import MeshModel

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: shooting of each period tried, unless the caller gives its own (15 iterations to 100 rtol;
#: the table of :class:`~gear_dyn.analysis.newton.NewtonSettings`)
NEWTON = NewtonSettings()
#: shooting over the least period d from a confirmed n-period orbit (already closed to 1e3 rtol
#: after d periods), for the multipliers over d periods
LEAST_PERIOD_NEWTON = NewtonSettings(max_iter=3)
#: kinds of motion
KINDS = ("periodic", "quasi-periodic", "chaotic", "not settled", "undetermined", "unbounded")
#: a Lyapunov exponent within this many standard errors of zero counts as zero ...
SIGMAS = 3.0
#: ... and so does one below this per mesh period (``abs(lambda T) <= ZERO_BAND``): a stable orbit
#: whose multiplier modulus is within 0.2 % of 1 is not told from a torus by its exponent
ZERO_BAND = 2e-3
#: samples further than this many state scales from zero: the response is unbounded
UNBOUNDED = 1e6
#: repeat error (relative to the state scale) below which a period is tried by shooting
TRY_TOL = 5e-2
#: periods tried by shooting at most, per set of samples
MAX_TRIES = 4
#: where the first exponent leaves the motion open (samples nearly repeating without a stable
#: orbit, or an unresolved exponent), a second estimate runs this many times as long
LONGER = 5
#: ... and near-repeating samples whose repeat error grows more than this over it are leaving
#: a saddle orbit (``not settled``), not on a banded chaotic attractor
GROWTH = 3.0


@dataclass(frozen=True, eq=False)
class Motion:
    """The motion a trajectory settles on.

    Made by :func:`~gear_dyn.analysis.motion.classify.classify_motion`; each parameter is kept as
    the attribute of that name.

    Parameters
    ----------
    kind : str
        One of :data:`~gear_dyn.analysis.motion.classify.KINDS`.
    label : str
        ``period-4``, ``quasi-periodic``, ``chaotic, lambda = 2054 +- 98 1/s`` ...
    state : ndarray
        On a confirmed orbit: its state at t = 0 (mesh phase 0); else the last state reached.
        SI units.
    samples : ndarray (n_samples, n_states)
        The stroboscopic samples classified, SI units.
    orbit : PeriodicSolution or None
        The confirmed orbit over its least period (``kind == "periodic"``), else None.
    lyapunov : LyapunovEstimate or None
        Computed where no orbit was confirmed.
    repeat_error : ndarray
        Relative repeat error of the samples after n = 1..16 periods
        (:func:`.period.repeat_errors`).
    shooting_iterations : int
        Newton iterations spent on confirming periods.

    Attributes
    ----------
    periodic : bool
        A stable orbit of ``period`` mesh periods was confirmed by shooting.
    period : int
        Least period in mesh periods of the confirmed orbit, else 0.
    multipliers : ndarray of complex
        Floquet multipliers of the orbit over its ``period`` mesh periods (empty if none).
    spectral_radius : float
        Largest multiplier modulus of the orbit (NaN without an orbit).

    See Also
    --------
    :func:`~gear_dyn.analysis.motion.classify.classify_motion` : Makes it.
    :class:`~gear_dyn.analysis.motion.diagram.BifurcationDiagram` : Motions over a range of speeds.

    Examples
    --------
    >>> from gear_dyn import SDOFModel, classify_motion, rectangular_stiffness
    >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 136.9,
    ...               backlash=1e-3)
    >>> motion = classify_motion(m, m.initial_state(), settle=20, samples=32)
    >>> motion.periodic, motion.period, motion.spectral_radius < 1  # a stable period-1 orbit
    (True, 1, True)
    """

    kind: str
    label: str
    state: FloatArray
    samples: FloatArray
    orbit: PeriodicSolution | None = None
    lyapunov: LyapunovEstimate | None = None
    repeat_error: FloatArray = field(default_factory=lambda: np.zeros(0))
    shooting_iterations: int = 0

    @property
    def periodic(self) -> bool:
        """A stable orbit of ``period`` mesh periods was confirmed by shooting."""
        return self.kind == "periodic"

    @property
    def period(self) -> int:
        """Least period in mesh periods of the confirmed orbit, else 0."""
        return 0 if self.orbit is None else self.orbit.periods

    @property
    def multipliers(self) -> ComplexArray:
        """Floquet multipliers of the orbit over its ``period`` mesh periods (empty if none)."""
        return np.zeros(0, complex) if self.orbit is None else self.orbit.multipliers

    @property
    def spectral_radius(self) -> float:
        """Largest multiplier modulus of the orbit (NaN without an orbit)."""
        return math.nan if self.orbit is None else self.orbit.spectral_radius

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: kind, label, period, the orbit's multipliers (``[re, im]`` pairs) and
        spectral radius, the Lyapunov exponent and its error (1/s; None where not computed),
        the repeat errors, the state and the Newton iterations.

        Returns
        -------
        dict
            Plain numbers, lists and strings; SI units in the key names (``state_si``: the
            model's state components, x in m and v in m/s for a single-DOF model).

        See Also
        --------
        :meth:`~gear_dyn.analysis.motion.classify.Motion.rows` : The samples.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, classify_motion, rectangular_stiffness
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 136.9,
        ...               backlash=1e-3)
        >>> motion = classify_motion(m, m.initial_state(), settle=20, samples=32)
        >>> motion.to_dict()["label"], motion.to_dict()["period"]
        ('period-1', 1)
        """
        lyap = self.lyapunov
        return {"kind": self.kind, "label": self.label, "periodic": self.periodic,
                "period": self.period,
                "spectral_radius": None if self.orbit is None else self.spectral_radius,
                "multipliers": [[float(z.real), float(z.imag)] for z in self.multipliers],
                "lyapunov_1_s": None if lyap is None else float(lyap.value),
                "lyapunov_error_1_s": None if lyap is None else float(lyap.error),
                "repeat_error": [float(e) for e in self.repeat_error],
                "state_si": [float(y) for y in self.state],
                "n_samples": int(self.samples.shape[0]),
                "shooting_iterations": int(self.shooting_iterations)}

    def rows(self) -> list[dict[str, float]]:
        """One row per stroboscopic sample: ``sample`` (k, at t = k T_m) and each state
        component ``state_0``, ``state_1`` ... in SI units (x in m, v in m/s for a single-DOF
        model).

        Returns
        -------
        list of dict
            Plain floats.

        See Also
        --------
        :meth:`~gear_dyn.analysis.motion.classify.Motion.to_csv` : Writes them.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, classify_motion, rectangular_stiffness
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 136.9,
        ...               backlash=1e-3)
        >>> motion = classify_motion(m, m.initial_state(), settle=20, samples=32)
        >>> len(motion.rows()), list(motion.rows()[0])
        (32, ['sample', 'state_0', 'state_1'])
        """
        from gear_dyn.io import column_rows

        return column_rows(self._columns())

    def _columns(self) -> dict[str, FloatArray]:
        n = self.samples.shape[0]
        return {"sample": np.arange(n, dtype=float),
                **{f"state_{i}": self.samples[:, i] for i in range(self.samples.shape[1])}}

    def to_csv(self, path: str | Path) -> Path:
        """Write :meth:`rows` as CSV atomically.

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
        :meth:`~gear_dyn.analysis.motion.classify.Motion.to_dict` : The same for JSON.

        Examples
        --------
        >>> import tempfile
        >>> from pathlib import Path
        >>> from gear_dyn import SDOFModel, classify_motion, rectangular_stiffness
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 136.9,
        ...               backlash=1e-3)
        >>> motion = classify_motion(m, m.initial_state(), settle=20, samples=32)
        >>> with tempfile.TemporaryDirectory() as folder:
        ...     lines = motion.to_csv(Path(folder) / "motion.csv").read_text().splitlines()
        >>> lines[0], len(lines)
        ('sample,state_0,state_1', 33)
        """
        from gear_dyn.io import write_csv

        return write_csv(path, self._columns())

    def plot(self, ax: Any = None) -> Any:
        """The samples in the state plane, a Poincaré section
        (:func:`gear_dyn.plots.bifurcation.plot_motion`, looked up by name as
        ``BifurcationDiagram.plot`` does); returns the Figure.

        Parameters
        ----------
        ax : matplotlib.axes.Axes or None
            Where to draw; None makes a new figure.

        Returns
        -------
        matplotlib.figure.Figure
            The figure drawn on.

        See Also
        --------
        :meth:`~gear_dyn.analysis.motion.diagram.BifurcationDiagram.plot` : Motions over speed.

        Examples
        --------
        >>> import matplotlib.pyplot as plt
        >>> from gear_dyn import SDOFModel, classify_motion, rectangular_stiffness
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 136.9,
        ...               backlash=1e-3)
        >>> motion = classify_motion(m, m.initial_state(), settle=20, samples=32)
        >>> fig = motion.plot()
        >>> fig.axes[0].get_title()
        'period-1'
        >>> plt.close(fig)
        """
        plots = importlib.import_module("gear_dyn.plots.bifurcation")
        return plots.plot_motion(self, ax=ax)

    def __repr__(self) -> str:
        return f"Motion({self.label})"


def lyapunov_kind(est: LyapunovEstimate) -> str:
    """What the largest Lyapunov exponent says of a motion with no orbit of <= 16 periods.

    ``chaotic``: positive by more than :data:`SIGMAS` standard errors and by more than
    :data:`ZERO_BAND` per mesh period; ``quasi-periodic``: zero, i.e. within :data:`ZERO_BAND`
    per mesh period with a standard error that resolves that band (:data:`SIGMAS` errors
    inside it); ``not settled``: negative by more than :data:`SIGMAS` errors (still converging);
    ``undetermined``: none of these (the estimate is too uncertain).
    """
    lam, err, period = est.value, est.error, est.mesh_period
    if lam > SIGMAS * err and lam * period > ZERO_BAND:
        return "chaotic"
    if abs(lam * period) <= ZERO_BAND and SIGMAS * err * period <= ZERO_BAND:
        return "quasi-periodic"
    if lam < -SIGMAS * err:
        return "not settled"
    return "undetermined"


def lyapunov_label(est: LyapunovEstimate) -> str:
    """``lambda = 2054 +- 98 1/s``: the estimate to the digits its error supports."""
    return f"lambda = {est.value:.4g} +- {est.error:.2g} 1/s"


def confirm_period(model: MeshModel, y: FloatArray, n: int, rtol: float = 1e-10,
                   newton: NewtonSettings = NEWTON) -> tuple[PeriodicSolution, int]:
    """A stable orbit of ``n`` mesh periods near ``y`` by shooting, and its least period.

    Parameters
    ----------
    model : MeshModel
    y : ndarray
        A stroboscopic sample near the orbit, SI units.
    n : int
        Mesh periods (1..16).
    rtol : float
        Tolerance of shooting (:func:`gear_dyn.analysis.stability.shoot`).
    newton : NewtonSettings
        Newton iterations and closing tolerance of shooting (default 15, 100 ``rtol``).

    Returns
    -------
    (PeriodicSolution, int)
        The shooting result (``periods = n``) and the least d dividing n after which the orbit
        repeats (to ``1000 rtol`` of the state scale); d = 0 where Newton did not converge or
        the orbit is unstable.
    """
    check_range("n", n, "", low=1, high=MAX_PERIOD)
    sol = shoot(model, y, rtol, newton.max_iter, periods=n, tol=newton.tolerance)
    if not sol.stable:
        return sol, 0
    least = n
    if n > 1:
        orbit = flow_periods(model, sol.y0, n, rtol).T
        scale = np.maximum(np.asarray(model.state_scale, dtype=float), np.abs(sol.y0))
        for d in range(1, n):
            if n % d == 0 and np.max(np.abs(orbit[d] - orbit[0]) / scale) <= 1e3 * rtol:
                least = d
                break
    return sol, least


def classify_samples(model: MeshModel, samples: FloatArray, rtol: float = 1e-10,
                     lyapunov_periods: int = 400, lyapunov_block: int = 40,
                     newton: NewtonSettings = NEWTON, route: str = "auto") -> Motion:
    """Classify the motion whose stroboscopic samples are ``samples`` (see the module text).

    Parameters
    ----------
    model : MeshModel
        Single-DOF mesh model.
    samples : ndarray (n_samples, n_states)
        Stroboscopic samples after settling, at least 32 (:data:`.period.MAX_PERIOD` x 2).
    rtol : float
        Tolerance of shooting and of the variational route.
    lyapunov_periods, lyapunov_block : int
        Mesh periods of the Lyapunov estimate and per block (:func:`.lyapunov.largest_lyapunov`).
    newton : NewtonSettings
        Shooting for each period tried (:func:`confirm_period`).
    route : {"auto", "exact", "variational"}
        Sensitivity route of the Lyapunov exponent (shooting takes ``auto``).

    Returns
    -------
    Motion

    Raises
    ------
    InputError
        Too few samples or a bad argument.
    SolverError
        Integration failure.
    """
    samples = np.asarray(samples, dtype=float)
    scale = np.asarray(model.state_scale, dtype=float)
    if not np.all(np.isfinite(samples)) or np.max(np.abs(samples) / scale) > UNBOUNDED:
        return Motion("unbounded", "unbounded", samples[-1].copy(), samples)
    found, iters = find_orbit(model, samples, rtol, newton)
    if found is not None:
        return found
    est = largest_lyapunov(model, samples[-1], lyapunov_periods, lyapunov_block, rtol=rtol,
                           route=route)
    # the run may have ended a transient (a slow escape from an unstable orbit shows a
    # positive exponent for a while): look for an orbit once more, from where it ended
    again = stroboscopic(model, est.y_end, 0, samples.shape[0], rtol)
    found, iters = find_orbit(model, again, rtol, newton, iters)
    if found is not None:
        return found
    kind = lyapunov_kind(est)
    near = repeat_errors(again, scale) <= TRY_TOL
    banded = False
    if near.any() or kind == "undetermined":
        # samples that nearly repeat without a stable orbit, or an exponent not resolved: a
        # run LONGER times as long decides (just past a period-doubling cascade the chaotic
        # attractor lies in narrow bands around an unstable period-n orbit, so its samples
        # nearly repeat after n periods while the exponent is positive)
        before = repeat_errors(again, scale)
        est = largest_lyapunov(model, est.y_end, LONGER * lyapunov_periods, lyapunov_block,
                               rtol=rtol, route=route)
        again = stroboscopic(model, est.y_end, 0, samples.shape[0], rtol)
        found, iters = find_orbit(model, again, rtol, newton, iters)
        if found is not None:
            return found
        first = repeat_errors(again, scale)
        kind = lyapunov_kind(est)
        # near-repeating samples stay so on a banded attractor; leaving a saddle orbit, their
        # repeat error grows with the escape (a positive exponent then is the saddle's)
        banded = not near.any() or bool(np.all(first[near] <= GROWTH * before[near]))
        near = first <= TRY_TOL
    if kind == "chaotic" and (banded or not near.any()):
        label = f"chaotic, {lyapunov_label(est)}"
    elif near.any():  # repeating, yet no stable orbit: a saddle orbit, left slowly
        kind = "not settled"
        label = (f"not settled (near an unstable period-{int(np.argmax(near)) + 1} orbit), "
                 f"{lyapunov_label(est)}")
    elif kind == "not settled":
        label = f"not settled (no stable orbit of <= {MAX_PERIOD} periods), {lyapunov_label(est)}"
    elif kind == "undetermined":
        label = f"undetermined (exponent not resolved: run longer), {lyapunov_label(est)}"
    else:
        label = f"{kind}, {lyapunov_label(est)}"
    return Motion(kind, label, est.y_end.copy(), samples, None, est,
                  repeat_errors(samples, scale), iters)


def find_orbit(model: MeshModel, samples: FloatArray, rtol: float = 1e-10,
               newton: NewtonSettings = NEWTON, iters: int = 0) -> tuple[Motion | None, int]:
    """A stable orbit of n <= 16 mesh periods that the samples suggest, confirmed by shooting.

    The periods after which the samples repeat to :data:`.TRY_TOL` state scales are tried in
    increasing order, at most :data:`.MAX_TRIES`, shooting from the last sample (the most
    settled). Multiples of a period that failed are tried too: samples that leave an unstable
    period-1 orbit repeat after one period for a while, and shooting over two periods reaches
    the stable period-2 orbit they are heading for.

    Parameters
    ----------
    model : MeshModel
    samples : ndarray (n_samples, n_states)
        Stroboscopic samples, at least 32, SI units.
    rtol, newton
        As :func:`confirm_period`.
    iters : int
        Newton iterations spent so far (added to).

    Returns
    -------
    (Motion or None, int)
        The periodic motion (None if no period was confirmed) and the Newton iterations.
    """
    scale = np.asarray(model.state_scale, dtype=float)
    err = repeat_errors(samples, scale)
    tried = [n for n in range(1, MAX_PERIOD + 1) if err[n - 1] <= TRY_TOL][:MAX_TRIES]
    for n in tried:
        sol, least = confirm_period(model, samples[-1], n, rtol, newton)
        iters += sol.iterations
        if least:
            # the orbit over its least period: the state confirmed, the least period's
            # multipliers
            orbit = (sol if least == n
                     else replace(shoot(model, sol.y0, rtol, LEAST_PERIOD_NEWTON.max_iter,
                                        periods=least, tol=LEAST_PERIOD_NEWTON.tolerance),
                                  y0=sol.y0))
            return Motion("periodic", f"period-{least}", sol.y0.copy(), samples, orbit,
                          None, err, iters), iters
    return None, iters


@blas_limited
def classify_motion(model: MeshModel, y0: FloatArray, settle: int = 200, samples: int = 64,
                    rtol: float = 1e-10, lyapunov_periods: int = 400,
                    lyapunov_block: int = 40, newton: NewtonSettings = NEWTON,
                    route: str = "auto") -> Motion:
    """Settle from ``y0`` and classify the motion (period-n, quasi-periodic, chaotic).

    Parameters
    ----------
    model : MeshModel
        Single-DOF mesh model (``mesh_periodic``), with or without backlash.
    y0 : ndarray
        Start state at t = 0, SI units (e.g. ``model.initial_state()`` or the state of a
        neighbouring speed).
    settle : int
        Mesh periods run before sampling (0..1e6).
    samples : int
        Stroboscopic samples classified (32..1e6).
    rtol, lyapunov_periods, lyapunov_block, newton, route
        As :func:`classify_samples`.

    Returns
    -------
    Motion

    Raises
    ------
    InputError
        A bad argument or a model that is not a mesh-periodic single-DOF model.
    SolverError
        Integration failure.

    See Also
    --------
    :class:`~gear_dyn.analysis.motion.classify.Motion` : The result.
    :func:`~gear_dyn.analysis.motion.diagram.bifurcation_diagram`
        The motion over a range of speeds.

    Examples
    --------
    >>> from gear_dyn import SDOFModel, rectangular_stiffness
    >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 136.9,
    ...               backlash=1e-3)
    >>> motion = classify_motion(m, m.initial_state(), settle=20, samples=32)
    >>> motion.label, motion.samples.shape
    ('period-1', (32, 2))
    """
    check_range("samples", samples, "", low=2 * MAX_PERIOD)
    strobe = stroboscopic(model, y0, settle, samples, rtol)
    return classify_samples(model, strobe, rtol, lyapunov_periods, lyapunov_block, newton,
                            route)
