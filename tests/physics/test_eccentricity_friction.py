"""Friction force and torques of the eccentric helical pair (Liu et al. 2017, eqs. 18-27)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from gear_dyn.eccentricity import Eccentricity, EccentricMesh
from gear_dyn.eccentricity.contact_lines import LineLayout, line_positions
from gear_dyn.eccentricity.friction import friction_factors, line_state_scalar, split_segments
from gear_dyn.errors import InputError
from gear_dyn.geometry import GearPair

W1 = 1500 * 2 * math.pi / 60
MU = 0.05


def pair_of(beta_deg: float) -> GearPair:
    return GearPair(18, 70, 3e-3, math.radians(20), 0.04, math.radians(beta_deg))


def brute_force(mesh: EccentricMesh, t: float, mu: float, n: int = 20000) -> tuple[float, ...]:
    """Friction from first principles at one instant, per unit normal load.

    Each contact line is sampled at n points across the face; each point carries load
    dl / L (uniform pressure); its sliding velocity is computed from the two rigid rotations
    (pinion CCW about (0, 0) at w1, gear CW about (H, 0) at w2 of eq. 12); the friction on the
    pinion opposes it; torques are cross products about the rotation centres. Returns
    (L, force along w = (cos a, -sin a) on the pinion, torque on pinion (CCW +), torque on gear
    (CW +)).
    """
    pair = mesh.pair
    k = mesh.kinematics(t)
    lay = LineLayout.of(mesh)
    pos = line_positions(lay, mesh.kinematics(np.array([t])))[:, 0]
    ux, uy = math.sin(k.alpha), math.cos(k.alpha)
    wx, wy = math.cos(k.alpha), -math.sin(k.alpha)
    tan_bb, cos_bb = math.tan(pair.beta_b), math.cos(pair.beta_b)
    z = (np.arange(n) + 0.5) / n * pair.face_width
    dl = pair.face_width / n / cos_bb
    pts = []
    for d in pos:
        s = d - z * tan_bb
        pts.append(s[(s >= 0) & (s <= k.l_cd)] + k.l_ac)  # distance from A
    s_all = np.concatenate(pts)
    length = s_all.size * dl
    x = k.xa + s_all * ux
    y = k.ya + s_all * uy
    h = pair.a_w
    v1 = (-k.w1 * y, k.w1 * x)
    v2 = (k.w2 * y, -k.w2 * (x - h))
    slide = (v1[0] - v2[0]) * wx + (v1[1] - v2[1]) * wy
    f = -mu * (dl / length) * np.sign(slide)  # friction on the pinion along w
    fx, fy = f * wx, f * wy
    torque1 = np.sum(x * fy - y * fx)
    torque2 = np.sum((x - h) * fy - y * fx)
    return length, float(np.sum(f)), float(torque1), float(torque2)


@pytest.mark.parametrize(("beta", "ecc"), [(15.0, 2e-4), (15.0, 0.0), (25.0, 1e-4)])
def test_friction_against_first_principles(beta: float, ecc: float) -> None:
    """Discretisation error of the brute force is one sample per line end: ~1e-4 relative of the
    largest value, so 2e-3 of the torque scale bounds it."""
    mesh = EccentricMesh(pair_of(beta), Eccentricity(ecc, ecc, 0.2, 1.1), W1)
    lay = LineLayout.of(mesh)
    for t in np.random.default_rng(11).uniform(0, 1.4, 12):
        k = mesh.kinematics(float(t))
        total, force, t1, t2 = line_state_scalar(lay, k, MU)
        length, f_ref, t1_ref, t2_ref = brute_force(mesh, float(t), MU)
        scale_t = MU * mesh.pair.rb2
        assert total == pytest.approx(length, rel=1e-3)
        assert force == pytest.approx(f_ref, abs=2e-3 * MU)
        assert t1 == pytest.approx(t1_ref, abs=2e-3 * scale_t)
        assert t2 == pytest.approx(t2_ref, abs=2e-3 * scale_t)


def test_vectorised_and_scalar_paths_agree() -> None:
    mesh = EccentricMesh(pair_of(15.0), Eccentricity(2e-4, 2e-4), W1)
    lay = LineLayout.of(mesh)
    t = np.random.default_rng(5).uniform(0, 1.4, 200)
    ff = friction_factors(lay, mesh.kinematics(t), MU)
    for i, ti in enumerate(t):
        _, f, t1, t2 = line_state_scalar(lay, mesh.kinematics(float(ti)), MU)
        # identical arithmetic apart from summation order, on kinematics whose gear angle is
        # iterated to 1e-14 rad per rad (scalar and array paths stop at slightly different
        # iterates): agreement to ~1e-11 relative
        assert f == pytest.approx(ff.force[i], rel=1e-10, abs=1e-16)
        assert t1 == pytest.approx(ff.torque_pinion[i], rel=1e-10, abs=1e-16)
        assert t2 == pytest.approx(ff.torque_gear[i], rel=1e-10, abs=1e-16)


def test_friction_dissipates_power() -> None:
    """Power of friction on both gears, T_f1 w1 + T_f2 w2, is never positive (second law), and
    equals -mu/L (w1 + w2) sum |s_mid - s_P| L_seg (sliding speed linear along the line)."""
    mesh = EccentricMesh(pair_of(15.0), Eccentricity(2e-4, 2e-4), W1)
    lay = LineLayout.of(mesh)
    t = np.linspace(0, 1.4, 20001)
    k = mesh.kinematics(t)
    seg = split_segments(lay, k)
    ff = friction_factors(lay, k, MU, seg)
    power = ff.torque_pinion * k.w1 + ff.torque_gear * k.w2
    assert np.all(power < 0)
    sp = k.l_ap
    expect = -MU / seg.total * (k.w1 + k.w2) * (
        seg.before * np.abs(seg.mid_before - sp) + seg.beyond * np.abs(seg.mid_beyond - sp)
    ).sum(axis=0)
    np.testing.assert_allclose(power, expect, rtol=1e-10)


@pytest.mark.parametrize(("beta", "width", "tol"), [(15.0, 0.04, 3e-3), (25.0, 0.06, 3e-3),
                                                     (15.0, 0.2, 1e-3)])
def test_mean_mesh_loss_matches_the_uniform_load_closed_form(beta: float, width: float,
                                                             tol: float) -> None:
    """Error-free pair. With load F / L per unit line length and line density B / (p_bt cos b_b)
    per unit transverse length, the time-mean friction power is mu F (w1 + w2) / g_a times the
    path integral of |s - s_P|, i.e. mu F (w1 + w2) p_bt (eps_1^2 + eps_2^2) / (2 eps_a), so the
    loss fraction is mu pi (u + 1) / (z1 u) (eps_1^2 + eps_2^2) / eps_a (eps_1, eps_2: approach
    and recess ratios). The closed form takes L = its mean; the residual from F / L(t) is
    ~1e-3 for eps_b >= 1 (smaller as eps_b grows). Ohlendorf's H_V (ISO/TR 14179-2) differs by
    its spur load-sharing assumption."""
    pair = GearPair(18, 70, 3e-3, math.radians(20), width, math.radians(beta))
    mesh = EccentricMesh(pair, Eccentricity(), W1)
    t = np.arange(20000) / 20000 / mesh.mesh_frequency
    k = mesh.kinematics(t)
    ff = friction_factors(LineLayout.of(mesh), k, MU)
    loss = -np.mean(ff.torque_pinion * k.w1 + ff.torque_gear * k.w2) / (pair.rb1 * W1)
    u = 70 / 18
    e1 = (pair.pitch_point - pair.start_of_contact) / pair.base_pitch
    e2 = (pair.end_of_contact - pair.pitch_point) / pair.base_pitch
    closed = MU * math.pi * (u + 1) / (18 * u) * (e1**2 + e2**2) / pair.contact_ratio
    assert loss == pytest.approx(closed, rel=tol)


def test_friction_torque_changes_sign_at_the_pitch_point() -> None:
    """Spur pair (one line per tooth): in the single-contact zone the friction torque on the
    pinion is that of one line; it helps the pinion before the pitch point and brakes it beyond,
    switching exactly when the line crosses P (seed: the sliding direction flips at P)."""
    pair = pair_of(0.0)
    mesh = EccentricMesh(pair, Eccentricity(), W1)
    lay = LineLayout.of(mesh)
    l_cp = pair.pitch_point - pair.start_of_contact
    assert pair.path_of_contact - pair.base_pitch < l_cp < pair.base_pitch  # P in single zone
    t_p = l_cp / (pair.rb1 * W1)  # line 1 enters C at t = 0 and reaches P here
    for dt, sign in ((-1e-9, 1.0), (1e-9, -1.0)):
        _, force, t1, t2 = line_state_scalar(lay, mesh.kinematics(t_p + dt), MU)
        assert np.sign(t1) == sign
        assert np.sign(force) == -sign
        assert np.sign(t2) == -sign
    # helical: each line's share flips at P, so the torque of a line before P helps, beyond brakes
    mesh_h = EccentricMesh(pair_of(15.0), Eccentricity(2e-4, 2e-4), W1)
    k = mesh_h.kinematics(np.linspace(0, 0.2, 4001))
    seg = split_segments(LineLayout.of(mesh_h), k)
    assert np.all(seg.mid_before[seg.before > 0] <= np.broadcast_to(k.l_ap, seg.before.shape)[
        seg.before > 0] + 1e-15)
    assert np.all(seg.mid_beyond[seg.beyond > 0] >= np.broadcast_to(k.l_ap, seg.beyond.shape)[
        seg.beyond > 0] - 1e-15)


def test_zero_friction_coefficient_gives_zero_friction() -> None:
    mesh = EccentricMesh(pair_of(15.0), Eccentricity(2e-4, 2e-4), W1)
    lay = LineLayout.of(mesh)
    ff = friction_factors(lay, mesh.kinematics(np.linspace(0, 0.1, 1001)), 0.0)
    assert not np.any(ff.force) and not np.any(ff.torque_pinion) and not np.any(ff.torque_gear)


def test_bad_friction_coefficient_is_refused() -> None:
    mesh = EccentricMesh(pair_of(15.0), Eccentricity(), W1)
    with pytest.raises(InputError, match="friction.coefficient"):
        friction_factors(LineLayout.of(mesh), mesh.kinematics(np.zeros(2)), 1.5)


@settings(max_examples=25, deadline=None)
@given(
    z1=st.integers(18, 40), ratio=st.floats(1.0, 5.0), beta=st.floats(0.0, 30.0),
    width=st.floats(0.01, 0.12), e1=st.floats(0.0, 3e-4), e2=st.floats(0.0, 3e-4),
    ph1=st.floats(0.0, 6.3), ph2=st.floats(0.0, 6.3),
)
def test_friction_never_produces_power_and_lines_stay_in_the_field(
        z1: int, ratio: float, beta: float, width: float, e1: float, e2: float, ph1: float,
        ph2: float) -> None:
    """Property over random pairs and eccentricities: friction power <= 0, every segment lies in
    [C, D], and the split lengths add up to the total contact length."""
    z2 = int(round(z1 * ratio))
    try:
        pair = GearPair(z1, z2, 3e-3, math.radians(20), width, math.radians(beta))
        mesh = EccentricMesh(pair, Eccentricity(e1, e2, ph1, ph2), W1)
    except InputError:
        assume(False)  # an impossible pair is refused elsewhere (tested); not this property
    lay = LineLayout.of(mesh)
    t = np.linspace(0.0, 2 / 25, 801)
    k = mesh.kinematics(t)
    seg = split_segments(lay, k)
    ff = friction_factors(lay, k, MU, seg)
    assert np.all(ff.torque_pinion * k.w1 + ff.torque_gear * k.w2 <= 1e-15)
    on = seg.before > 0
    lo = np.broadcast_to(k.l_ac, seg.before.shape)
    hi = np.broadcast_to(k.l_ad, seg.before.shape)
    assert np.all(seg.mid_before[on] >= lo[on] - 1e-12)
    on = seg.beyond > 0
    assert np.all(seg.mid_beyond[on] <= hi[on] + 1e-12)
    from gear_dyn.eccentricity.contact_lines import contact_lines

    np.testing.assert_allclose(seg.total, contact_lines(lay, k).total, rtol=1e-12, atol=1e-15)
