"""Property-based tests of the pure physics (hypothesis; derandomized in CI, see conftest.py).

Each property is checked against a formula written out here, independently of gear_dyn's own:
- geometry: contact ratio = path of contact / base pitch, the path from the tip and base radii;
  mesh frequency and output speed from speed and teeth;
- stiffness: positive and periodic in the mesh phase, its mean the average over one cycle;
- energy balance of the undamped, unloaded linear single-DOF model over mesh periods: the
  energy m v^2/2 + k x^2/2 is conserved between stiffness jumps and changes by
  (k_after - k_before) x^2/2 at each jump.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, reject, settings
from hypothesis import strategies as st

from gear_dyn.errors import InputError
from gear_dyn.geometry import GearPair, mesh_frequency, output_speed
from gear_dyn.models.sdof import SDOFModel
from gear_dyn.solvers import SolverSettings, integrate, time_grid
from gear_dyn.stiffness import build_stiffness, rectangular_stiffness

PAIRS = st.fixed_dictionaries({
    "z1": st.integers(14, 80), "z2": st.integers(14, 200),
    "module": st.sampled_from([1e-3, 2.5e-3, 4e-3, 6e-3, 10e-3]),
    "alpha": st.floats(17.0, 25.0), "width": st.floats(5e-3, 0.1),
})


def _pair(p: dict) -> GearPair:
    return GearPair(p["z1"], p["z2"], p["module"], math.radians(p["alpha"]), p["width"])


@settings(max_examples=60, deadline=None)
@given(PAIRS, st.floats(1.0, 2000.0))
def test_contact_ratio_and_kinematics(p: dict, speed: float) -> None:
    try:
        pair = _pair(p)
    except InputError:
        reject()  # a refused pair (undercut, interference) is tested elsewhere
    m, a = p["module"], math.radians(p["alpha"])
    r1, r2 = m * p["z1"] / 2, m * p["z2"] / 2
    rb1, rb2, ra1, ra2 = r1 * math.cos(a), r2 * math.cos(a), r1 + m, r2 + m
    path = math.sqrt(ra1**2 - rb1**2) + math.sqrt(ra2**2 - rb2**2) - (r1 + r2) * math.sin(a)
    assert pair.path_of_contact == pytest.approx(path, rel=1e-10)
    assert pair.contact_ratio == pytest.approx(path / (math.pi * m * math.cos(a)), rel=1e-10)
    assert pair.base_pitch == pytest.approx(math.pi * m * math.cos(a), rel=1e-12)
    rpm = speed * 60 / (2 * math.pi)
    assert mesh_frequency(pair, speed) == pytest.approx(p["z1"] * rpm / 60, rel=1e-12)
    assert output_speed(pair, speed) == pytest.approx(speed * p["z1"] / p["z2"], rel=1e-12)


@settings(max_examples=12, deadline=None)
@given(PAIRS, st.sampled_from(["iso6336", "potential_energy", "contact_line"]))
def test_stiffness_positive_periodic_with_its_mean(p: dict, method: str) -> None:
    try:
        pair = _pair(p)
        k = build_stiffness(pair, method)
    except InputError:
        reject()
    phase = np.linspace(0.0, 1.0, 2001)
    values = np.asarray(k(phase))
    assert np.all(values > 0) and np.all(np.isfinite(values))
    assert np.allclose(np.asarray(k(phase + 1.0)), values, rtol=1e-12)
    assert np.allclose(np.asarray(k(phase + 7.0)), values, rtol=1e-12)
    # the mean over one cycle: a fine midpoint sum (jumps cost 1/n of their height)
    n = 200_000
    mid = np.asarray(k((np.arange(n) + 0.5) / n))
    assert k.mean == pytest.approx(float(np.mean(mid)), rel=2e-4)


@settings(max_examples=25, deadline=None)
@given(eps=st.floats(1.05, 1.95), ratio=st.floats(1.05, 2.5), mass=st.floats(0.1, 10.0),
       x0=st.floats(-1e-5, 1e-5), v0=st.floats(-1e-2, 1e-2))
def test_undamped_energy_balance_over_periods(eps: float, ratio: float, mass: float, x0: float,
                                              v0: float) -> None:
    k1 = 5e8
    k = rectangular_stiffness(eps, k1, ratio * k1)
    model = SDOFModel(mass=mass, stiffness=k, damping_ratio=0.0, static_load=0.0,
                      mesh_frequency=1000.0)
    t = time_grid(1000.0, 5e-3, 64)  # 5 mesh periods
    y0 = np.array([x0, v0])
    y, _ = integrate(model, t, SolverSettings(method="exact"), y0)
    cuts = model.switching_times(0.0, float(t[-1]))
    pieces = np.concatenate([[0.0], cuts, [t[-1]]])
    # the state at each jump, by the same exact propagation (grid = the jump instants)
    yj, _ = integrate(model, pieces, SolverSettings(method="exact"), y0)
    kt = np.asarray(k(model.phase(0.5 * (pieces[:-1] + pieces[1:]))))
    jumps = 0.5 * (kt[1:] - kt[:-1]) * yj[0, 1:-1] ** 2
    e0 = 0.5 * mass * v0**2 + 0.5 * kt[0] * x0**2
    e_end = 0.5 * mass * y[1, -1] ** 2 + 0.5 * kt[-1] * y[0, -1] ** 2
    scale = max(e0, 1e-30)
    # exact propagation: rounding only (~1e-15 per piece, ~10 pieces): tolerance 1e-10
    assert abs(e_end - (e0 + float(np.sum(jumps)))) <= 1e-10 * (scale + float(np.sum(
        np.abs(jumps))))
