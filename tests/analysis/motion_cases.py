"""Scenes of the motion tests: the packaged backlash pair made to show period-n orbits and chaos.

- :func:`te_scene`: constant mesh stiffness (1e9 N/m) excited by a 10 um transmission error
  (as tests/analysis/test_sweep_aperiodic.py and issue 25): heavy separation near
  f_m / f_n = 1.2..1.6, period doubling. The exact flow does not apply (a TE): DOP853 with
  located contact changes.
- :func:`parametric_scene`: rectangular stiffness 0.5e9 / 1.5e9 N/m, damping ratio 0.02, no TE:
  the parametric resonance near f_m = 2 f_n with backlash; chaos near f_m / f_n = 2.0, a
  period-4 orbit at 2.08, period-2 at 2.24 (a bifurcation diagram shows them). Piecewise-constant
  stiffness: the exact flow applies.
"""

from __future__ import annotations

import math
import tomllib
from typing import Any

from gear_dyn.scene import build_model, parse_scene
from gear_dyn.scene.packaged import scene_path
from gear_dyn.scene.sweep import model_at_speed

Z1 = 23  # pinion teeth of the packaged pair: f_m = Z1 w / 2 pi


def _scene(stiffness: dict[str, str], damping: float, te: bool) -> Any:
    data = tomllib.loads(scene_path("helicopter_tail_backlash").read_text())
    data["stiffness"] = {"method": "rectangular", **stiffness}
    data["damping"] = {"ratio": damping}
    if te:
        data["transmission_error"] = {"cos": ["10 um"]}
    return parse_scene(data, "motion_case.toml")


def te_scene() -> Any:
    """Constant stiffness, 10 um transmission error, damping ratio 0.06 (the packaged one)."""
    return _scene({"single": "1e9 N/m", "double": "1e9 N/m"}, 0.06, True)


def parametric_scene() -> Any:
    """Rectangular stiffness 0.5e9 / 1.5e9 N/m, damping ratio 0.02, no transmission error."""
    return _scene({"single": "0.5e9 N/m", "double": "1.5e9 N/m"}, 0.02, False)


def speed_of(scene: Any, ratio: float) -> float:
    """Pinion speed in rad/s where f_m / f_n = ``ratio``."""
    return ratio * build_model(scene).natural_frequency * 2 * math.pi / Z1


def model_of(scene: Any, ratio: float) -> Any:
    """The scene's model at f_m / f_n = ``ratio``."""
    return model_at_speed(scene, speed_of(scene, ratio))
