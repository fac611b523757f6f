"""Sweeps of a scene: the model factory over speed, and the scene's sweep in one call.

The analysis layer sweeps any model factory ``speed -> Model``
(:func:`gear_dyn.analysis.sweep.sweep`); here a scene becomes such a factory (:class:`SceneModels`).
"""

from __future__ import annotations

import concurrent.futures as cf
import json
from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import lru_cache
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.geometry import GearPair
from gear_dyn.models.base import Model, at_speed
from gear_dyn.scene.build import RunPlan, build_model, build_pair, build_plan
from gear_dyn.scene.hints import backlash_gap_hint
from gear_dyn.scene.operating import check_keywords, parse_speeds
from gear_dyn.scene.validated import Scene

if TYPE_CHECKING:  # the sweep itself is imported by sweep_scene (SceneModels, for a continuation,
    # needs none of it)
    from gear_dyn.analysis.sweep import SweepOptions, SweepResult

FloatArray = NDArray[np.float64]
#: the ``[solver]`` values a sweep may override
SOLVER_OVERRIDES = ("method", "rtol", "atol", "samples_per_period", "periods", "steady_periods",
                    "max_nfev")


@lru_cache(maxsize=4)
def _base(source: str, tables_json: str, overrides_json: str) -> tuple[Scene, RunPlan, GearPair]:
    """(scene, plan, pair) rebuilt from JSON (cached per worker process)."""
    scene = Scene(source=source, tables=json.loads(tables_json))
    plan = build_plan(scene, **json.loads(overrides_json))
    return scene, plan, build_pair(scene)


@dataclass(frozen=True)
class SceneModels:
    """The model of a scene at any pinion speed: ``SceneModels.of(scene)(speed) -> Model``.

    Picklable: it holds the scene as JSON, so process pools and Dask workers rebuild the scene's
    model once each (cached) and then only what depends on speed.
    """

    source: str
    tables_json: str
    overrides_json: str

    @classmethod
    def of(cls, scene: Scene, **overrides: Any) -> SceneModels:
        """The factory of ``scene`` with ``[solver]`` ``overrides``."""
        ov = {k: v for k, v in overrides.items() if v is not None}
        return cls(scene.source, json.dumps(scene.tables, sort_keys=True),
                   json.dumps(ov, sort_keys=True))

    @property
    def torque(self) -> float:
        """The scene's pinion torque (``operating.torque``, N m): the torque of every model
        made here (:class:`gear_dyn.analysis.continuation.SpeedTorqueFamily` reads it)."""
        scene = _base(self.source, self.tables_json, self.overrides_json)[0]
        return float(scene.get("operating")["torque"])

    @property
    def plan(self) -> RunPlan:
        """The scene's run plan (model at the scene's own speed, settings, span)."""
        return _base(self.source, self.tables_json, self.overrides_json)[1]

    @property
    def mesh_frequency_only(self) -> bool:
        """True when the models differ only in the mesh frequency (the scene's model has
        ``at_mesh_frequency``; else each speed rebuilds it): the continuation then takes the
        shooting map's exact speed derivative."""
        model = _base(self.source, self.tables_json, self.overrides_json)[1].model
        return model.at_mesh_frequency(float(getattr(model, "mesh_frequency", 1.0))) is not None

    def __call__(self, speed: float) -> Model:
        """The scene's model at pinion speed ``speed`` in rad/s, as ``run_scene`` builds it
        (:func:`gear_dyn.models.base.at_speed`, else the scene rebuilt at that speed)."""
        scene, plan, pair = _base(self.source, self.tables_json, self.overrides_json)
        model = at_speed(plan.model, pair.z1, speed)
        if model is not None:
            return model
        tables = {**scene.tables, "operating": {**scene.tables["operating"], "speed": speed}}
        return build_model(Scene(source=scene.source, tables=tables))


def model_at_speed(scene: Scene, speed: float, **overrides: Any) -> Model:
    """The scene's model at pinion speed ``speed`` (rad/s), as ``run_scene`` would build it."""
    return SceneModels.of(scene, **overrides)(speed)


