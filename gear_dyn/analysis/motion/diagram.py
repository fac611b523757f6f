"""The bifurcation diagram: stroboscopic samples against speed, swept up and down.

At each speed the model settles from the state where the previous speed ended (a slow physical
sweep), then a number of stroboscopic samples are kept (:mod:`.samples`): one point for a
period-1 orbit, n for period n, a cloud for chaos (Kahraman & Singh 1990; Parker & Chua 1989,
ch. 6). Sweeping up and down shows coexisting attractors.

Where it runs (:func:`gear_dyn.analysis.executor.task_map`: here, a process pool or any
executor): each direction is a chain of blocks of speeds, each block starting where the one
before it ended, and the i-th blocks of the up and the down chains run side by side (why a
chain is not cut into independent pieces: docs/motion.md). The blocks and their starting
states do not depend on the executor: the samples are the serial run's, bit for bit.
"""

from __future__ import annotations

import importlib
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.executor import (
    SpeedBlock,
    check_speeds,
    run_blocks,
    speed_blocks,
    task_map,
)
from gear_dyn.analysis.motion.classify import (
    UNBOUNDED,
    Motion,
    classify_samples,
    find_orbit,
)
from gear_dyn.analysis.motion.period import MAX_PERIOD
from gear_dyn.analysis.motion.samples import stroboscopic
from gear_dyn.analysis.newton import NewtonSettings
from gear_dyn.analysis.stability import PeriodicSolution
from gear_dyn.analysis.threads import blas_limited
from gear_dyn.errors import InputError, SolverError, check_range
from gear_dyn.models.base import Model

FloatArray = NDArray[np.float64]
ModelFactory = Callable[[float], Model]

#: speeds per block of a direction's chain
BLOCK = 8
#: the module that draws a BifurcationDiagram, looked up by name when plotted
PLOTS_MODULE = "gear_dyn.plots.bifurcation"
RPM = 2 * math.pi / 60


@dataclass(frozen=True)
class DiagramOptions:
    """How each speed of a bifurcation diagram is evaluated.

    Parameters
    ----------
    settle : int
        Mesh periods run before sampling at each speed (0..1e6).
    samples : int
        Stroboscopic samples kept per speed (32..1e5).
    classify : bool
        Where no orbit of 1..16 mesh periods is confirmed, classify the motion by its Lyapunov
        exponent (:func:`gear_dyn.analysis.motion.classify_samples`: quasi-periodic or
        chaotic); False: such speeds are left unlabelled. Periods are always confirmed by
        shooting (:func:`gear_dyn.analysis.motion.find_orbit`), and a confirmed orbit's samples
        are taken on the orbit itself.
    lyapunov_periods : int
        Mesh periods of each Lyapunov estimate where ``classify`` (20..1e6).
    rtol : float
        Relative tolerance where the exact flow does not apply (1e-13..1e-4).
    newton : NewtonSettings
        Shooting that confirms each period (default 15 iterations to 100 ``rtol``;
        :func:`gear_dyn.analysis.motion.find_orbit`).

    Raises
    ------
    InputError
        Any field outside its range.

    See Also
    --------
    :func:`~gear_dyn.analysis.motion.diagram.bifurcation_diagram` : Uses them at every speed.
    :class:`~gear_dyn.analysis.sweep.types.SweepOptions` : The same for a speed sweep.

    Examples
    --------
    >>> DiagramOptions(settle=50).samples
    64
    >>> DiagramOptions(samples=10)
    Traceback (most recent call last):
    ...
    gear_dyn.errors.InputError: samples = 10 is out of range: valid range 32 <= x <= 100000
    """

    settle: int = 200
    samples: int = 64
    classify: bool = False
    lyapunov_periods: int = 200
    rtol: float = 1e-10
    newton: NewtonSettings = NewtonSettings(max_iter=15)

    def __post_init__(self) -> None:
        check_range("settle", self.settle, "", low=0, high=1_000_000)
        check_range("samples", self.samples, "", low=2 * MAX_PERIOD, high=100_000)
        check_range("lyapunov_periods", self.lyapunov_periods, "", low=20, high=1_000_000)
        check_range("rtol", self.rtol, "", low=1e-13, high=1e-4)


