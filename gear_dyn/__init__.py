"""gear_dyn: dynamics of gear pairs.

The public API in one place::

    from gear_dyn import GearPair, load_scene, run_scene, simulate, SolverSettings, sweep_scene

    scene = load_scene("helicopter_tail")
    res = run_scene(scene, speed="6000 rpm", torque="200 Nm")   # units as in a scene file
    sweep = sweep_scene(scene, "1000 rpm:8000 rpm:141")          # a SweepResult

What two of these names mean, beside their relatives deeper in the package:

- ``gear_dyn.simulate`` is :func:`gear_dyn.analysis.study.simulate`: the run with its error
  estimate and stability checks (what ``run_scene`` calls). The bare run without them is
  :func:`gear_dyn.solvers.simulate_bare`.
- ``gear_dyn.build_stiffness`` is :func:`gear_dyn.stiffness.build_stiffness`: the mesh stiffness
  of a pair by a method's name and options. A scene's ``[stiffness]`` table gives
  :func:`gear_dyn.scene.scene_stiffness`.

Importing ``gear_dyn`` is cheap: each public name loads its module on first use (a module
``__getattr__``, Scientific Python SPEC 1), so ``import gear_dyn`` loads neither scipy, matplotlib
nor pint, and changes no environment variable. The layers of the package are described in
docs/architecture.md.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

__version__ = "0.1.0"

#: public name -> module that defines it
_EXPORTS: dict[str, str] = {
    "GearDynError": "gear_dyn.errors",
    "InputError": "gear_dyn.errors",
    "SceneError": "gear_dyn.errors",
    "SolverError": "gear_dyn.errors",
    "GearPair": "gear_dyn.geometry",
    "mesh_frequency": "gear_dyn.geometry",
    "output_speed": "gear_dyn.geometry",
    "SDOFModel": "gear_dyn.models.sdof",
    "sdof_from_pair": "gear_dyn.models.sdof",
    "summarize": "gear_dyn.analysis.report",
    "load_scene": "gear_dyn.scene",
    "parse_scene": "gear_dyn.scene",
    "run_scene": "gear_dyn.scene",
    "sweep_scene": "gear_dyn.scene.sweep",
    "compare_scenes": "gear_dyn.scene.compare",
    "Comparison": "gear_dyn.analysis.compare",
    "SweepOptions": "gear_dyn.analysis.sweep.types",
    "SweepResult": "gear_dyn.analysis.sweep.types",
    "continue_orbits": "gear_dyn.analysis.continuation.arclength",
    "sdof_family": "gear_dyn.analysis.continuation.family",
    "Branch": "gear_dyn.analysis.continuation.branch",
    "ContinuationSettings": "gear_dyn.analysis.continuation.settings",
    "BifurcationDiagram": "gear_dyn.analysis.motion.diagram",
    "DiagramOptions": "gear_dyn.analysis.motion.diagram",
    "bifurcation_diagram": "gear_dyn.analysis.motion.diagram",
    "Motion": "gear_dyn.analysis.motion.classify",
    "classify_motion": "gear_dyn.analysis.motion.classify",
    "fold_map": "gear_dyn.analysis.continuation.fold_curve",
    "SpeedTorqueFamily": "gear_dyn.analysis.continuation.fold_curve",
    "FoldMap": "gear_dyn.analysis.continuation.jump_map",
    "Result": "gear_dyn.solvers.result",
    "SolverSettings": "gear_dyn.solvers.settings",
    "simulate": "gear_dyn.analysis.study",
    "FourierStiffness": "gear_dyn.stiffness.periodic",
    "PeriodicStiffness": "gear_dyn.stiffness.periodic",
    "PiecewiseStiffness": "gear_dyn.stiffness.periodic",
    "rectangular_stiffness": "gear_dyn.stiffness.periodic",
    "iso6336_stiffness": "gear_dyn.stiffness.iso6336",
    "build_stiffness": "gear_dyn.stiffness.select",
}

__all__ = sorted(_EXPORTS)

if TYPE_CHECKING:  # what type checkers and IDEs see; at run time the names load lazily
    from gear_dyn.analysis.compare import Comparison
    from gear_dyn.analysis.continuation.arclength import continue_orbits
    from gear_dyn.analysis.continuation.branch import Branch
    from gear_dyn.analysis.continuation.family import sdof_family
    from gear_dyn.analysis.continuation.fold_curve import SpeedTorqueFamily, fold_map
    from gear_dyn.analysis.continuation.jump_map import FoldMap
    from gear_dyn.analysis.continuation.settings import ContinuationSettings
    from gear_dyn.analysis.motion.classify import Motion, classify_motion
    from gear_dyn.analysis.motion.diagram import (
        BifurcationDiagram,
        DiagramOptions,
        bifurcation_diagram,
    )
    from gear_dyn.analysis.report import summarize
    from gear_dyn.analysis.study import simulate
    from gear_dyn.analysis.sweep.types import SweepOptions, SweepResult
    from gear_dyn.errors import GearDynError, InputError, SceneError, SolverError
    from gear_dyn.geometry import GearPair, mesh_frequency, output_speed
    from gear_dyn.models.sdof import SDOFModel, sdof_from_pair
    from gear_dyn.scene import load_scene, parse_scene, run_scene
    from gear_dyn.scene.compare import compare_scenes
    from gear_dyn.scene.sweep import sweep_scene
    from gear_dyn.solvers.result import Result
    from gear_dyn.solvers.settings import SolverSettings
    from gear_dyn.stiffness.iso6336 import iso6336_stiffness
    from gear_dyn.stiffness.periodic import (
        FourierStiffness,
        PeriodicStiffness,
        PiecewiseStiffness,
        rectangular_stiffness,
    )
    from gear_dyn.stiffness.select import build_stiffness


def __getattr__(name: str) -> Any:
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'gear_dyn' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value  # later lookups skip this function
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})
