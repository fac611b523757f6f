"""The closed-form backlash propagator with a harmonic transmission error (method
exact_contact, gear_dyn.solvers.contact_exact with gear_dyn.solvers.harmonic_forcing).

The scene of issue 25: the helicopter-tail pair's magnitudes (m_e = 3.05 kg, W = 5782 N, half gap
10 um, damping ratio 0.06) with constant mesh stiffness 1e9 N/m, excited only by a 10 um
transmission error. Independent references:

- an event-locating DOP853 on the model's right-hand side (dop853_reference.py) (``x - e(t) = +-b``
  located by solve_ivp's own event finder), at rtol 1e-12 and 1e-13; its own error is their
  difference, and each tolerance is that error (times ten) plus the propagator's stated
  rounding bound;
- the switching times of a second closed form in extended precision (``np.longdouble``, 64-bit
  mantissa): the homogeneous part from the complex eigenvalues ``exp(lambda s)`` and the
  particular part as ``Re(F e^(i th) / (w2 - W^2 + i a W))``, roots by bisection to the
  long double's resolution (not the propagator's cos/sin form nor its root finder);
- the monodromy matrix against central differences of the flow and Liouville's formula
  ``det M = exp(-c T / m)``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from dop853_reference import dop853_events

from gear_dyn.errors import InputError
from gear_dyn.excitation import HarmonicSignal, SampledSignal
from gear_dyn.models.sdof import SDOFModel
from gear_dyn.solvers import SolverSettings, integrate, resolve_auto
from gear_dyn.solvers.contact_exact import (
    DRIVE,
    GAP,
    _first_crossing,
    _Piece,
    contact_exact_applies,
    flow_with_sensitivity,
    propagate_contact_exact,
    rounding_bound,
)
from gear_dyn.stiffness.periodic import rectangular_stiffness

M_E, K1, W, B = 3.045616654145314, 1.0e9, 5782.170507648933, 1e-5
FN = math.sqrt(K1 / M_E) / (2 * math.pi)
ONE = HarmonicSignal(0.0, np.array([1e-5]), np.array([0.0]))
TWO = HarmonicSignal(2e-6, np.array([8e-6, 1.5e-6]), np.array([3e-6, -2e-6]))


def te_model(ratio: float, te: HarmonicSignal = ONE, k_double: float = K1, xi: float = 0.06,
             phase0: float = 0.0) -> SDOFModel:
    """The constant-stiffness TE scene at f_m / f_n = ``ratio`` (``k_double`` != K1: a
    rectangular stiffness, piecewise constant)."""
    return SDOFModel(mass=M_E, stiffness=rectangular_stiffness(1.41, K1, k_double),
                     damping_ratio=xi, static_load=W, mesh_frequency=ratio * FN, backlash=B,
                     transmission_error=te, phase0=phase0)


def test_applies_to_harmonic_te_only() -> None:
    """A harmonic TE is covered (auto picks exact_contact); a sampled one or an undamped model
    with a TE is not (the variational route then); ``exact_contact`` asked for names it."""
    assert contact_exact_applies(te_model(1.5)) and resolve_auto(te_model(1.5)) == "exact_contact"
    sampled = SampledSignal(np.array([0.0, 0.5]), np.array([0.0, 1e-5]))
    for model in (te_model(1.5, te=sampled), te_model(1.5, xi=0.0)):  # type: ignore[arg-type]
        assert not contact_exact_applies(model)
        with pytest.raises(InputError, match="harmonic transmission error"):
            propagate_contact_exact(model, np.array([0.0, 1e-4]))


@pytest.mark.parametrize(("ratio", "te", "k_double"), [
    (1.6, ONE, K1),  # heavy separation: teeth apart for ~55 % of the time
    (0.9, ONE, K1),  # back-flank impacts (u reaches -6.8 b)
    (1.5, TWO, 1.6 * K1),  # two harmonics with sines, piecewise-constant stiffness, back flank
])
def test_trajectory_and_events_match_dop853(ratio: float, te: HarmonicSignal, k_double: float
                                            ) -> None:
    model = te_model(ratio, te, k_double, phase0=0.137)
    period = 1 / model.mesh_frequency
    t = np.linspace(0.0, 24 * period, 24 * 32 + 1)
    y0 = model.initial_state()
    y, st = propagate_contact_exact(model, t, y0=y0)
    y12, ev12 = dop853_events(model, t, 1e-12, y0)
    y13, ev13 = dop853_events(model, t, 1e-13, y0)
    ours = np.asarray(st["event_times"])
    assert ours.size == ev13.size > 20, "the case must separate the teeth often"
    u = y[0] - te.value(model.phase(t))
    assert np.mean(np.abs(u) <= B) > 0.05
    if ratio < 1.55:
        assert np.min(u) < -B, "must reach the back flank"
    ev_own = float(np.max(np.abs(ev12 - ev13)))
    assert np.max(np.abs(ours - ev13)) <= 10 * ev_own + 1e-12 * period
    scale = model.state_scale[:, None]
    ref_own = float(np.max(np.abs(y12 - y13) / scale))
    bound = rounding_bound(y, model.state_scale, st["n_segments"])
    assert float(np.max(np.abs(y - y13) / scale)) <= 10 * ref_own + bound


def _piece_reference(model: SDOFModel, state: int, t0: float, u0: np.longdouble,
                     v0: np.longdouble, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``u(t0 + s), u'(t0 + s)`` in one contact state, in long double, by a second closed
    form: complex eigenvalues of the homogeneous part and the complex particular solution."""
    ld = np.longdouble
    m, c, w, b = ld(model.mass), ld(model.damping), ld(model.static_load), ld(B)
    a = c / m
    te = model.transmission_error
    assert isinstance(te, HarmonicSignal)
    fm, p0 = ld(model.mesh_frequency), ld(model.phase0)
    two_pi = 2 * ld(np.pi)
    k = ld(K1) if state != GAP else ld(0)
    n = np.arange(1, te.cos.size + 1).astype(ld)
    om = two_pi * n * fm
    forcing = om**2 * (te.cos.astype(ld) - 1j * te.sin.astype(ld))  # -e'' = Re(F e^(i th))
    resp = forcing / (k / m - om**2 + 1j * a * om)

    def part(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        e = np.exp(1j * two_pi * (fm * t[:, None] + p0) * n)
        return (e @ resp).real, (e @ (1j * om * resp)).real

    tt = ld(t0) + s
    pu0, pv0 = part(np.array([ld(t0)]))
    z0, zv0 = u0 - pu0[0], v0 - pv0[0]
    if state == GAP:  # z'' + a z' = w/m: z = C1 + C2 e^(-a s) + (w / (m a)) s
        drift = w / (m * a)
        c2 = -(zv0 - drift) / a
        z = (z0 - c2) + c2 * np.exp(-a * s) + drift * s
        zv = -a * c2 * np.exp(-a * s) + drift
    else:
        z_eq = state * b + w / k
        root = np.sqrt(ld(0) + 0j + a * a / 4 - k / m)
        l1, l2 = -a / 2 + root, -a / 2 - root
        c1 = (zv0 - l2 * (z0 - z_eq)) / (l1 - l2)
        c2 = (z0 - z_eq) - c1
        z = z_eq + (c1 * np.exp(l1 * s) + c2 * np.exp(l2 * s)).real
        zv = (c1 * l1 * np.exp(l1 * s) + c2 * l2 * np.exp(l2 * s)).real
    pu, pv = part(tt)
    return z + pu, zv + pv


def test_switching_times_to_1e14_against_extended_precision() -> None:
    """The first contact changes from the static state at f_m / f_n = 1.6 (teeth apart most of
    the time): each located time agrees with the long-double closed form's root to 1e-14
    relative. The reference walks the same contact sequence from its own event states."""
    model = te_model(1.6, phase0=0.0)
    ld = np.longdouble
    period = 1 / model.mesh_frequency
    t = np.linspace(0.0, 6 * period, 7)
    _y, st = propagate_contact_exact(model, t, y0=model.initial_state())
    ours = np.asarray(st["event_times"])
    assert ours.size >= 10
    te = model.transmission_error
    assert te is not None
    y0 = model.initial_state()
    u, v = ld(y0[0]) - ld(te.value(0.0)), ld(y0[1]) - ld(model.mesh_frequency * te.slope(0.0))
    state, t_now, b = DRIVE, ld(0), ld(B)
    h = ld(period) / 400
    for t_ours in ours:
        s = np.arange(1, 4000, dtype=ld) * h
        us = _piece_reference(model, state, t_now, u, v, s)[0]
        first, lev = None, b
        for level in (b, -b) if state == GAP else (state * b,):
            inside = 1 if state == DRIVE or (state == GAP and level < 0) else -1
            hits = np.flatnonzero((us - level) * inside < 0)
            if hits.size and (first is None or hits[0] < first):
                first, lev = int(hits[0]), level
        assert first is not None
        lo, hi = (s[first - 1] if first else ld(0)), s[first]
        sgn_hi = np.sign(_piece_reference(model, state, t_now, u, v, np.array([hi]))[0][0] - lev)
        for _ in range(200):  # bisection to the long double's resolution
            mid = (lo + hi) / 2
            if mid in (lo, hi):
                break
            val = _piece_reference(model, state, t_now, u, v, np.array([mid]))[0][0] - lev
            if np.sign(val) == sgn_hi:
                hi = mid
            else:
                lo = mid
        t_ref = t_now + (lo + hi) / 2
        assert abs(ld(t_ours) - t_ref) <= 1e-14 * t_ref, (t_ours, t_ref)
        # the reference goes on from its own event state; the velocity picks the new state
        v = _piece_reference(model, state, t_now, u, v, np.array([(lo + hi) / 2]))[1][0]
        u, t_now = lev, t_ref
        state = GAP if state != GAP else (DRIVE if v > 0 else -1)


def test_monodromy_against_finite_differences_and_liouville() -> None:
    """Over two mesh periods at 1.24 f_n (a period-2 regime with separation): central
    differences of the flow with steps 1e-6 of the state scale (truncation ~1e-12 times the
    second derivative, rounding ~1e-16/1e-6: 1e-7 relative is ten times both), and
    ``det M = exp(-2 c T / m)`` to rounding."""
    model = te_model(1.24, TWO, 1.3 * K1)
    t1 = 2 / model.mesh_frequency
    y0 = model.initial_state()
    y, phi = flow_with_sensitivity(model, y0, t1)
    scale = model.state_scale
    fd = np.empty((2, 2))
    for j in range(2):
        dy = np.zeros(2)
        dy[j] = 1e-6 * scale[j]
        yp, _ = flow_with_sensitivity(model, y0 + dy, t1)
        ym, _ = flow_with_sensitivity(model, y0 - dy, t1)
        fd[:, j] = (yp - ym) / (2 * dy[j])
    rel = np.abs(phi - fd) * scale[None, :] / scale[:, None]
    assert float(np.max(rel)) <= 1e-7 * float(np.max(np.abs(phi) * scale[None, :]
                                                          / scale[:, None]))
    expected = math.exp(-model.damping * t1 / model.mass)
    assert abs(np.linalg.det(phi) / expected - 1) <= 1e-12
    traj, st = propagate_contact_exact(model, np.array([0.0, t1]), y0=y0)
    assert st["n_contact_events"] >= 4
    assert np.all(np.abs(traj[:, -1] - y) <= 1e-12 * scale)  # the same pieces, to rounding


def test_crossing_search_misses_no_dip() -> None:
    """Start states in the gap and on the drive flank whose motion dips across a boundary
    between two samples: every crossing a dense scan (2000 points per sample step) sees is
    found, at the dense scan's time to within its step; where the scan sees none, none is
    claimed. Random starts near grazing make the bound prove or bisect."""
    model = te_model(1.45, TWO)
    rng = np.random.default_rng(7)
    found = 0
    for state in (GAP, DRIVE):
        pc = _Piece(model, K1, state)
        length = 3 * pc.h
        s = np.linspace(0.0, length, 6001)
        for _ in range(60):
            t0 = float(rng.uniform(0.0, 1.0 / model.mesh_frequency))
            u0 = (rng.uniform(-0.9, 0.9) * B if state == GAP
                  else B + rng.uniform(0.05, 1.5) * W / K1)
            v0 = float(rng.normal()) * 0.02
            u, _v = pc.at(u0, v0, s, t0)
            inside = (u > B) if state == DRIVE else (np.abs(u) <= B)
            out = np.flatnonzero(~inside[1:])
            hit = _first_crossing(pc, t0, u0, v0, length, 1e-18)
            if out.size:
                found += 1
                assert hit is not None
                assert s[out[0]] - 2 * (s[1] - s[0]) <= hit <= s[out[0] + 1]
            else:
                assert hit is None or hit > s[-2]
    assert found > 30


def test_auto_integrates_the_te_scene_by_the_closed_form() -> None:
    model = te_model(1.5)
    t = np.linspace(0.0, 10 / model.mesh_frequency, 641)
    y, st = integrate(model, t, SolverSettings())
    assert st["method"] == "exact_contact"
    y_d, _ = integrate(model, t, SolverSettings(method="DOP853", rtol=1e-10))
    assert np.max(np.abs(y - y_d) / model.state_scale[:, None]) < 1e-6


@pytest.mark.parametrize("te", [None, TWO])
def test_walk_setup_reused_across_speeds_is_the_fresh_one(te: HarmonicSignal | None) -> None:
    """The walk's setup (the stiffness's segments, the piece rows) is kept between models of
    one family: walking at a second speed after the first gives, bit for bit, what a walk
    with nothing kept gives (the rows carry f_m with a transmission error, so they are not
    reused across speeds then; without one they are)."""
    from gear_dyn.solvers import contact_exact as ce

    base = te_model(1.3, k_double=1.6 * K1, phase0=0.21)
    if te is None:
        base = SDOFModel(mass=M_E, stiffness=base.stiffness, damping_ratio=0.06,
                         static_load=W, mesh_frequency=base.mesh_frequency, backlash=B,
                         phase0=0.21)
    else:
        base = te_model(1.3, te, k_double=1.6 * K1, phase0=0.21)
    first, second = base, base.at_mesh_frequency(1.7 * FN)
    y0 = np.array([W / K1 + 4 * B, 0.0])  # swings through the gap onto the back flank

    def end_and_phi(model: SDOFModel) -> np.ndarray:
        w = ce.walk(model, y0, 3 / model.mesh_frequency)
        return np.concatenate([w.end, w.sensitivity().ravel(), w.event_times])

    ce._PIECES.clear()
    ce._ROWS.clear()
    fresh = end_and_phi(second)
    ce._PIECES.clear()
    ce._ROWS.clear()
    end_and_phi(first)
    assert len(ce._ROWS) == 1
    reused = end_and_phi(second)
    assert len(ce._ROWS) == (1 if te is None else 2)
    np.testing.assert_array_equal(reused, fresh)
    assert fresh.size > 6  # contact changes were walked
