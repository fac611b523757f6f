"""ISO 1328-1:2013 tolerances and the deviation patterns."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gear_dyn.errors import InputError
from gear_dyn.excitation import HarmonicSignal, SumSignal
from gear_dyn.modification.deviations import (
    Tolerances,
    iso1328_tolerances,
    pitch_pattern,
    sample_deviations,
    shaft_order_signal,
)
from gear_dyn.scene import build_pair, load_scene


def test_tolerances_follow_the_2013_formulas() -> None:
    """m_n = 3 mm, z = 40 (d = 120 mm), b = 30 mm, grade 6: the standard's formulas by hand
    (eqs. 5, 6, 8, 10-12; grade step sqrt 2)."""
    t = iso1328_tolerances(6, 3e-3, 120e-3, 30e-3)
    step = math.sqrt(2)
    d, m, b = 120.0, 3.0, 30.0
    assert t.f_pt * 1e6 == pytest.approx((0.001 * d + 0.4 * m + 5) * step, rel=1e-12)
    assert t.F_p * 1e6 == pytest.approx((0.002 * d + 0.55 * math.sqrt(d) + 0.7 * m + 12) * step)
    assert t.f_falpha * 1e6 == pytest.approx((0.55 * m + 5) * step)
    f_hb = 0.05 * math.sqrt(d) + 0.35 * math.sqrt(b) + 4
    f_fb = 0.07 * math.sqrt(d) + 0.45 * math.sqrt(b) + 4
    assert t.F_beta * 1e6 == pytest.approx(math.hypot(f_hb, f_fb) * step)
    # rounded as the standard's tables (5-10 um to 0.5, above 10 um to 1): 9.0 and 29 um
    assert round(t.f_pt * 1e6 * 2) / 2 == 9.0 and round(t.F_p * 1e6) == 29
    # two grades apart: a factor 2
    t8 = iso1328_tolerances(8, 3e-3, 120e-3, 30e-3)
    assert t8.F_p / t.F_p == pytest.approx(2.0)
    with pytest.raises(InputError, match="accuracy_grade"):
        iso1328_tolerances(12, 3e-3, 120e-3, 30e-3)


def test_random_pattern_stays_within_the_grade_and_repeats_by_seed() -> None:
    tol = Tolerances(8e-6, 25e-6, 9e-6, 12e-6)
    for seed in range(50):
        cum = pitch_pattern(23, tol, "random", np.random.default_rng(seed))
        single = np.diff(np.append(cum, cum[0]))  # closes over the revolution
        assert np.max(np.abs(single)) <= tol.f_pt * (1 + 1e-12)
        assert np.ptp(cum) <= tol.F_p * (1 + 1e-12)
    a = pitch_pattern(23, tol, "random", np.random.default_rng(3))
    b = pitch_pattern(23, tol, "random", np.random.default_rng(3))
    np.testing.assert_array_equal(a, b)
    sine = pitch_pattern(23, tol, "sine")
    # a sine of range F_p sampled at 23 teeth: its extremes within a quarter tooth of the peaks
    assert tol.F_p * math.cos(math.pi / 46) <= np.ptp(sine) <= tol.F_p
    with pytest.raises(InputError, match="pattern"):
        pitch_pattern(23, tol, "gaussian")


def test_shaft_order_signal_interpolates_every_tooth() -> None:
    for z in (23, 64):
        v = np.random.default_rng(z).normal(size=z) * 1e-6
        sig = shaft_order_signal(v, z)
        assert sig.period == z and sig.cos.size == z // 2
        np.testing.assert_allclose(sig.value(np.arange(z) + 5 * z), v - v.mean(), atol=1e-18)
        # the slope is the derivative of the value
        p = np.linspace(0, z, 97)
        h = 1e-6
        np.testing.assert_allclose(sig.slope(p), (sig.value(p + h) - sig.value(p - h)) / (2 * h),
                                   atol=1e-6 * np.max(np.abs(sig.slope(p))))


def test_pair_deviations_repeat_over_the_hunting_period() -> None:
    pair = build_pair(load_scene("helicopter_tail"))
    tol = (Tolerances(8e-6, 25e-6, 9e-6, 12e-6),) * 2
    dev = sample_deviations(pair, tol, "random", [7, 1])
    te = dev.transmission_error()
    assert isinstance(te, SumSignal) and te.period == 1472
    p = np.linspace(0, 40, 301)
    np.testing.assert_allclose(te.value(p + 1472), te.value(p), atol=1e-15)
    assert np.max(np.abs(te.value(p + 23) - te.value(p))) > 1e-7  # not the pinion's period
    # along the line of action: the reference-circle deviations times cos a_t
    cum = pitch_pattern(23, tol[0], "random", np.random.default_rng([7, 1]))
    np.testing.assert_allclose(dev.pitch_pinion, cum * math.cos(pair.alpha_t))
    with pytest.raises(InputError, match="seed"):
        sample_deviations(pair, tol, "random")
    with pytest.raises(InputError, match="period"):
        HarmonicSignal(0.0, np.ones(2), np.ones(2), period=2.5)  # type: ignore[arg-type]
