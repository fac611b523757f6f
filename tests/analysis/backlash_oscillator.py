"""The test model of test_continuation, test_detect and test_fold_curve: m = 1 kg, a rectangular
mesh stiffness (contact ratio 1.6, 0.8e6 / 1.2e6 N/m; piecewise constant, so every map is the
backlash oscillator's piecewise closed form), half gap 1 mm, 20 pinion teeth."""

from __future__ import annotations

import math

from gear_dyn import SDOFModel, rectangular_stiffness

K = rectangular_stiffness(1.6, 8e5, 1.2e6)
B = 1e-3  # half gap, m
TEETH = 20
WN = math.sqrt(K.mean / 1.0)  # rad/s


def oscillator(load: float = 1040.0, xi: float = 0.05, backlash: float | None = B) -> SDOFModel:
    """The model at static load ``load`` (N, 1040 N: 1 mm static deflection), damping ratio
    ``xi`` and half gap ``backlash`` (m), at a 100 Hz mesh frequency until a family sets it."""
    return SDOFModel(1.0, K, xi, load, 100.0, backlash=backlash)
