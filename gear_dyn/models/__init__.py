"""Dynamic models: each offers the face described in :mod:`gear_dyn.models.base`."""

from .base import Model
from .sdof import SDOFModel, dead_zone, effective_mass, sdof_from_pair
from .torsional import TorsionalModel

__all__ = ["Model", "SDOFModel", "TorsionalModel", "dead_zone", "effective_mass", "sdof_from_pair"]