class DiagramSpeed(NamedTuple):
    """One speed of a diagram, as the workers return it: the row's samples and label beside the
    orbit confirmed there.

    Attributes
    ----------
    speed : float
        Pinion speed in rad/s.
    mesh_frequency : float
        Hz.
    samples : ndarray (n_samples, n_states)
        Stroboscopic samples, SI units (NaN where the response diverged).
    orbit : PeriodicSolution or None
        The orbit confirmed by shooting, over its least period (``Motion.orbit``); None where
        none of 1..16 mesh periods was.
    label : str
        The motion's label (``period-4``, ``chaotic, lambda = ...``, ``unbounded``) or "".
    lyapunov, lyapunov_error : float
        Largest Lyapunov exponent and its standard error in 1/s (NaN where not computed).
    """

    speed: float
    mesh_frequency: float
    samples: FloatArray
    orbit: PeriodicSolution | None
    label: str
    lyapunov: float
    lyapunov_error: float

    @property
    def period(self) -> int:
        """Least period in mesh periods of the orbit (0: none)."""
        return 0 if self.orbit is None else self.orbit.periods


@dataclass(frozen=True)
class _Job:
    """What a diagram does at each speed (the job of its :class:`.executor.SpeedBlock`)."""

    factory: ModelFactory
    options: DiagramOptions


