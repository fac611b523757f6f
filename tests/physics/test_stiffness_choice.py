"""The default mesh-stiffness method of a pair (gear_dyn.stiffness.select.choose_stiffness) and
what each method includes and leaves out (method_scope)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gear_dyn.geometry import GearPair
from gear_dyn.stiffness import build_stiffness, iso6336_stiffness, potential_energy_compliances
from gear_dyn.stiffness.contact_line import contact_line_length, mean_contact_line_length
from gear_dyn.stiffness.select import METHODS, choose_stiffness, method_scope

SPUR = GearPair(19, 48, 3.2e-3, math.radians(20), 16e-3)
#: the rail pair: 23/79, m_n 6 mm, 20 deg, helix 20 deg, B 70 mm, x +0.3/-0.1 (eps_beta 1.27)
RAIL = GearPair(23, 79, 6e-3, math.radians(20), 70e-3, helix_angle=math.radians(20), x1=0.3,
                x2=-0.1)


def test_helical_pair_defaults_to_contact_line_spur_to_iso() -> None:
    choice = choose_stiffness(RAIL)
    assert (choice.method, choice.by_default) == ("contact_line", True)
    assert f"eps_beta = {RAIL.overlap_ratio:.3g}" in choice.reason
    assert choose_stiffness(SPUR).method == "iso6336"
    given = choose_stiffness(RAIL, "iso6336")
    assert (given.method, given.by_default) == ("iso6336", False)
    assert "spur wave" in given.reason  # a spur wave asked for a helical pair is said to be one


def test_default_curve_is_the_contact_line_length_with_iso_mean() -> None:
    # Without a method the helical pair's k(p) is k_l L(p) with L from the closed-form
    # contact-line geometry and k_l = c_gamma b / mean L (ISO 6336-1): checked pointwise against
    # contact_line_length, and it is no spur wave: its max/min ratio stays well under ISO's step
    # of 1.75 (L varies by far less than a pair count for eps_beta = 1.27).
    k = build_stiffness(RAIL)
    assert k.name == "contact_line"
    iso = iso6336_stiffness(RAIL).k_mesh
    assert k.mean == pytest.approx(iso, rel=1e-9)
    p = (np.arange(97) + 0.5) / 97
    k_l = iso / mean_contact_line_length(RAIL)
    np.testing.assert_allclose(k(p), k_l * contact_line_length(RAIL, p), rtol=1e-9)
    assert k.max / k.min < 1.2
    assert build_stiffness(SPUR).name == "iso6336"
    assert build_stiffness(SPUR).max / build_stiffness(SPUR).min == pytest.approx(1.75)


def test_left_hand_helix_gets_the_same_default() -> None:
    left = GearPair(23, 79, 6e-3, math.radians(20), 70e-3, helix_angle=-math.radians(20),
                    x1=0.3, x2=-0.1)
    assert choose_stiffness(left).method == "contact_line"
    assert build_stiffness(left).mean == pytest.approx(build_stiffness(RAIL).mean, rel=1e-12)


@pytest.mark.parametrize("pair", [SPUR, RAIL])
@pytest.mark.parametrize("method", METHODS)
def test_every_method_has_a_scope(pair: GearPair, method: str) -> None:
    includes, leaves_out = method_scope(pair, method)
    assert includes and leaves_out
    helical = pair is RAIL
    # the helical statements appear only for a helical pair
    if method in ("potential_energy", "weber"):
        assert ("uncoupled face slices" in includes) is helical
    if method == "iso6336":
        assert ("eps_beta" in leaves_out) is helical


def test_weber_spread_is_the_foundation_term_it_leaves_out() -> None:
    # The scope says Weber leaves out the fillet-foundation deflection, the largest compliance
    # term, and uses the 1.35 E modulus of Jiang et al. (2018). Both statements are checked
    # against the code: at the pitch point the Sainsot term is the largest potential-energy
    # compliance; and Weber with that term added and E in the tooth terms comes to the
    # potential-energy mean (the same beam terms, 20 slices instead of the exact integral:
    # within 1 %), down from 2.76 x ISO.
    iso = iso6336_stiffness(RAIL).k_mesh
    assert "fillet-foundation" in method_scope(RAIL, "weber")[1]
    assert "fillet-foundation" not in method_scope(RAIL, "weber",
                                                   {"weber_foundation": True})[1]
    assert "1.35 E" in method_scope(RAIL, "weber")[0]
    c = potential_energy_compliances(RAIL, np.array([RAIL.pitch_point]))
    terms = {"hertz": c.hertz[0], "bending": c.bending.sum(), "shear": c.shear.sum(),
             "axial": c.axial.sum(), "fillet": c.fillet.sum()}
    assert max(terms, key=lambda t: terms[t]) == "fillet"
    weber = build_stiffness(RAIL, "weber").mean
    closed = build_stiffness(RAIL, "weber", weber_foundation=True,
                             weber_modulus="plane_stress").mean
    pe = build_stiffness(RAIL, "potential_energy").mean
    assert weber / iso == pytest.approx(2.76, abs=0.01)
    assert closed == pytest.approx(pe, rel=1e-2)
