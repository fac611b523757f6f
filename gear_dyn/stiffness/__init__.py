"""Mesh stiffness: one periodic type, several methods that build it.

``build_stiffness(pair, method, **options)`` is the single entry point; the single-pair functions
(``potential_energy_pair_stiffness``, ``weber_pair_stiffness``) and the generic builder
``mesh_stiffness_from_pair`` are public for models that need the pair stiffness K_i(s).
"""

from gear_dyn.stiffness.contact_line import contact_line_length, mean_contact_line_length
from gear_dyn.stiffness.iso6336 import IsoStiffness, iso6336_stiffness
from gear_dyn.stiffness.mesh import mesh_stiffness_from_pair
from gear_dyn.stiffness.periodic import (
    FourierStiffness,
    PeriodicStiffness,
    PiecewiseStiffness,
    rectangular_stiffness,
)
from gear_dyn.stiffness.potential_energy import (
    PairCompliance,
    potential_energy_compliances,
    potential_energy_pair_stiffness,
)
from gear_dyn.stiffness.select import METHODS, build_stiffness
from gear_dyn.stiffness.tooth import ToothOptions
from gear_dyn.stiffness.weber import weber_compliances, weber_pair_stiffness

__all__ = [
    "METHODS",
    "FourierStiffness",
    "IsoStiffness",
    "PairCompliance",
    "PeriodicStiffness",
    "PiecewiseStiffness",
    "ToothOptions",
    "build_stiffness",
    "contact_line_length",
    "iso6336_stiffness",
    "mean_contact_line_length",
    "mesh_stiffness_from_pair",
    "potential_energy_compliances",
    "potential_energy_pair_stiffness",
    "rectangular_stiffness",
    "weber_compliances",
    "weber_pair_stiffness",
]
