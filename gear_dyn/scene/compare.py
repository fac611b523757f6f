"""Designs compared: every scene swept over the same speeds, ranked by physical figures.

:func:`compare_scenes` (the public ``gear_dyn.compare_scenes``, and what ``gear-dyn compare``
calls) sweeps each scene with :func:`gear_dyn.scene.sweep.sweep_scene`, adds what only the scene
knows (its operating speed, the quasi-static contact stress of its loaded contact, ISO K_v) and
hands the sweeps to :func:`gear_dyn.analysis.compare.compare_sweeps`.
"""

from __future__ import annotations

import concurrent.futures as cf
import math
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from gear_dyn.analysis.compare import Comparison, compare_sweeps
from gear_dyn.analysis.sweep import SweepOptions, SweepResult
from gear_dyn.errors import InputError
from gear_dyn.scene.build import build_pair
from gear_dyn.scene.iso import iso_kv_at
from gear_dyn.scene.loader import load_scene
from gear_dyn.scene.operating import check_keywords, parse_speeds
from gear_dyn.scene.sweep import SOLVER_OVERRIDES, sweep_scene
from gear_dyn.scene.validated import Scene


def static_contact_stress(scene: Scene) -> float:
    """Quasi-static peak Hertz contact stress (Pa) of the scene's loaded contact at its torque,
    along the path of contact (Wang et al. 2024, eqs. 27-31; tip relief included); NaN where
    it is not known: a helical pair, or zero load.

    The load sharing of the tooth pairs is that of ``gear-dyn contact``: the single-pair
    stiffness of ``tip_relief.pair_stiffness`` (potential energy unless set).
    """
    from gear_dyn.modification.analysis import relief_case
    from gear_dyn.scene.modification import relief_from_scene, scene_pair_function

    pair = build_pair(scene)
    torque = scene.get("operating")["torque"]
    if pair.helix_angle > 0 or not torque > 0:
        return math.nan
    modification = relief_from_scene(scene, pair) if scene.has("tip_relief") else None
    try:
        case = relief_case("scene", pair, scene_pair_function(scene, pair), torque,
                           modification)
    except InputError:  # a pair the loaded contact does not take: the stress is not known
        return math.nan
    return float(np.max(case.stress))


def _names(scenes: Sequence[Scene], names: Sequence[str] | None) -> list[str]:
    if names is None:
        names = [s.name for s in scenes]
        if len(set(names)) != len(names):
            names = [f"{s.name} ({Path(s.source).name})" for s in scenes]
    names = list(names)
    if len(names) != len(scenes):
        raise InputError(f"compare_scenes names: {len(names)} given for {len(scenes)} scenes")
    if len(set(names)) != len(names):
        raise InputError(f"compare_scenes: the same design given twice ({names}); pass "
                         "names=[...] to tell them apart")
    return names


def compare_scenes(scenes: Sequence[Scene | str | Path], speeds: Any, *, si: bool = False,
                   names: Sequence[str] | None = None, options: SweepOptions | None = None,
                   workers: int | None = None, executor: cf.Executor | None = None,
                   progress: Callable[[str], Callable[[int, int], None] | None] | None = None,
                   **solver: Any) -> Comparison:
    """Sweep several designs over the same speeds and rank them by their peak F_max / W.

    Each scene is swept as :func:`~gear_dyn.scene.sweep.sweep_scene` does, with its own
    operating speed added to the speeds where it lies inside the range (outside, a one-speed
    sweep gives its values, and the row is flagged). The first scene is the baseline: every
    figure has its difference from the baseline's, absolute and in per cent.

    Parameters
    ----------
    scenes : sequence of Scene, path or packaged scene name
        The designs, baseline first (paths and names are loaded with
        :func:`~gear_dyn.scene.load_scene`, all of them before any sweep).
    speeds : str or sequence
        As for :func:`~gear_dyn.scene.sweep.sweep_scene`: ``"1000 rpm:10000 rpm:181"``,
        strings with units, or numbers in rad/s with ``si=True``.
    si : bool
        Plain numbers in ``speeds`` are rad/s.
    names : sequence of str, optional
        One unique name per design (default: the scenes' names, with the file name where two
        are the same).
    options : SweepOptions, optional
        How each speed is evaluated.
    workers, executor :
        Where each sweep runs, as for :func:`~gear_dyn.scene.sweep.sweep_scene`.
    progress : callable, optional
        ``progress(name)`` returns the progress callback of that design's sweep (or None).
    **solver
        ``[solver]`` overrides for every scene (:data:`~gear_dyn.scene.sweep.SOLVER_OVERRIDES`).

    Returns
    -------
    Comparison
        ``.designs`` (figures, deltas, ranks, flags; ``.rows()`` in rank order), ``.ranking``,
        ``.to_dict()``, ``.to_csv(path)``, ``.plot(ax=None)``
        (:class:`~gear_dyn.analysis.compare.Comparison`).

    Raises
    ------
    InputError
        No scenes, names not unique, bad speeds or keywords.
    SceneError
        A scene file that does not load.
    SolverError
        An integration failed.

    See Also
    --------
    :func:`~gear_dyn.scene.sweep.sweep_scene` : One design's sweep.
    :class:`~gear_dyn.analysis.compare.Comparison` : The result.
    :func:`~gear_dyn.scene.load_scene` : Loads each scene file.

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
    >>> cmp.ranking  # lowest peak F_max / W first
    ('xi=0.1', 'xi=0.06')
    >>> [round(row["peak_peak_force_ratio"], 2) for row in cmp.designs]
    [2.15, 2.06]
    """
    check_keywords("compare_scenes", solver, (
        "si", "names", "options", "workers", "executor", "progress", *SOLVER_OVERRIDES))
    if not scenes:
        raise InputError("compare_scenes: no scenes given (at least 1)")
    loaded = [s if isinstance(s, Scene) else load_scene(s) for s in scenes]
    labels = _names(loaded, names)
    grid = parse_speeds(speeds, si=si, function="compare_scenes")
    lo, hi = float(np.min(grid)), float(np.max(grid))
    sweeps: list[SweepResult] = []
    operating: list[SweepResult | None] = []
    op_speeds = []
    for name, scene in zip(labels, loaded, strict=True):
        op = float(scene.get("operating")["speed"])
        op_speeds.append(op)
        inside = lo <= op <= hi
        own = np.unique(np.append(grid, op)) if inside else grid
        show = progress(name) if progress is not None else None
        kw: dict[str, Any] = dict(si=True, options=options, workers=workers, executor=executor,
                                  **solver)
        sweeps.append(sweep_scene(scene, own, progress=show, **kw))
        operating.append(None if inside else sweep_scene(scene, [op], **kw))
    kv = []
    for scene, res in zip(loaded, sweeps, strict=True):
        p = res.peak("peak_force_ratio")
        k = iso_kv_at(scene, np.array([p.speed])) if math.isfinite(p.speed) else None
        kv.append(math.nan if k is None else float(np.asarray(k)[0]))
    return compare_sweeps(sweeps, labels, op_speeds, operating=operating,
                          static_stress=[static_contact_stress(s) for s in loaded],
                          iso_kv_at_peak=kv)


__all__ = ["compare_scenes", "static_contact_stress"]
