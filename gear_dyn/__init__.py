"""gear_dyn: dynamics of gear pairs.

The public API in one place::

    from gear_dyn import GearPair, load_scene, run_scene, simulate, SolverSettings
"""

from . import _threads  # noqa: F401  (must run before numpy is imported)
from .errors import GearDynError, InputError, SceneError, SolverError
from .geometry import GearPair, mesh_frequency, output_speed
from .models import SDOFModel, sdof_from_pair
from .report import summarize
from .scene import load_scene, parse_scene, run_scene
from .solve import Result, SolverSettings, simulate
from .stiffness import (
    FourierStiffness,
    PeriodicStiffness,
    PiecewiseStiffness,
    iso6336_stiffness,
    rectangular_stiffness,
)

__version__ = "0.1.0"

__all__ = [
    "FourierStiffness", "GearDynError", "GearPair", "InputError", "PeriodicStiffness",
    "PiecewiseStiffness", "Result", "SDOFModel", "SceneError", "SolverError", "SolverSettings",
    "iso6336_stiffness", "load_scene", "mesh_frequency", "output_speed", "parse_scene",
    "rectangular_stiffness", "run_scene", "sdof_from_pair", "simulate", "summarize",
]
