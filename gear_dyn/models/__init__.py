"""Dynamic models: each offers the face described in :mod:`gear_dyn.models.base`."""

from .base import Model
from .sdof import SDOFModel, dead_zone, effective_mass, sdof_from_pair

__all__ = ["Model", "SDOFModel", "dead_zone", "effective_mass", "sdof_from_pair"]
