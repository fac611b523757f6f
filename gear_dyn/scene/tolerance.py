"""A scene's tolerance study: its deviations drawn N times, each with its own seed.

The samples follow the scene's ``[deviations]`` table (grade or explicit values; the pattern is
``random``), or the ``grade`` given here; sample i draws from
``numpy.random.default_rng([seed, i])``. The model is the scene's without the table
(:func:`gear_dyn.analysis.tolerance.tolerance_study` adds every sample's deviations).
"""

from __future__ import annotations

import concurrent.futures as cf
from typing import Any

from gear_dyn.analysis.tolerance import ToleranceResult, tolerance_study
from gear_dyn.errors import InputError, SceneError, check_range
from gear_dyn.modification.deviations import pair_tolerances, sample_deviations
from gear_dyn.scene.build import build_pair
from gear_dyn.scene.deviations import scene_tolerances
from gear_dyn.scene.operating import parse_speeds
from gear_dyn.scene.sweep import SceneModels
from gear_dyn.scene.validated import Scene, scene_error

#: most samples of one study
MAX_SAMPLES = 1_000_000


def tolerance_scene(scene: Scene, speeds: Any, *, samples: int = 100, seed: int | None = None,
                    grade: int | None = None, si: bool = False,
                    samples_per_period: int | None = None, workers: int | None = None,
                    executor: cf.Executor | None = None) -> ToleranceResult:
    """Monte-Carlo tolerance study of ``scene`` at ``speeds``.

    Parameters
    ----------
    scene : Scene
        A linear single-DOF scene with piecewise-constant stiffness.
    speeds : str, sequence or array
        As :func:`gear_dyn.scene.sweep.sweep_scene` (``"1000 rpm:6000 rpm:51"``; numbers in
        rad/s with ``si=True``).
    samples : int
        N, 1..1e6.
    seed : int or None
        Base seed (default ``[deviations] seed``, else 1); sample i uses ``[seed, i]``.
    grade : int or None
        ISO 1328-1:2013 grade (default: the scene's ``[deviations]``, else ``[iso]
        accuracy_grade``).
    samples_per_period : int or None
        Output samples per mesh period (default the scene's ``[solver]``).
    workers, executor
        Where the blocks of speeds run (as a sweep); the numbers do not depend on it.

    Raises
    ------
    SceneError
        No grade or deviation values, or a scene the study does not cover.
    InputError
        Bad speeds, samples or workers.
    """
    check_range("samples", samples, "", low=1, high=MAX_SAMPLES)
    speeds = parse_speeds(speeds, si=si)
    pair = build_pair(scene)
    dev = scene.tables.get("deviations", {})
    if grade is not None:
        tol = pair_tolerances(pair, grade)
    elif dev:
        tol = scene_tolerances(scene, pair)[0]
    elif scene.get("iso")["accuracy_grade"] is not None:
        tol = pair_tolerances(pair, scene.get("iso")["accuracy_grade"])
    else:
        raise SceneError(f"{scene.source}: tolerance study: no grade: give --grade, a "
                         "[deviations] table or [iso] accuracy_grade")
    base_seed = int(seed if seed is not None else dev.get("seed", 1))
    seeds = [[base_seed, i] for i in range(int(samples))]
    draws = [sample_deviations(pair, tol, "random", s) for s in seeds]
    tables = {k: v for k, v in scene.tables.items() if k != "deviations"}
    factory = SceneModels.of(Scene(source=scene.source, tables=tables))
    try:
        return tolerance_study(factory, speeds, draws, seeds=seeds,
                               settings=factory.plan.settings,
                               samples_per_period=samples_per_period, workers=workers,
                               executor=executor, name=scene.name)
    except SceneError:
        raise
    except InputError as exc:
        raise scene_error(scene.source, exc) from None
