"""Contact lines of the eccentric helical pair (Liu et al. 2017, eqs. 14-17)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gear_dyn.eccentricity import Eccentricity, EccentricMesh
from gear_dyn.eccentricity.contact_lines import (
    LineLayout,
    contact_lines,
    line_lengths,
    mean_length,
    total_length_scalar,
)
from gear_dyn.geometry import GearPair
from gear_dyn.stiffness.contact_line import contact_line_length

W1 = 1500 * 2 * math.pi / 60


def pair_of(beta_deg: float, width: float = 0.04) -> GearPair:
    return GearPair(18, 70, 3e-3, math.radians(20), width, math.radians(beta_deg))


def printed_eq15(d: np.ndarray, w: float, l_cd: float, sin_bb: float) -> np.ndarray:
    """Liu et al. (2017), eqs. 15-16, literally: four pieces, plus zero before entry (D < 0)."""
    lo, hi = min(w, l_cd), max(w, l_cd)
    out = np.zeros_like(d)
    a = (d >= 0) & (d < lo)
    b = (d >= lo) & (d < hi)
    c = (d >= hi) & (d < l_cd + w)
    out[a] = d[a] / sin_bb
    out[b] = lo / sin_bb
    out[c] = (l_cd - (d[c] - w)) / sin_bb
    return out


@pytest.mark.parametrize("width", [0.02, 0.04, 0.08])  # eps_b < eps_a, ~, > eps_a
def test_overlap_form_equals_the_printed_piecewise_function(width: float) -> None:
    pair = pair_of(15.0, width)
    mesh = EccentricMesh(pair, Eccentricity(), W1)
    lay = LineLayout.of(mesh)
    d = np.linspace(-0.01, 0.06, 7001)
    l_cd = pair.path_of_contact
    # same arithmetic up to rounding of (min - max) vs direct sums: 1e-15 m
    np.testing.assert_allclose(line_lengths(lay, d, l_cd), printed_eq15(d, lay.width, l_cd,
                                                                      lay.sin_bb), atol=1e-14)


@pytest.mark.parametrize("beta", [0.0, 8.0, 15.0, 30.0])
def test_error_free_total_equals_the_independent_contact_line_module(beta: float) -> None:
    """e1 = e2 = 0: L(t) equals gear_dyn.stiffness.contact_line (issue 3, written separately,
    parameterised by mesh phase and the rectangle of the field from A): rounding only."""
    pair = pair_of(beta)
    mesh = EccentricMesh(pair, Eccentricity(), W1)
    t = np.linspace(0.0, 3 / mesh.mesh_frequency, 3001)[1:]  # skip t = 0 (spur jump side)
    ours = contact_lines(LineLayout.of(mesh), mesh.kinematics(t)).total
    ref = contact_line_length(pair, mesh.mesh_frequency * t)
    if beta == 0.0:
        # spur: both are step functions; compare away from the switching instants
        sw = np.mod(mesh.mesh_frequency * t, 1.0)
        eps_f = pair.contact_ratio % 1.0
        keep = (np.abs(sw - eps_f) > 1e-6) & (sw > 1e-6) & (sw < 1 - 1e-6)
        ours, ref = ours[keep], ref[keep]
    np.testing.assert_allclose(ours, ref, rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("beta", [8.0, 15.0, 30.0])
def test_error_free_mean_is_b_eps_a_over_cos_beta_b(beta: float) -> None:
    """Maatar & Velex (1996): mean L = B eps_a / cos b_b. L(t) is piecewise linear in t, so the
    trapezoidal mean over one mesh period with 20000 samples is exact to ~1e-8 relative (only the
    few kinks fall between samples)."""
    pair = pair_of(beta)
    mesh = EccentricMesh(pair, Eccentricity(), W1)
    t = np.linspace(0.0, 1 / mesh.mesh_frequency, 20001)
    total = contact_lines(LineLayout.of(mesh), mesh.kinematics(t)).total
    mean = np.trapezoid(total, t) * mesh.mesh_frequency
    assert mean == pytest.approx(pair.face_width * pair.contact_ratio / math.cos(pair.beta_b),
                                 rel=1e-7)
    assert mean_length(mesh) == pytest.approx(mean, rel=1e-7)


def test_eccentric_lengths_against_brute_force_sampling_of_the_face() -> None:
    """Second method: sample each line at 20000 points across the face width, keep those inside
    the instantaneous field [C, D]; the count times dz / cos b_b is the length (error one dz)."""
    pair = pair_of(15.0)
    mesh = EccentricMesh(pair, Eccentricity(2e-4, 2e-4, 0.5, 2.0), W1)
    lay = LineLayout.of(mesh)
    ts = np.random.default_rng(7).uniform(0.0, 1.4, 25)
    n = 20000
    z = (np.arange(n) + 0.5) / n * pair.face_width
    dz = pair.face_width / n
    tan_bb = math.tan(pair.beta_b)
    for t in ts:
        k = mesh.kinematics(float(t))
        lines = contact_lines(lay, mesh.kinematics(np.array([t])))
        total = 0.0
        for d in lines.position[:, 0]:
            s = d - z * tan_bb  # transverse distance of each face point from C
            total += np.count_nonzero((s >= 0) & (s <= k.l_cd)) * dz / math.cos(pair.beta_b)
        # one sample per line end may fall either side: <= 2 * n_lines * dz / cos b_b
        assert lines.total[0] == pytest.approx(total, abs=12 * dz)
        assert total_length_scalar(lay, k) == pytest.approx(lines.total[0], rel=1e-14)


def test_shorter_centre_distance_brings_pair_zero_into_contact_early() -> None:
    """Seed Fig. 5b: when the centre distance shrinks, C moves towards A and pair i = 0 is in
    contact before the nominal entry; when it grows, contact is late (total shorter)."""
    pair = pair_of(15.0)
    mesh = EccentricMesh(pair, Eccentricity(2e-4, 2e-4), W1)
    lay = LineLayout.of(mesh)
    t = np.linspace(0.0, 1.4, 40321)
    k = mesh.kinematics(t)
    lines = contact_lines(lay, k)
    assert lay.index[0] == 0
    early = lines.lengths[0] > 0  # pair i = 0 in contact
    assert np.any(early)
    assert np.all(k.l[early] < k.l[0] + 1e-12)  # only when l(t) < l(0): C moved towards A
    # total length correlates negatively with the centre distance (contact ratio falls with l)
    assert np.corrcoef(k.l, lines.total)[0, 1] < -0.5


def test_spur_lines_have_full_face_width() -> None:
    pair = pair_of(0.0)
    mesh = EccentricMesh(pair, Eccentricity(1e-4, 1e-4), W1)
    t = np.linspace(0.0, 0.2, 5001)
    total = contact_lines(LineLayout.of(mesh), mesh.kinematics(t)).total
    assert set(np.unique(np.round(total / pair.face_width, 12))) <= {1.0, 2.0}
