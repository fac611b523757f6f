"""Shared fixtures: the seed 002 helicopter tail pair and model."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from gear_dyn.geometry import GearPair

ROOT = Path(__file__).resolve().parent.parent
SCENES = ROOT / "examples" / "scenes"


@pytest.fixture
def heli_pair() -> GearPair:
    """Seed 002 equivalent spur pair: z 23/64, m 6 mm, 22.5 deg, B 50 mm, E 207 GPa."""
    return GearPair(23, 64, 6e-3, math.radians(22.5), 0.05,
                    youngs_modulus1=2.07e11, youngs_modulus2=2.07e11)


@pytest.fixture
def scenes_dir() -> Path:
    return SCENES
