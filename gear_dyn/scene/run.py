"""Run a scene: build its plan, simulate it with the run's checks, attach what the scene says.

The step above :mod:`.build`: it adds the simulation (:func:`gear_dyn.analysis.study.simulate`)
and the ISO 6336-1 K_v beside it (:mod:`.iso`).
"""

from __future__ import annotations

from typing import Any

from gear_dyn.analysis.study import simulate
from gear_dyn.errors import InputError
from gear_dyn.scene.build import build_plan, scene_facts
from gear_dyn.scene.iso import iso_kv_summary
from gear_dyn.scene.validated import Scene, scene_error
from gear_dyn.solvers import Result


def run_scene(scene: Scene, **overrides: Any) -> Result:
    """Build and simulate a scene; the Result carries the scene and, in ``extra``, what the
    scene says about the case (:func:`scene_facts`: speeds, contact ratio, backlash, ...) and
    ``iso_6336_kv``, the ISO 6336-1 method B K_v at the same speed (:mod:`gear_dyn.scene.iso`)."""
    plan = build_plan(scene, **overrides)
    iso_kv = iso_kv_summary(scene)  # before the run: a bad [iso] table fails fast
    try:
        result = simulate(plan.model, plan.t_end, plan.settings, plan.steady_start, scene=scene)
    except InputError as exc:  # e.g. a run too long for the solver: name the file
        raise scene_error(scene.source, exc) from None
    for key, value in scene_facts(scene).items():
        result.extra.setdefault(key, value)  # the model's own figures take precedence
    result.extra.setdefault("iso_6336_kv", iso_kv)
    return result