def sweep_scene(scene: Scene, speeds: Any, *, si: bool = False,
                options: SweepOptions | None = None,
                direction: str = "auto", workers: int | None = None,
                executor: cf.Executor | None = None, block: int | None = None,
                progress: Callable[[int, int], None] | None = None,
                **solver: Any) -> SweepResult:
    """Sweep a scene over pinion speeds: :func:`gear_dyn.analysis.sweep.sweep` with the
    scene's model factory, solver settings and span.

    ``speeds``: strings with units (``["4000 rpm", "6275 rpm"]``), a range ``"1000 rpm:6000
    rpm:51"`` (START:STOP:N, as ``--speeds``), or, with ``si=True``, numbers in rad/s (a list or
    a numpy array); plain numbers without ``si=True`` are refused, as in a scene file
    (:func:`gear_dyn.scene.operating.parse_speeds`).

    Serial in the calling process unless ``workers`` (N >= 2: a local process pool) or an
    ``executor`` (e.g. ``distributed.Client(...).get_executor()``, which needs the ``dask``
    extra: ``pip install "gear_dyn[dask]"``) is given; the numbers are
    the same. ``options``, ``direction``, ``workers``, ``executor``, ``block`` and ``progress``
    are those of :func:`~gear_dyn.analysis.sweep.sweep`; ``solver``: ``[solver]`` overrides
    (:data:`SOLVER_OVERRIDES`). ``SweepResult.warnings`` states what the scene leaves out
    (:func:`gear_dyn.scene.hints.backlash_gap_hint`).

    Parameters
    ----------
    scene : Scene
        From :func:`~gear_dyn.scene.load_scene` or :func:`~gear_dyn.scene.parse_scene`.
    speeds : str, sequence of str, or sequence of float
        Pinion speeds with units, a range ``"START:STOP:N"``, or numbers in rad/s with
        ``si=True``.
    si : bool
        Plain numbers in ``speeds`` are rad/s.
    options : SweepOptions or None
        How each speed is evaluated (default :class:`~gear_dyn.analysis.sweep.types.SweepOptions`).
    direction : {"auto", "up", "down", "both"}
        Sweep directions (``auto``: both for a model with backlash, else up).
    workers : int or None
        Local processes (None or 1: the calling process).
    executor : concurrent.futures.Executor or None
        Runs the blocks through its ``map`` (e.g. Dask's).
    block : int or None
        Speeds per task.
    progress : callable or None
        ``progress(done, total)`` after each block.
    **solver
        ``[solver]`` overrides (:data:`SOLVER_OVERRIDES`).

    Returns
    -------
    SweepResult
        One curve per direction, with the dynamic factor, F_max / W, DTE figures (m) and
        spectra at each speed.

    Raises
    ------
    InputError
        Plain-number speeds without ``si=True``; bad speeds, options, overrides, direction,
        block or workers; an unknown keyword.
    SolverError
        An integration failed.

    See Also
    --------
    :func:`~gear_dyn.scene.run_scene` : One speed, in time.
    :func:`~gear_dyn.scene.compare.compare_scenes` : Several designs over the same speeds.
    :class:`~gear_dyn.analysis.sweep.types.SweepOptions` : How each speed is evaluated.

    Examples
    --------
    >>> import gear_dyn as gd
    >>> sweep = gd.sweep_scene(gd.load_scene("helicopter_tail"), "3000 rpm:3600 rpm:3")
    >>> sweep.curve("up").dynamic_factor.round(3)
    array([0.788, 0.85 , 1.195])
    >>> gd.sweep_scene(gd.load_scene("helicopter_tail"), [300.0, 400.0])
    Traceback (most recent call last):
    ...
    gear_dyn.errors.InputError: ...
    """
    from gear_dyn.analysis.sweep import sweep

    check_keywords("sweep_scene", solver, (
        "si", "options", "direction", "workers", "executor", "block", "progress",
        *SOLVER_OVERRIDES))
    speeds = parse_speeds(speeds, si=si)
    factory = SceneModels.of(scene, **solver)
    plan = factory.plan
    f0 = plan.model.mesh_frequency
    periods = round(plan.t_end * f0)
    steady = round((plan.t_end - plan.steady_start) * f0)
    result = sweep(factory, speeds, settings=plan.settings, periods=periods,
                   steady_periods=steady, name=scene.name, options=options, direction=direction,
                   workers=workers, executor=executor, block=block, progress=progress)
    separated = any(np.any(np.nan_to_num(c.separation) > 0) for c in result.curves)
    hint = backlash_gap_hint(scene, separated)
    return result if hint is None else replace(result, warnings=(*result.warnings, hint))
