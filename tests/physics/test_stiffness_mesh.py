"""Mesh stiffness over a cycle: pairs add, switching phases, Fourier series, selector, centre
distance."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from gear_dyn.errors import InputError
from gear_dyn.geometry import GearPair, involute
from gear_dyn.stiffness import (
    build_stiffness,
    iso6336_stiffness,
    mesh_stiffness_from_pair,
    potential_energy_pair_stiffness,
)
from gear_dyn.stiffness.select import stiffness_options_from_table
from gear_dyn.stiffness.summary import operating_summary, stiffness_summary

CLASSIC = GearPair(19, 48, 3.2e-3, math.radians(20), 16e-3, youngs_modulus1=206.8e9,
                   youngs_modulus2=206.8e9)
TAIL = GearPair(23, 64, 6e-3, math.radians(22.5), 50e-3, youngs_modulus1=207e9,
                youngs_modulus2=207e9)
HELICAL = GearPair(25, 60, 3e-3, math.radians(20), 30e-3, helix_angle=math.radians(15))


def test_constant_pair_counts_pairs() -> None:
    # K = const: k(p) = (pairs in contact) * K; mean = eps_a * K exactly (the pair count averages
    # to eps_a over a cycle); switching at 0 and frac(eps_a). Exact arithmetic: rel 1e-12.
    k = mesh_stiffness_from_pair(CLASSIC, lambda p, s: np.full(np.shape(s), 1e8))
    f = CLASSIC.contact_ratio - 1
    np.testing.assert_allclose(k.switching_phases, [0.0, f], atol=1e-15)
    assert k.mean == pytest.approx(CLASSIC.contact_ratio * 1e8, rel=1e-12)
    np.testing.assert_allclose(k(np.array([0.01, f - 1e-6, f + 1e-6, 0.99])),
                               [2e8, 2e8, 1e8, 1e8], rtol=1e-12)


def test_pairs_add_in_parallel() -> None:
    # Direct evaluation: in the double zone k(p) = K(A + p p_b) + K(A + (p + 1) p_b), in the
    # single zone k(p) = K(A + p p_b). Tolerance 1e-9: the curve is sampled at these phases
    # (linspace over each segment) so interpolation adds nothing there.
    k = mesh_stiffness_from_pair(CLASSIC, potential_energy_pair_stiffness, samples_per_cycle=200)
    a, pb = CLASSIC.start_of_contact, CLASSIC.base_pitch
    ph0, _ = k.samples[0]
    ph1, _ = k.samples[1]
    p, q = ph0[3:6], ph1[3:6]
    exp0 = (potential_energy_pair_stiffness(CLASSIC, a + p * pb)
            + potential_energy_pair_stiffness(CLASSIC, a + (p + 1) * pb))
    exp1 = potential_energy_pair_stiffness(CLASSIC, a + q * pb)
    np.testing.assert_allclose(k(p), exp0, rtol=1e-9)
    np.testing.assert_allclose(k(q), exp1, rtol=1e-9)


def test_jumps_at_entry_and_exit() -> None:
    # At exit (p = f) the mesh loses the pair at E: the jump equals K(E). At entry (p = 0) it gains
    # the pair at A: the jump equals K(A). Tolerance 1e-6: one-sided limits at +-1e-10 cycles.
    k = build_stiffness(CLASSIC, "potential_energy")
    f = CLASSIC.contact_ratio - 1
    ke = float(potential_energy_pair_stiffness(CLASSIC, CLASSIC.end_of_contact))
    ka = float(potential_energy_pair_stiffness(CLASSIC, CLASSIC.start_of_contact))
    d = 1e-10
    assert float(k(f - d) - k(f + d)) == pytest.approx(ke, rel=1e-6)
    assert float(k(d) - k(1 - d)) == pytest.approx(ka, rel=1e-6)


@pytest.mark.parametrize("method", ["rectangular", "potential_energy", "weber"])
def test_fourier_series_converges_away_from_jumps(method: str) -> None:
    # Truncated Fourier series of a piecewise-smooth function with jumps converges pointwise as
    # O(1/N) away from the jumps (Gibbs overshoot stays near them). Points farther than 0.05
    # cycles from a switching phase: error(5) > error(40) > error(400), and the 400-term error is
    # below 1 % of the mean (O(jump / (pi N d)) ~ 0.3 % for these curves).
    k = build_stiffness(CLASSIC, method)
    p = np.linspace(0.0, 1.0, 2001)
    sw = np.append(k.switching_phases, 1.0)
    dist = np.min(np.abs(p[:, None] - sw[None, :]), axis=1)
    far = p[dist > 0.05]
    exact = k(far)
    errs = [float(np.max(np.abs(k.truncated(n)(far) - exact))) for n in (5, 40, 400)]
    assert errs[0] > errs[1] > errs[2]
    assert errs[2] < 0.01 * k.mean
    # means are preserved by every truncation (the constant term is the mean)
    assert k.truncated(5).mean == pytest.approx(k.mean, rel=1e-12)


def test_parseval_for_pem_curve() -> None:
    # Second method: Parseval, k0^2 + sum (a_n^2 + b_n^2)/2 -> mean of k^2 (dense midpoint rule
    # with 200 001 points; jump error ~ 1e-5). The series' tail beyond 2000 harmonics of a
    # piecewise-smooth curve is O(jump^2 / N) ~ 1e-4 relative.
    k = build_stiffness(CLASSIC, "potential_energy")
    k0, a, b = k.fourier_coefficients(2000)
    n = 200_001
    p = (np.arange(n) + 0.5) / n
    assert k0**2 + 0.5 * float(np.sum(a**2 + b**2)) == pytest.approx(
        float(np.mean(k(p) ** 2)), rel=3e-4)


def test_selector_iso_and_contact_line_means() -> None:
    # Decision kept: rectangular/iso6336 use k_single = c' b, k_double = 1.75 c' b, whose mean is
    # c_gamma b exactly for 1 < eps_a < 2; contact_line scales L(p) to the same mean. Rel 1e-12.
    for pair in (CLASSIC, TAIL):
        iso = iso6336_stiffness(pair)
        for method in ("rectangular", "iso6336"):
            k = build_stiffness(pair, method)
            assert k.mean == pytest.approx(iso.k_mesh, rel=1e-12)
            assert k.min == pytest.approx(iso.k_single, rel=1e-12)
            assert k.max == pytest.approx(1.75 * iso.k_single, rel=1e-12)
    k = build_stiffness(HELICAL, "contact_line")
    assert k.mean == pytest.approx(iso6336_stiffness(HELICAL).k_mesh, rel=1e-9)
    # high contact ratio (eps_a = 2.25): n pairs -> c' b (0.75 n + 0.25) keeps the mean exact
    high = GearPair(40, 90, 2e-3, math.radians(20), 20e-3, addendum_coef=1.3, clearance_coef=0.3)
    iso = iso6336_stiffness(high)
    k = build_stiffness(high, "iso6336")
    assert high.contact_ratio > 2
    assert k.mean == pytest.approx(iso.k_mesh, rel=1e-12)
    assert (k.min, k.max) == pytest.approx((1.75 * iso.k_single, 2.5 * iso.k_single), rel=1e-12)
    user = build_stiffness(CLASSIC, "rectangular", single=2e8, double=3e8)
    assert (user.min, user.max) == (2e8, 3e8)
    assert build_stiffness(CLASSIC, "rectangular", single=2e8).max == pytest.approx(3.5e8)


def test_mean_is_path_integral_over_base_pitch() -> None:
    # Each pair crosses the whole path A..E once per tooth, so the cycle mean of the summed
    # stiffness is (1/p_b) int_A^E K(s) ds (independent of how the phases are sampled).
    # Second method: scipy quad of the pair function. Spur: rel 2e-4 (linear interpolation
    # between 200 samples of a smooth convex/concave curve).
    ref = quad(lambda s: float(potential_energy_pair_stiffness(CLASSIC, s)),
               CLASSIC.start_of_contact, CLASSIC.end_of_contact,
               epsabs=0, epsrel=1e-6, limit=200)[0]
    k = build_stiffness(CLASSIC, "potential_energy")
    assert k.mean == pytest.approx(ref / CLASSIC.base_pitch, rel=2e-4)


def test_helical_pem_is_continuous_and_flatter() -> None:
    # Thin-slice helical model: the overlap smears the entries and exits, so the curve has no
    # jumps (continuous slicing, sampled 400 times per cycle) and a smaller
    # relative fluctuation than one slice (the transverse curve); shifting the slices does not
    # change the mean, (1/p_b) int_A^E K ds (rel 1e-3: linear interpolation between samples of
    # the averaged curve and of the fine transverse curve).
    k = build_stiffness(HELICAL, "potential_energy", samples_per_cycle=400)
    v = k(np.linspace(0, 1, 4001))
    assert np.max(np.abs(np.diff(v))) < 0.01 * k.mean
    one = build_stiffness(HELICAL, "potential_energy", slices=1)
    assert (k.max - k.min) / k.mean < 0.5 * (one.max - one.min) / one.mean
    ref = quad(lambda s: float(potential_energy_pair_stiffness(HELICAL, s)),
               HELICAL.start_of_contact, HELICAL.end_of_contact,
               epsabs=0, epsrel=1e-6, limit=200)[0]
    assert k.mean == pytest.approx(ref / HELICAL.base_pitch, rel=1e-3)


def test_continuous_face_slicing_is_the_limit_of_discrete_slices() -> None:
    # Default helical model: the face sliced continuously (exact antiderivative of the transverse
    # curve). Second method: 400 discrete slices; they differ by the slice staircase, jumps of
    # K/400 -> rel 3e-3 pointwise.
    k = build_stiffness(HELICAL, "potential_energy")
    d = build_stiffness(HELICAL, "potential_energy", slices=400)
    p = np.linspace(0, 1, 1001)
    np.testing.assert_allclose(k(p), d(p), rtol=3e-3)


def test_centre_distance_offset_follows_everywhere() -> None:
    # As in Jiang et al. (2018): a shaft offset d_a = 0.3 mm widens the centre distance.
    # Independent closed forms:
    #   cos a_wt = a cos a / a_w;   backlash along the line of action for nominal-thickness
    #   standard teeth j = (z1 + z2) m cos a (inv a_wt - inv a) (involute tooth-space arithmetic),
    #   approximately 2 d_a sin a for small d_a (within 2 %).
    da = 0.3e-3
    base = TAIL
    shifted = GearPair(23, 64, 6e-3, math.radians(22.5), 50e-3, youngs_modulus1=207e9,
                       youngs_modulus2=207e9, center_distance=base.a_w + da)
    a = math.radians(22.5)
    awt = math.acos(base.a_w * math.cos(a) / (base.a_w + da))
    j = (23 + 64) * 6e-3 * math.cos(a) * (involute(awt) - involute(a))
    op = operating_summary(shifted)
    assert op["backlash_m"] == pytest.approx(j, rel=1e-9)
    assert op["backlash_m"] == pytest.approx(2 * da * math.sin(a), rel=0.02)
    assert op["center_distance_offset_m"] == pytest.approx(da, rel=1e-9)
    # contact ratio and single-tooth share
    assert shifted.contact_ratio < base.contact_ratio
    assert op["single_contact_share"] == pytest.approx(2 - shifted.contact_ratio, rel=1e-12)
    # every method's switching phase moves to the new frac(eps_a); mean stiffness drops
    for method in ("iso6336", "potential_energy", "weber", "contact_line"):
        k0, k1 = build_stiffness(base, method), build_stiffness(shifted, method)
        assert k1.switching_phases[1] == pytest.approx(shifted.contact_ratio - 1, abs=1e-12)
        assert k1.mean < k0.mean


def test_summary_zone_values() -> None:
    # Rectangular: the zone means are its two levels exactly; PEM: the zone means bracket the mean.
    pair = CLASSIC
    iso = iso6336_stiffness(pair)
    s = stiffness_summary(pair, build_stiffness(pair, "iso6336"))
    assert s["single_pair_n_per_m"] == pytest.approx(iso.k_single, rel=1e-12)
    assert s["double_pair_n_per_m"] == pytest.approx(1.75 * iso.k_single, rel=1e-12)
    pem = stiffness_summary(pair, build_stiffness(pair, "potential_energy"))
    assert pem["single_pair_n_per_m"] < pem["mean_n_per_m"] < pem["double_pair_n_per_m"]
    assert (pem["pairs_low"], pem["pairs_high"]) == (1, 2)


def test_selector_refuses_bad_input() -> None:
    with pytest.raises(InputError, match="valid values are"):
        build_stiffness(CLASSIC, "fem")
    with pytest.raises(InputError, match="unknown option"):
        build_stiffness(CLASSIC, "potential_energy", slicez=3)
    with pytest.raises(InputError, match="takes no single/double"):
        build_stiffness(CLASSIC, "iso6336", single=1e8)
    with pytest.raises(InputError, match="fourier_terms"):
        build_stiffness(CLASSIC, "iso6336", fourier_terms=0)
    with pytest.raises(InputError, match="does not apply to method"):
        stiffness_options_from_table({"method": "iso6336", "weber_slices": 4})
    with pytest.raises(InputError, match="numbers, strings or booleans"):
        build_stiffness(CLASSIC, "rectangular", single=[1e8])
    with pytest.raises(InputError, match="bore_radius1"):
        build_stiffness(CLASSIC, "potential_energy", bore_radius1=0.05)


def test_scalar_and_array_evaluation_agree() -> None:
    # PiecewiseStiffness has a plain-Python scalar path for the solver's right-hand side; it must
    # give the array path's values (np.searchsorted + np.interp) to rounding, also exactly at the
    # switching phases and sample points, and for phases outside [0, 1).
    rng = np.random.default_rng(7)
    for method in ("potential_energy", "contact_line", "iso6336"):
        for pair in (CLASSIC, HELICAL):
            k = build_stiffness(pair, method)
            p = np.concatenate([rng.uniform(-3, 3, 500), k.switching_phases,
                                k.switching_phases + 2, [0.0, 1.0, 1 - 1e-17]])
            scalar = np.array([float(k(float(v))) for v in p])
            np.testing.assert_allclose(scalar, k(p), rtol=1e-14)
