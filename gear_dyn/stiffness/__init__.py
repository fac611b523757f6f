"""Mesh stiffness: one periodic type, several methods that build it."""

from .iso6336 import IsoStiffness, iso6336_stiffness
from .periodic import (
    FourierStiffness,
    PeriodicStiffness,
    PiecewiseStiffness,
    rectangular_stiffness,
)

__all__ = [
    "FourierStiffness",
    "IsoStiffness",
    "PeriodicStiffness",
    "PiecewiseStiffness",
    "iso6336_stiffness",
    "rectangular_stiffness",
]
