"""Slice-method loaded tooth contact analysis (spur and helical): checks against the spur loaded
contact, equilibrium, the contact-line length of Liu et al. (2017), ISO 6336-1, a closed form of
a crowned contact, the discrete beam on an elastic foundation, and convergence."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from gear_dyn.errors import InputError
from gear_dyn.geometry import GearPair
from gear_dyn.modification import recommended_relief
from gear_dyn.modification.contact import contact_state
from gear_dyn.modification.lead import FlankModification, LeadModification, Misalignment
from gear_dyn.modification.slice_contact import SliceOptions, pasternak_solve, slice_contact
from gear_dyn.stiffness.contact_line import contact_line_length
from gear_dyn.stiffness.iso6336 import iso6336_stiffness
from gear_dyn.stiffness.potential_energy import potential_energy_pair_stiffness

#: the rail pair: 23/79, m_n 6 mm, 20 deg, helix 20 deg, B 70 mm, x = +0.3 / -0.1
RAIL = GearPair(23, 79, 6e-3, math.radians(20), 70e-3, math.radians(20), x1=0.3, x2=-0.1)
TAIL = GearPair(23, 64, 6e-3, math.radians(22.5), 50e-3)


def pe(pair: GearPair):  # noqa: ANN201
    return lambda s: potential_energy_pair_stiffness(pair, s)


def test_helix_zero_equals_spur_loaded_contact() -> None:
    """A spur pair sliced (all slices at one roll distance) is the spur analysis of .contact:
    same approach, tangent stiffness and pair loads at the same phases (both use K(s) at the
    same positions, so only rounding separates them)."""
    mod = recommended_relief(TAIL, 1474.4, "wang2024").modification()
    fn = pe(TAIL)
    r = slice_contact(TAIL, 1474.4, FlankModification(profile=mod), fn,
                      SliceOptions(slices=7, positions=40))
    ref = contact_state(TAIL, fn, 1474.4 / TAIL.rb1, r.phase, mod)
    np.testing.assert_allclose(r.deflection[0], ref.deflection, rtol=1e-9)
    np.testing.assert_allclose(r.tangent_stiffness[0], ref.tangent_stiffness, rtol=1e-9)
    n = ref.force.shape[1]
    pair_load = np.zeros_like(ref.force)
    pair_load[:, :min(n, r.pair_load.shape[2])] = r.pair_load[0][:, :n]
    np.testing.assert_allclose(pair_load, ref.force, rtol=1e-9, atol=1e-9 * ref.force.max())
    # the slices of one pair share its load evenly: the coupling has nothing to do
    loaded = r.load[0] > 0
    hi = np.where(loaded, r.load[0], -np.inf).max(axis=2)
    lo = np.where(loaded, r.load[0], np.inf).min(axis=2)
    some = loaded.any(axis=2)
    np.testing.assert_allclose(hi[some], lo[some], rtol=1e-9)


def test_slice_loads_sum_to_the_normal_load_and_are_never_negative() -> None:
    mod = FlankModification(
        profile=recommended_relief(RAIL, 2000.0, "handbook").modification("parabolic"),
        lead_pinion=LeadModification(crowning=12e-6, end_relief=5e-6, end_relief_length=8e-3),
        lead_gear=LeadModification(helix_slope=-6e-6),
        misalignment=Misalignment(f_ma=8e-6, f_sigma_beta=5e-6),
    )
    r = slice_contact(RAIL, [400.0, 2000.0], mod)
    f_n = np.array([400.0, 2000.0]) / (RAIL.rb1 * math.cos(RAIL.beta_b))
    np.testing.assert_allclose(r.load.sum(axis=(2, 3)), f_n[:, None] * np.ones((1, r.phase.size)),
                               rtol=1e-10)
    assert np.all(r.load >= 0.0)
    assert np.all(r.load[:, np.isnan(r.position)] == 0.0)  # no load out of contact
    np.testing.assert_allclose(r.sharing.sum(axis=2), 1.0, rtol=1e-10)


def _overlap_pair(eps_b: float) -> GearPair:
    return replace(RAIL, face_width=eps_b * RAIL.base_pitch / math.tan(RAIL.beta_b))


def test_integer_overlap_ratio_gives_small_te_fluctuation() -> None:
    """Liu et al. (2017): with an integer overlap ratio the total contact-line length is
    constant, so an unmodified pair's static TE barely fluctuates; eps_b = n + 0.5 leaves the
    line length fluctuating. Independent slices isolate that effect (what is left comes from
    the stiffness varying along the path: measured ratios 0.04 and 0.12 at n = 1, 2). The
    coupled slices add the support a line gets from the rest of the tooth, which changes as the
    line ends move along the face edges (ratios 0.42 and 0.36; 60 slices, 64 positions)."""
    ph = np.linspace(0, 1, 101)
    for n in (1, 2):
        whole, half = _overlap_pair(n), _overlap_pair(n + 0.5)
        assert np.ptp(contact_line_length(whole, ph)) < 1e-12
        for lam, ratio in ((0.0, 0.2), (None, 0.5)):
            opts = SliceOptions(slices=60, positions=64, coupling_length=lam)
            # same line load (torque in proportion to the face width)
            te = [slice_contact(p, 2000.0 * p.face_width / RAIL.face_width,
                                options=opts).peak_to_peak_te[0] for p in (whole, half)]
            assert te[0] < ratio * te[1], (n, lam, te)


def test_mean_loaded_stiffness_against_iso6336() -> None:
    """ISO 6336-1 method B: c' = c'_th C_M C_R C_B cos(b) with C_M = 0.8 the correction from the
    theoretical to the measured stiffness, so an elastic model is compared with c_gamma b / C_M.
    Independent slices are the potential-energy method (stated spread [0.85, 1.25] of ISO
    c_gamma b, docs/stiffness.md); the coupled slices (stiffer: the unloaded rest of the tooth
    helps) within +-15 % of the theoretical ISO value, the same band width."""
    iso = iso6336_stiffness(RAIL).k_mesh
    free = slice_contact(RAIL, 2000.0, options=SliceOptions(coupling_length=0.0))
    assert 0.85 < free.mean_secant_stiffness[0] / iso < 1.25
    coupled = slice_contact(RAIL, 2000.0)
    assert abs(coupled.mean_secant_stiffness[0] / (iso / 0.8) - 1.0) < 0.15
    assert coupled.mean_secant_stiffness[0] > free.mean_secant_stiffness[0]


@pytest.mark.parametrize("f_ma", [-12e-6, 0.0, 20e-6])
def test_crowned_contact_centre_moves_as_the_closed_form(f_ma: float) -> None:
    """Crowning C_b and misalignment f: gap (4 C_b / B^2) y_c^2 + (f / B) y_c is a parabola
    with its vertex at y_c = -f B / (8 C_b). On a uniform foundation (a spur pair: one roll
    distance across the face) the load is symmetric about the vertex while the loaded zone stays
    inside the face: the load centre sits at B/2 - f B / (8 C_b). Independent slices: within the
    slice width's rounding of a truncated parabola (dy / 4); coupled slices (a free-free beam on
    a Pasternak foundation): the ends pull the centre by less than 2 % of B here."""
    b, c_b = TAIL.face_width, 60e-6
    mod = FlankModification(lead_pinion=LeadModification(crowning=c_b),
                            misalignment=Misalignment(f_ma=f_ma))
    expect = 0.5 * b - f_ma * b / (8 * c_b)
    for lam, tol in ((0.0, 0.25 * b / 80), (None, 0.02 * b)):
        r = slice_contact(TAIL, 300.0, mod, options=SliceOptions(slices=80, positions=8,
                                                                  coupling_length=lam))
        loaded = r.load[0].sum(axis=1) > 0  # (P, S): the zone stays off the face ends
        assert not loaded[:, 0].any() and not loaded[:, -1].any()
        np.testing.assert_allclose(r.load_centre[0], expect, atol=tol)


def test_coupling_decays_as_a_beam_on_elastic_foundation() -> None:
    """A unit load on one slice of a long row: the structural deflection decays by the root r
    of k_c r^2 - (k_w + 2 k_c) r + k_c = 0 per slice (the discrete exp(-|y| / lambda))."""
    k_w, k_c, n = 2e7, 5e7, 101
    load = np.zeros(n)
    load[50] = 1.0
    col = pasternak_solve(np.full(n, k_w), k_c, load)
    q = (k_w + 2 * k_c) / k_c
    r = (q - math.sqrt(q * q - 4)) / 2
    np.testing.assert_allclose(col[51:60] / col[50:59], r, rtol=1e-9)
    np.testing.assert_allclose(col[50], 1 / math.sqrt(k_w * (k_w + 4 * k_c)), rtol=1e-9)
    # the dense matrix gives the same deflections (a second method)
    lap = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    lap[0, 0] = lap[-1, -1] = 1.0
    dense = np.linalg.solve(k_w * np.eye(n) + k_c * lap, load)
    np.testing.assert_allclose(col, dense, rtol=1e-9, atol=1e-12 * dense.max())


def test_doubling_slices_and_positions_changes_ppte_below_one_percent() -> None:
    coarse = slice_contact(RAIL, 2000.0, options=SliceOptions(slices=60, positions=64))
    fine = slice_contact(RAIL, 2000.0, options=SliceOptions(slices=120, positions=128))
    assert abs(fine.peak_to_peak_te[0] / coarse.peak_to_peak_te[0] - 1.0) < 0.01


def test_torque_ladder_equals_single_torques() -> None:
    mod = FlankModification(lead_pinion=LeadModification(crowning=15e-6))
    ladder = slice_contact(RAIL, [500.0, 2000.0], mod, options=SliceOptions(10, 8))
    one = slice_contact(RAIL, 2000.0, mod, options=SliceOptions(10, 8))
    np.testing.assert_allclose(ladder.at(1).deflection, one.deflection, rtol=1e-12)
    np.testing.assert_allclose(ladder.at(1).load, one.load, rtol=1e-10, atol=1e-9)
    d = one.to_dict()
    assert d["summary"][0]["peak_to_peak_static_te_m"] == pytest.approx(
        float(one.peak_to_peak_te[0]))
    assert len(one.position_table()["phase"]) == one.phase.size
    np.testing.assert_array_equal(ladder.at(-1).load, ladder.at(1).load)
    rows = one.slice_table()
    assert rows["load_n"].size == int(np.isfinite(one.position).sum())
    assert rows["load_n"].sum() == pytest.approx(one.load.sum(), rel=1e-12)
    with pytest.raises(InputError, match="torque index"):
        ladder.at(2)


def test_bad_input_is_refused() -> None:
    with pytest.raises(InputError, match="torque"):
        slice_contact(RAIL, 0.0)
    with pytest.raises(InputError, match="slices"):
        SliceOptions(slices=0)
    with pytest.raises(InputError, match="end_relief_length"):
        LeadModification(end_relief=5e-6)
    with pytest.raises(InputError, match="single-pair stiffness"):
        slice_contact(RAIL, 100.0, pair_stiffness=lambda s: np.full(np.shape(s), 1e14))


def test_unmodified_aligned_pair_is_linear_in_the_load() -> None:
    """Perfect, aligned flanks: every slice in contact carries load at any torque, so the
    approach is F_t / k(p) and the p-p static TE grows in proportion to the torque."""
    r = slice_contact(RAIL, [100.0, 1000.0, 3000.0], options=SliceOptions(20, 16))
    inside = np.isfinite(r.position)
    assert np.all(r.load[:, inside] > 0.0)
    np.testing.assert_allclose(r.peak_to_peak_te / r.torque, r.peak_to_peak_te[0] / 100.0,
                               rtol=1e-9)
    np.testing.assert_allclose(r.secant_stiffness, r.tangent_stiffness, rtol=1e-9)


def test_relief_study_ranks_as_single_runs() -> None:
    """The study's ladder against one slice_contact per design and torque (a second path):
    same PPTE, and the best design is the lowest mean PPTE."""
    from gear_dyn.analysis.relief_study import relief_study
    from gear_dyn.modification.analysis import rule_modifications

    designs = rule_modifications(RAIL, 2000.0)
    torques = [600.0, 2000.0]
    opts = SliceOptions(12, 12)
    study = relief_study(RAIL, torques, designs, options=opts)
    ppte = np.array([[slice_contact(RAIL, t, FlankModification(profile=m),
                                    options=opts).peak_to_peak_te[0] for t in torques]
                     for m in designs.values()])
    np.testing.assert_allclose(study.ppte, ppte, rtol=1e-9)
    assert study.best == list(designs)[int(np.argmin(ppte.mean(axis=1)))]
    assert len(study.rows()) == len(designs) * len(torques)
    with pytest.raises(InputError, match="no designs"):
        relief_study(RAIL, torques, {})


def test_piecewise_signal_slope_at_a_sample_does_not_depend_on_rounding() -> None:
    """A phase a few ulps below a sample of a piecewise-linear signal (a time's rounding puts it
    on either side) takes the slope of the piece that starts there, as the sample itself does;
    the value stays continuous (an FMU read every step or every other step gives the same
    damping force)."""
    import numpy as np

    from gear_dyn.modification.contact import PiecewiseSignal

    sig = PiecewiseSignal.from_segments(np.array([0.0, 1.0]), np.zeros(4, dtype=int),
                                        np.array([0.0, 0.25, 0.5, 1.0]),
                                        np.array([0.0, 1.0, 3.0, 0.0]))
    node = 0.25
    below = np.nextafter(np.nextafter(node, 0.0), 0.0)
    assert sig.slope(node) == sig.slope(below) == 8.0
    assert float(sig.slope(np.array([below]))[0]) == 8.0
    assert abs(sig.value(below) - 1.0) < 1e-12
    # a phase clearly below the sample keeps its own piece
    assert sig.slope(node - 1e-6) == 4.0
