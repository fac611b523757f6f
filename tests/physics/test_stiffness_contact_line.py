"""Contact-line length of the error-free pair (gear_dyn.stiffness.contact_line)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gear_dyn.geometry import GearPair
from gear_dyn.stiffness.contact_line import (
    contact_line_breakpoints,
    contact_line_length,
    mean_contact_line_length,
)

SPUR = GearPair(19, 48, 3.2e-3, math.radians(20), 16e-3)
HELICAL = GearPair(18, 70, 3e-3, math.radians(20), 30e-3, helix_angle=math.radians(15))
WIDE = GearPair(23, 64, 6e-3, math.radians(22.5), 50e-3, helix_angle=math.radians(25))


@pytest.mark.parametrize("pair", [SPUR, HELICAL, WIDE])
def test_mean_equals_b_eps_over_cos_beta_b(pair: GearPair) -> None:
    # Identity (docs/stiffness.md): the mean over a mesh cycle equals B eps_a / cos b_b.
    # The mean is taken numerically with the midpoint rule on 200 001 phases; L(p) is piecewise
    # linear, so the rule's error is below (jump or kink size) / n ~ 1e-5 relative.
    n = 200_001
    p = (np.arange(n) + 0.5) / n
    mean = float(np.mean(contact_line_length(pair, p)))
    expected = pair.face_width * pair.contact_ratio / math.cos(pair.beta_b)
    assert mean == pytest.approx(expected, rel=2e-5)
    assert mean_contact_line_length(pair) == pytest.approx(expected, rel=1e-12)


def test_spur_counts_pairs_times_face_width() -> None:
    # Spur: during the first frac(eps_a) of the cycle two pairs touch (2 B), then one (B).
    f = SPUR.contact_ratio % 1.0
    p = np.array([0.0, 0.5 * f, f - 1e-9, f + 1e-9, 0.99])
    expected = SPUR.face_width * np.array([2, 2, 2, 1, 1])
    np.testing.assert_allclose(contact_line_length(SPUR, p), expected, rtol=1e-12)


@pytest.mark.parametrize("pair", [HELICAL, WIDE])
def test_helical_equals_sum_of_spur_slices(pair: GearPair) -> None:
    # Second method: slice the face into N thin spur slices, each shifted along the path by
    # z tan b_b, and count the slices in contact; each contributes dz / cos b_b of line length.
    # Slicing error ~ (lines in contact) * dz / cos b_b at most = 4 * B / N.
    n = 20_000
    z = (np.arange(n) + 0.5) / n * pair.face_width
    p = np.linspace(0.0, 1.0, 37)
    ga, pb = pair.path_of_contact, pair.base_pitch
    tb = math.tan(pair.beta_b)
    lengths = []
    for ph in p:
        total = 0.0
        for j in range(8):
            u = (ph + j) * pb - z * tb
            total += np.count_nonzero((u >= 0) & (u <= ga))
        lengths.append(total * pair.face_width / n / math.cos(pair.beta_b))
    np.testing.assert_allclose(contact_line_length(pair, p), lengths,
                               atol=4 * pair.face_width / n)


def test_periodic_and_shape() -> None:
    # Period 1 in phase by construction of the phase convention; shape follows the input.
    p = np.linspace(-2.0, 2.0, 41).reshape(41, 1)
    out = contact_line_length(WIDE, p)
    assert out.shape == (41, 1)
    np.testing.assert_allclose(out, contact_line_length(WIDE, p + 3.0), rtol=1e-9)


def test_breakpoints_are_the_kinks() -> None:
    # Between breakpoints L is linear: the midpoint equals the mean of the ends (exact to rounding).
    bp = np.append(contact_line_breakpoints(WIDE), 1.0)
    eps = 1e-9
    for lo, hi in zip(bp[:-1], bp[1:], strict=True):
        a, b = lo + eps, hi - eps
        ends = contact_line_length(WIDE, np.array([a, b]))
        mid = contact_line_length(WIDE, 0.5 * (a + b))
        assert float(mid) == pytest.approx(0.5 * float(ends.sum()), rel=1e-7)
