"""Shared fixtures (the helicopter tail pair of Jiang et al. 2018) and the hypothesis profiles.

Property tests are derandomized by default (profile ``ci``): the same examples on every run
and machine, so a verdict never depends on the draw; a bug a property test once found is kept
as an explicit ``@example``. Longer randomized runs are a separate command:
``GEAR_DYN_HYPOTHESIS=random python -m pytest tests/scene/test_scene_fuzz.py``.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import pytest
from hypothesis import settings

from gear_dyn.geometry import GearPair

settings.register_profile("ci", derandomize=True, print_blob=True)
settings.register_profile("random", derandomize=False, print_blob=True)
settings.load_profile(os.environ.get("GEAR_DYN_HYPOTHESIS", "ci"))

ROOT = Path(__file__).resolve().parent.parent
SCENES = ROOT / "examples" / "scenes"


@pytest.fixture
def heli_pair() -> GearPair:
    """The helicopter tail pair as an equivalent spur pair: z 23/64, m 6 mm, 22.5 deg, B 50 mm,
    E 207 GPa."""
    return GearPair(23, 64, 6e-3, math.radians(22.5), 0.05,
                    youngs_modulus1=2.07e11, youngs_modulus2=2.07e11)


@pytest.fixture
def scenes_dir() -> Path:
    return SCENES
