"""A scene's bifurcation diagram in one call: the scene's model factory over speed, handed to
:func:`gear_dyn.analysis.motion.bifurcation_diagram`."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from gear_dyn.analysis.motion.diagram import (
    BifurcationDiagram,
    DiagramOptions,
    bifurcation_diagram,
)
from gear_dyn.scene.operating import check_keywords, parse_speeds
from gear_dyn.scene.sweep import SOLVER_OVERRIDES, SceneModels
from gear_dyn.scene.validated import Scene


def bifurcation_scene(scene: Scene, speeds: Any, *, si: bool = False,
                      options: DiagramOptions | None = None, direction: str = "both",
                      workers: int | None = None, executor: Any = None,
                      block: int | None = None,
                      progress: Callable[[int, int], None] | None = None,
                      **solver: Any) -> BifurcationDiagram:
    """The bifurcation diagram of a scene over pinion speeds.

    ``speeds`` as for :func:`gear_dyn.scene.sweep.sweep_scene` (``"6000 rpm:9000 rpm:61"``, a
    list of strings with units, or numbers in rad/s with ``si=True``). ``options``,
    ``direction``, ``workers``, ``executor``, ``block``, ``progress``: those of
    :func:`gear_dyn.analysis.motion.bifurcation_diagram`; ``solver``: ``[solver]`` overrides
    (``rtol`` sets the tolerance where the exact flow does not apply, unless ``options`` is
    given).

    Raises
    ------
    InputError
        Bad speeds, options or overrides; a scene whose model is not the single-DOF mesh model;
        an unknown keyword.
    SolverError
        An integration failed.
    """
    check_keywords("bifurcation_scene", solver, (
        "si", "options", "direction", "workers", "executor", "block", "progress",
        *SOLVER_OVERRIDES))
    sp = parse_speeds(speeds, si=si, function="bifurcation_scene")
    factory = SceneModels.of(scene, **solver)
    if options is None:
        options = DiagramOptions(rtol=max(factory.plan.settings.rtol, 1e-13))
    return bifurcation_diagram(factory, sp, options=options, direction=direction,
                               name=scene.name, workers=workers, executor=executor, block=block,
                               progress=progress)
