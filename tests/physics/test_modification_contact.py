"""Loaded contact with tip relief: load sharing, K_TPM, relief TE (Wang et al. 2024, eqs. 7-26)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gear_dyn.errors import InputError
from gear_dyn.geometry import GearPair
from gear_dyn.modification import (
    CURVES,
    ProfileModification,
    TipRelief,
    contact_state,
    loaded_contact,
)

TAIL = GearPair(23, 64, 6e-3, math.radians(22.5), 50e-3)
TORQUE = 1474.4
LOAD = TORQUE / TAIL.rb1


def parabola(s: np.ndarray) -> np.ndarray:
    """A single-pair stiffness peaking at the pitch point (shape of the potential-energy curve)."""
    x = (np.asarray(s) - TAIL.pitch_point) / 0.02
    return 4e8 * (1.0 - 0.3 * x**2)


def constant(s: np.ndarray) -> np.ndarray:
    return np.full(np.shape(s), 4e8)


def test_zero_relief_reproduces_unmodified_sharing_and_stiffness() -> None:
    for mod in (None, ProfileModification(TipRelief(0.0, 3e-3), TipRelief(0.0, 3e-3))):
        lc = loaded_contact(TAIL, parabola, TORQUE, mod)
        c = lc.cycle
        k_sum = c.stiffness.sum(axis=1)
        # Wang et al. (2024), eq. 17: S_i = K_i / sum K (rounding only)
        np.testing.assert_allclose(c.sharing, c.stiffness / k_sum[:, None], rtol=1e-12)
        np.testing.assert_allclose(c.secant_stiffness, k_sum, rtol=1e-12)
        ph = np.linspace(0, 1, 333, endpoint=False)
        np.testing.assert_allclose(lc.mesh_stiffness()(ph), lc.unmodified_stiffness()(ph),
                                   rtol=1e-12)
        np.testing.assert_allclose(lc.transmission_error().value(ph), 0.0, atol=1e-20)


def test_unmodified_single_contact_zone_is_between_b_and_d() -> None:
    lc = loaded_contact(TAIL, parabola, TORQUE)
    start, end = lc.single_contact_zone() or (np.nan, np.nan)
    # B = E - p_b and D = A + p_b; the along-path grid is one-sided at +-1e-9 p_b
    assert start == pytest.approx(TAIL.end_of_contact - TAIL.base_pitch, abs=1e-9)
    assert end == pytest.approx(TAIL.start_of_contact + TAIL.base_pitch, abs=1e-9)


def test_huge_relief_runs_in_single_contact_throughout() -> None:
    """Linear long relief C on both gears, constant K: two pairs are loaded only while the gaps
    differ by less than F/K, i.e. over a phase width (F / (K C)) L / p_b (closed form); every
    other phase is single contact, so a huge relief gives single contact throughout."""
    length = (TAIL.contact_ratio - 1) * TAIL.base_pitch
    k = 4e8
    for amount in (1e-4, 1e-3):
        mod = ProfileModification(TipRelief(amount, length), TipRelief(amount, length))
        ph = np.linspace(0, 1, 200001, endpoint=False)
        c = contact_state(TAIL, constant, LOAD, ph, mod)
        n_loaded = c.loaded.sum(axis=1)
        assert np.all(n_loaded >= 1) and np.all(n_loaded <= 2)
        width = LOAD / (k * amount) * length / TAIL.base_pitch
        # grid resolution 5e-6 cycles on each of the two ends of the interval
        assert np.mean(n_loaded == 2) == pytest.approx(width, abs=1e-5)
    assert width < 0.035  # 1 mm relief: single contact over more than 96.5 % of the cycle
    # with only the entering pair relieved, by 1 mm over 1.5 times the double-contact zone, its
    # gap at the single-contact point is still 333 um > F/K: one loaded pair at every phase
    mod = ProfileModification(gear=TipRelief(1e-3, 1.5 * length))
    lc = loaded_contact(TAIL, parabola, TORQUE, mod)
    assert np.all(lc.cycle.loaded.sum(axis=1) == 1)
    view = lc.along_path()
    # every load share is 0 or 1 (rounding only)
    assert np.all((np.abs(view.sharing) < 1e-12) | (np.abs(view.sharing - 1) < 1e-12))


def test_two_pair_load_sharing_closed_form() -> None:
    """Only the gear is relieved: in double contact delta = (F + K0 g0) / (K0 + K1) (eq. 10) and
    K_TPM = K0 + K1 - K0 g0 / delta (eq. 11)."""
    mod = ProfileModification(gear=TipRelief(150e-6, 6e-3, "linear"))
    ph = np.linspace(0.0, 0.58, 59)
    c = contact_state(TAIL, parabola, LOAD, ph, mod)
    k0, k1 = c.stiffness[:, 0], c.stiffness[:, 1]
    g0 = c.gap[:, 0]
    both = c.loaded[:, 0] & c.loaded[:, 1]
    assert both.sum() > 10 and (~both).sum() > 3  # the case covers both contact states
    delta = (LOAD + k0 * g0) / (k0 + k1)
    np.testing.assert_allclose(c.deflection[both], delta[both], rtol=1e-12)
    k_tpm = k0 + k1 - k0 * g0 / c.deflection
    np.testing.assert_allclose(c.secant_stiffness[both], k_tpm[both], rtol=1e-12)
    # single contact: the relieved pair's gap is larger than the other pair's deflection
    single = ~both
    np.testing.assert_allclose(c.deflection[single], LOAD / k1[single], rtol=1e-12)
    assert np.all(g0[single] >= c.deflection[single])


@settings(max_examples=40, deadline=None)
@given(
    a1=st.floats(0.0, 200e-6), a2=st.floats(0.0, 200e-6),
    l1=st.floats(0.5e-3, 20e-3), l2=st.floats(0.5e-3, 20e-3),
    curve=st.sampled_from(CURVES), torque=st.floats(1.0, 5000.0),
)
def test_sharing_bounded_and_loads_sum_to_total(a1: float, a2: float, l1: float, l2: float,
                                                curve: str, torque: float) -> None:
    mod = ProfileModification(TipRelief(a1, l1, curve), TipRelief(a2, l2, curve))
    load = torque / TAIL.rb1
    c = contact_state(TAIL, parabola, load, np.linspace(0, 1, 97, endpoint=False), mod)
    assert np.all(c.sharing >= 0.0) and np.all(c.sharing <= 1.0 + 1e-12)
    np.testing.assert_allclose(c.force.sum(axis=1), load, rtol=1e-12)
    # every loaded pair is compressed by delta - g_j >= 0; unloaded pairs have g_j >= delta
    comp = c.deflection[:, None] - c.gap
    assert np.all(comp[c.loaded] >= -1e-15)
    assert np.all(comp[~c.loaded & np.isfinite(c.gap)] <= 1e-15)
    # decomposition for dynamics: delta = F / k_t + e
    np.testing.assert_allclose(c.deflection, load / c.tangent_stiffness + c.relief_error,
                               rtol=1e-10)


def test_relief_softens_and_widens_single_zone() -> None:
    base = loaded_contact(TAIL, constant, TORQUE)
    length = 0.5 * (TAIL.contact_ratio - 1) * TAIL.base_pitch
    mod = ProfileModification(TipRelief(60e-6, length), TipRelief(60e-6, length))
    lc = loaded_contact(TAIL, constant, TORQUE, mod)
    zb, zm = base.single_contact_zone(), lc.single_contact_zone()
    assert zb is not None and zm is not None
    assert zm[0] < zb[0] and zm[1] > zb[1]
    # the load-dependent stiffness never exceeds the unmodified one (relief only removes contact)
    ph = np.linspace(0, 1, 501, endpoint=False)
    assert np.all(lc.mesh_stiffness()(ph) <= base.mesh_stiffness()(ph) * (1 + 1e-12))
    # the pick-up points are switching phases: the loaded-pair count is constant between them
    edges = lc.edges
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        c = contact_state(TAIL, constant, lc.load, np.linspace(a, b, 41)[1:-1], mod)
        assert np.unique(c.loaded.sum(axis=1)).size == 1


def test_piecewise_outputs_match_pointwise_solution() -> None:
    mod = ProfileModification(TipRelief(40e-6, 5e-3, "parabolic"), TipRelief(30e-6, 5e-3, "walker"))
    lc = loaded_contact(TAIL, parabola, TORQUE, mod, samples_per_segment=200)
    ph = np.linspace(0.003, 0.997, 157)
    ph = ph[np.min(np.abs(ph[:, None] - lc.edges[None, :]), axis=1) > 1e-6]
    c = contact_state(TAIL, parabola, LOAD, ph, mod)
    # linear interpolation of smooth pieces at 200 samples: error ~ (1/200)^2 * curvature, < 1e-4
    np.testing.assert_allclose(lc.mesh_stiffness()(ph), c.secant_stiffness, rtol=1e-4)
    np.testing.assert_allclose(lc.tangent_stiffness()(ph), c.tangent_stiffness, rtol=1e-4)
    np.testing.assert_allclose(lc.static_transmission_error().value(ph), c.deflection, rtol=1e-4)
    e = lc.transmission_error()
    h = 1e-7
    # slope is piecewise: compare with a central difference away from the jumps
    np.testing.assert_allclose(e.slope(ph), (e.value(ph + h) - e.value(ph - h)) / (2 * h),
                               rtol=1e-5, atol=1e-12)


def test_helical_pair_and_bad_stiffness_are_refused() -> None:
    hel = GearPair(23, 64, 6e-3, math.radians(20), 50e-3, helix_angle=math.radians(15))
    with pytest.raises(InputError, match="spur pairs only"):
        loaded_contact(hel, constant, 100.0)
    with pytest.raises(InputError, match="single-pair stiffness"):
        loaded_contact(TAIL, lambda s: -np.ones_like(s), 100.0)
    with pytest.raises(InputError, match="torque"):
        loaded_contact(TAIL, constant, 0.0)


def test_relief_length_and_exponent_trends() -> None:
    """Gear-tip relief, amount above the single-pair deflection. A longer relief lowers the
    entering pair's load everywhere (its gap C f(1 - d/L) grows with L); a larger exponent k
    opens a smaller gap inside the relief (u^k <= u on [0, 1]), so it never delays the pick-up
    and never lowers the entering pair's load: the printed trend 'a steeper curve exponent delays
    load pickup' does not hold at equal amount and length (docs/modification.md)."""
    long = (TAIL.contact_ratio - 1) * TAIL.base_pitch
    ph = np.linspace(0.0, TAIL.contact_ratio - 1 - 1e-6, 301)

    def entering_load(relief: TipRelief) -> np.ndarray:
        c = contact_state(TAIL, parabola, LOAD, ph, ProfileModification(gear=relief))
        return c.force[:, 0]

    loads = [entering_load(TipRelief(40e-6, f * long)) for f in (0.25, 0.5, 0.75, 1.0)]
    for a, b in zip(loads, loads[1:], strict=False):
        assert np.all(b <= a * (1 + 1e-12) + 1e-9) and np.sum(b) < np.sum(a)
    curves = [entering_load(TipRelief(40e-6, long, c))
              for c in ("linear", "yoshio", "walker", "parabolic")]
    pickup = [ph[np.argmax(f > 0)] for f in curves]
    for a, b in zip(curves, curves[1:], strict=False):
        assert np.all(b >= a * (1 - 1e-12) - 1e-9) and np.sum(b) > np.sum(a)
    assert all(q <= p for p, q in zip(pickup, pickup[1:], strict=False))
