"""Dynamic models: each offers the face described in :mod:`gear_dyn.models.base`."""

from gear_dyn.models.base import Model
from gear_dyn.models.sdof import SDOFModel, dead_zone, effective_mass, sdof_from_pair
from gear_dyn.models.torsional import TorsionalModel

__all__ = ["Model", "SDOFModel", "TorsionalModel", "dead_zone", "effective_mass", "sdof_from_pair"]