@blas_limited
def _run_task(task: SpeedBlock[_Job]) -> tuple[list[DiagramSpeed], FloatArray | None]:
    """Evaluate a block of speeds in order, each from the previous speed's final state."""
    opts, y = task.job.options, task.start
    out = []
    for s in task.speeds:
        model: Any = task.job.factory(s)
        y0 = model.initial_state() if y is None else y
        nan = math.nan
        try:
            strobe = stroboscopic(model, y0, opts.settle, opts.samples, opts.rtol)
        except SolverError as exc:
            if "non-finite" not in str(exc):
                raise
            strobe = np.full((opts.samples, y0.size), math.inf)
        if not np.all(np.abs(strobe) / model.state_scale <= UNBOUNDED):
            # a diverging response (a parametric instability that contact loss does not
            # bound): said, no samples drawn, and the chain restarts from the static state
            out.append(DiagramSpeed(s, model.mesh_frequency, np.full_like(strobe, nan), None,
                                    "unbounded", nan, nan))
            y = None
            continue
        if opts.classify:
            motion: Motion | None = classify_samples(
                model, strobe, opts.rtol, opts.lyapunov_periods,
                max(10, opts.lyapunov_periods // 10), opts.newton)
        else:
            motion, _iters = find_orbit(model, strobe, opts.rtol, opts.newton)
        if motion is None:  # not classified, no orbit confirmed
            out.append(DiagramSpeed(s, model.mesh_frequency, strobe, None, "", nan, nan))
            y = strobe[-1]
            continue
        if motion.periodic:  # the orbit itself, sampled: no settling remainder drawn
            # its n samples repeat every n mesh periods: one period of the orbit is walked
            one = stroboscopic(model, motion.state, 0, motion.period, opts.rtol)
            strobe = np.tile(one, (-(-opts.samples // motion.period), 1))[:opts.samples]
        est = motion.lyapunov
        out.append(DiagramSpeed(s, model.mesh_frequency, strobe, motion.orbit, motion.label,
                                nan if est is None else est.value,
                                nan if est is None else est.error))
        y = motion.state
    return out, y


@dataclass(frozen=True, eq=False)
class DiagramCurve:
    """One sweep direction of a bifurcation diagram, in sweep order.

    Attributes
    ----------
    direction : str
        ``up`` or ``down``.
    speed : ndarray (n,)
        Pinion speed in rad/s.
    mesh_frequency : ndarray (n,)
        Hz.
    samples : ndarray (n, n_samples, n_states)
        Stroboscopic samples at each speed, SI units.
    orbits : tuple of (PeriodicSolution or None)
        The orbit confirmed by shooting at each speed, over its least period (multipliers,
        stability); None where none of 1..16 mesh periods was.
    period : ndarray of int (n,)
        Least period in mesh periods of each orbit (0: none of 1..16).
    label : tuple of str
        The motion's label (``period-4``; where classified ``chaotic, lambda = ...``,
        ``quasi-periodic, ...``), else "". Where the response diverged (non-finite, or beyond
        :data:`gear_dyn.analysis.motion.classify.UNBOUNDED` state scales): ``unbounded``, the
        samples NaN, and the next speed starts from the static state.
    lyapunov, lyapunov_error : ndarray (n,)
        Largest Lyapunov exponent and its standard error in 1/s where computed, else NaN.
    """

    direction: str
    speed: FloatArray
    mesh_frequency: FloatArray
    samples: FloatArray
    orbits: tuple[PeriodicSolution | None, ...]
    label: tuple[str, ...]
    lyapunov: FloatArray
    lyapunov_error: FloatArray

    @property
    def period(self) -> NDArray[np.int_]:
        """Least period in mesh periods of each orbit (0: none of 1..16)."""
        return np.array([0 if o is None else o.periods for o in self.orbits], dtype=int)

    @classmethod
    def from_speeds(cls, direction: str, pts: Sequence[DiagramSpeed]) -> DiagramCurve:
        """Stack the rows of one direction, in sweep order."""
        speed, f_m, samples, orbits, label, lyapunov, error = zip(*pts, strict=True)
        return cls(direction, np.array(speed, dtype=float), np.array(f_m, dtype=float),
                   np.array(samples, dtype=float), orbits, label,
                   np.array(lyapunov, dtype=float), np.array(error, dtype=float))


@dataclass(frozen=True, eq=False, repr=False)
class BifurcationDiagram:
    """Stroboscopic samples against pinion speed, swept up and down.

    Made by :func:`~gear_dyn.analysis.motion.diagram.bifurcation_diagram`; each parameter is kept as
    the attribute of that name.

    Parameters
    ----------
    scene_name : str
        The scene's name (empty for a model family).
    curves : tuple of DiagramCurve
        One per direction (``up`` first).
    state_labels : tuple of str
        Names of the state components (``x``, ``v``).
    natural_frequency : float
        f_n in Hz (NaN for models without it).
    options : DiagramOptions
        How each speed was evaluated.
    run_time_s : float
        Wall time in s.
    executor : str
        Where it ran (``serial``, ``process pool, N workers``, or the executor's class name).

    See Also
    --------
    :func:`~gear_dyn.analysis.motion.diagram.bifurcation_diagram` : Makes it.
    :class:`~gear_dyn.analysis.motion.classify.Motion` : The motion at one speed.

    Examples
    --------
    >>> from gear_dyn import (DiagramOptions, SDOFModel, bifurcation_diagram,
    ...                       rectangular_stiffness, sdof_family)
    >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
    ...               backlash=1e-3)
    >>> diagram = bifurcation_diagram(sdof_family(m, "speed", teeth=20), [43.0, 44.0],
    ...                               options=DiagramOptions(settle=20, samples=32))
    >>> diagram.state_labels, diagram.executor
    (('x', 'v'), 'serial')
    """

    scene_name: str
    curves: tuple[DiagramCurve, ...]
    state_labels: tuple[str, ...]
    natural_frequency: float
    options: DiagramOptions
    run_time_s: float
    executor: str

    def __repr__(self) -> str:
        c = self.curves[0]
        rpm = c.speed / RPM
        periods = sorted({int(p) for cc in self.curves for p in cc.period})
        return (f"BifurcationDiagram({self.scene_name!r}: {c.speed.size} speeds "
                f"{rpm.min():.0f}-{rpm.max():.0f} rpm, "
                f"{'/'.join(cc.direction for cc in self.curves)}, {self.options.samples} "
                f"samples per speed; periods found {periods} (0: none); "
                f"{self.run_time_s:.3g} s)")

    def curve(self, direction: str) -> DiagramCurve:
        """The curve of ``direction`` (``up`` or ``down``).

        Parameters
        ----------
        direction : {"up", "down"}
            The sweep direction.

        Returns
        -------
        DiagramCurve
            Speeds (rad/s), mesh frequencies (Hz), samples (SI), periods and labels.

        Raises
        ------
        InputError
            No such direction in this diagram.

        See Also
        --------
        :meth:`~gear_dyn.analysis.motion.diagram.BifurcationDiagram.columns`
            All curves as columns.

        Examples
        --------
        >>> from gear_dyn import (DiagramOptions, SDOFModel, bifurcation_diagram,
        ...                       rectangular_stiffness, sdof_family)
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
        ...               backlash=1e-3)
        >>> diagram = bifurcation_diagram(sdof_family(m, "speed", teeth=20), [43.0, 44.0],
        ...                               options=DiagramOptions(settle=20, samples=32))
        >>> diagram.curve("down").speed  # rad/s, in the order swept
        array([44., 43.])
        """
        for c in self.curves:
            if c.direction == direction:
                return c
        raise InputError(f"direction {direction!r} not in this diagram; available: "
                         f"{', '.join(c.direction for c in self.curves)}")

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """Draw the diagram (:func:`gear_dyn.plots.bifurcation.plot_bifurcation`; ``ax`` None
        or one Axes; ``kwargs`` as there, e.g. ``state``). Returns the Figure.

        Parameters
        ----------
        ax : matplotlib.axes.Axes or None
            Where to draw; None makes a new figure.
        **kwargs
            Passed to :func:`gear_dyn.plots.bifurcation.plot_bifurcation`.

        Returns
        -------
        matplotlib.figure.Figure
            The figure drawn on.

        See Also
        --------
        :meth:`~gear_dyn.analysis.continuation.branch.Branch.plot`
            The orbits followed by continuation.

        Examples
        --------
        >>> import matplotlib.pyplot as plt
        >>> from gear_dyn import (DiagramOptions, SDOFModel, bifurcation_diagram,
        ...                       rectangular_stiffness, sdof_family)
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
        ...               backlash=1e-3)
        >>> diagram = bifurcation_diagram(sdof_family(m, "speed", teeth=20), [43.0, 44.0],
        ...                               options=DiagramOptions(settle=20, samples=32))
        >>> fig = diagram.plot()
        >>> plt.close(fig)
        """
        plots = importlib.import_module(PLOTS_MODULE)
        return plots.plot_bifurcation(self, ax=ax, **kwargs)

    def columns(self) -> dict[str, FloatArray]:
        """One row per sample: direction (+1 up, -1 down), speed (rad/s and rpm), f_m (Hz),
        f_m / f_n, the sample index, each state component (SI), the period, the Lyapunov
        exponent and its error (1/s; NaN where not computed). For ``io.write_csv``.

        Returns
        -------
        dict of ndarray
            Columns of equal length, SI units in the names.

        See Also
        --------
        :meth:`~gear_dyn.analysis.motion.diagram.BifurcationDiagram.to_dict` : One entry per speed.

        Examples
        --------
        >>> from gear_dyn import (DiagramOptions, SDOFModel, bifurcation_diagram,
        ...                       rectangular_stiffness, sdof_family)
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
        ...               backlash=1e-3)
        >>> diagram = bifurcation_diagram(sdof_family(m, "speed", teeth=20), [43.0, 44.0],
        ...                               options=DiagramOptions(settle=20, samples=32))
        >>> len(diagram.columns()["speed_rad_s"])  # 2 directions x 2 speeds x 32 samples
        128
        """
        cols: dict[str, list[Any]] = {k: [] for k in (
            "direction", "speed_rad_s", "speed_rpm", "mesh_frequency_hz", "fm_over_fn",
            "sample", *self.state_labels, "period", "lyapunov_1_s", "lyapunov_error_1_s")}
        for c in self.curves:
            n_s = c.samples.shape[1]
            per_speed = {"direction": np.full(c.speed.size, 1.0 if c.direction == "up" else -1.0),
                         "speed_rad_s": c.speed, "speed_rpm": c.speed / RPM,
                         "mesh_frequency_hz": c.mesh_frequency,
                         "fm_over_fn": c.mesh_frequency / self.natural_frequency,
                         "period": c.period, "lyapunov_1_s": c.lyapunov,
                         "lyapunov_error_1_s": c.lyapunov_error}
            for name, v in per_speed.items():
                cols[name].append(np.repeat(v, n_s))
            cols["sample"].append(np.tile(np.arange(n_s), c.speed.size))
            for i, name in enumerate(self.state_labels):
                cols[name].append(c.samples[:, :, i].ravel())
        return {k: np.concatenate(v).astype(float) for k, v in cols.items()}

    def rows(self) -> list[dict[str, float]]:
        """One row per sample, the rows of samples.csv (:meth:`columns` as dicts of plain
        floats).

        Returns
        -------
        list of dict
            SI units (and rpm) in the key names.

        See Also
        --------
        :meth:`~gear_dyn.analysis.motion.diagram.BifurcationDiagram.to_csv` : Writes them.

        Examples
        --------
        >>> from gear_dyn import (DiagramOptions, SDOFModel, bifurcation_diagram,
        ...                       rectangular_stiffness, sdof_family)
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
        ...               backlash=1e-3)
        >>> diagram = bifurcation_diagram(sdof_family(m, "speed", teeth=20), [43.0, 44.0],
        ...                               options=DiagramOptions(settle=20, samples=32))
        >>> len(diagram.rows()), diagram.rows()[0]["direction"]
        (128, 1.0)
        """
        from gear_dyn.io import column_rows

        return column_rows(self.columns())

    def to_csv(self, path: str | Path) -> Path:
        """Write :meth:`rows` as CSV (samples.csv) atomically, after two ``#`` lines stating
        the units.

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
        :meth:`~gear_dyn.analysis.motion.diagram.BifurcationDiagram.to_dict` : The same for
            JSON, one entry per speed.

        Examples
        --------
        >>> import tempfile
        >>> from pathlib import Path
        >>> from gear_dyn import (DiagramOptions, SDOFModel, bifurcation_diagram,
        ...                       rectangular_stiffness, sdof_family)
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
        ...               backlash=1e-3)
        >>> diagram = bifurcation_diagram(sdof_family(m, "speed", teeth=20), [43.0, 44.0],
        ...                               options=DiagramOptions(settle=20, samples=32))
        >>> with tempfile.TemporaryDirectory() as folder:
        ...     lines = diagram.to_csv(Path(folder) / "samples.csv").read_text().splitlines()
        >>> len(lines)  # 2 comment lines, the header, 2 directions x 2 speeds x 32 samples
        131
        """
        from gear_dyn.io import write_csv

        return write_csv(path, self.columns(), comments=[
            f"# {self.scene_name}: stroboscopic samples (t = k / f_m after "
            f"{self.options.settle} mesh periods), SI units: speed in rad/s and rpm, f_m in Hz, "
            "x in m, v in m/s,",
            "# direction +1 up / -1 down; period: least period in mesh periods confirmed by "
            "shooting (0: none of 1..16); lyapunov in 1/s (NaN: not computed)"])

    def to_dict(self) -> dict[str, Any]:
        """Per direction and speed: speed (rad/s, rpm), f_m / f_n, period, label, Lyapunov
        exponent and error (1/s; NaN where not computed, null in JSON written with
        ``io.write_json``), what bifurcation.json holds.

        Returns
        -------
        dict
            The scene, f_n in Hz, the options, and one list per direction.

        See Also
        --------
        :meth:`~gear_dyn.analysis.motion.diagram.BifurcationDiagram.columns` : Every sample.

        Examples
        --------
        >>> from gear_dyn import (DiagramOptions, SDOFModel, bifurcation_diagram,
        ...                       rectangular_stiffness, sdof_family)
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
        ...               backlash=1e-3)
        >>> diagram = bifurcation_diagram(sdof_family(m, "speed", teeth=20), [43.0, 44.0],
        ...                               options=DiagramOptions(settle=20, samples=32))
        >>> diagram.to_dict()["settle_periods"]
        20
        """
        return {
            "scene": self.scene_name, "natural_frequency_hz": self.natural_frequency,
            "settle_periods": self.options.settle, "samples": self.options.samples,
            "executor": self.executor, "run_time_s": self.run_time_s,
            "curves": {c.direction: [
                {"speed_rad_s": float(c.speed[i]), "speed_rpm": float(c.speed[i] / RPM),
                 "fm_over_fn": float(c.mesh_frequency[i] / self.natural_frequency),
                 "period": int(c.period[i]), "label": c.label[i],
                 "lyapunov_1_s": float(c.lyapunov[i]),
                 "lyapunov_error_1_s": float(c.lyapunov_error[i])}
                for i in range(c.speed.size)] for c in self.curves},
        }


@blas_limited
def bifurcation_diagram(
    factory: ModelFactory,
    speeds: Sequence[float] | FloatArray,
    *,
    options: DiagramOptions | None = None,
    direction: str = "both",
    name: str = "",
    workers: int | None = None,
    executor: Any = None,
    block: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> BifurcationDiagram:
    """Stroboscopic samples against speed, each speed continuing from the previous one.

    Parameters
    ----------
    factory : callable
        ``factory(speed) -> Model`` (speed in rad/s): a single-DOF mesh model; picklable for
        ``workers`` and ``executor`` (:class:`gear_dyn.scene.sweep.SceneModels` is).
    speeds : sequence of float
        Pinion speeds in rad/s (> 0, at most 1e5); sorted, duplicates removed.
    options : DiagramOptions or None
        Settling, samples, classification (default: :class:`DiagramOptions`).
    direction : {"both", "up", "down"}
        Sweep directions.
    name : str
        Stored in the result (the scene's name).
    workers : int or None
        Local processes (1..4096; None or 1: the calling process).
    executor : concurrent.futures.Executor or None
        Runs the blocks through its ``map`` (e.g. Dask's ``Client.get_executor()``).
    block : int or None
        Speeds per block (1..10000; default 8): the tasks and the steps of ``progress``.
    progress : callable or None
        ``progress(done, total)`` after each block.

    Returns
    -------
    BifurcationDiagram

    Raises
    ------
    InputError
        Bad speeds, direction, block or workers; a model that is not mesh-periodic.
    SolverError
        An integration failed.

    See Also
    --------
    :class:`~gear_dyn.analysis.motion.diagram.DiagramOptions` : How each speed is evaluated.
    :func:`~gear_dyn.analysis.motion.classify.classify_motion` : The motion at one speed.
    :func:`~gear_dyn.analysis.continuation.arclength.continue_orbits`
        The orbits followed through their folds.

    Examples
    --------
    >>> from gear_dyn import (DiagramOptions, SDOFModel, bifurcation_diagram,
    ...                       rectangular_stiffness, sdof_family)
    >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
    ...               backlash=1e-3)
    >>> diagram = bifurcation_diagram(sdof_family(m, "speed", teeth=20), [43.0, 44.0],
    ...                               options=DiagramOptions(settle=20, samples=32))
    >>> [(c.direction, c.period.tolist()) for c in diagram.curves]  # 20 periods: unsettled
    [('up', [1, 0]), ('down', [1, 1])]
    >>> settled = bifurcation_diagram(sdof_family(m, "speed", teeth=20), [43.0, 44.0],
    ...                               options=DiagramOptions(settle=200, samples=32))
    >>> [(c.direction, c.period.tolist()) for c in settled.curves]  # period-1 everywhere
    [('up', [1, 1]), ('down', [1, 1])]
    """
    opts = options or DiagramOptions()
    if direction not in ("both", "up", "down"):
        raise InputError(f"direction = {direction!r}: valid choices are both, up, down")
    size = BLOCK if block is None else int(check_range("block", block, "", low=1, high=10_000))
    sp = check_speeds(speeds, "bifurcation_diagram")
    model = factory(float(sp[0]))
    if not model.mesh_periodic:
        raise InputError(f"a bifurcation diagram needs the single-DOF mesh model; this model is "
                         f"{type(model).__name__}")
    start = time.perf_counter()
    dirs = ("up", "down") if direction == "both" else (direction,)
    with task_map(workers, executor) as (run_map, label):
        pts = run_blocks(run_map, _run_task, speed_blocks(sp, dirs, size), _Job(factory, opts),
                         None, progress=progress)
    fn = model.natural_frequency
    return BifurcationDiagram(
        scene_name=name, curves=tuple(DiagramCurve.from_speeds(d, pts[d]) for d in dirs),
        state_labels=tuple(model.state_labels),
        natural_frequency=math.nan if fn is None else float(fn), options=opts,
        run_time_s=time.perf_counter() - start, executor=label)
