"""Exact sensitivity of the backlash propagator (gear_dyn.solvers.contact_exact:
flow_with_sensitivity, saltation).

References: the saltation matrix on a switched system with a discontinuous field whose flow
and Jacobian are known in closed form; the piece matrices against the matrix exponential of
scipy.linalg; the contact states' fields against the model's own right-hand side.
The map against the variational equations and finite differences: tests/analysis/
test_shoot_exact.py.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.linalg import expm

from gear_dyn.errors import SolverError
from gear_dyn.models.sdof import SDOFModel
from gear_dyn.solvers.contact_exact import (
    BACK,
    DRIVE,
    GAP,
    _Piece,
    flow_with_sensitivity,
    propagate_contact_exact,
    rounding_bound,
    saltation,
)
from gear_dyn.stiffness.periodic import rectangular_stiffness

EPS = np.finfo(float).eps


def switched_flow(x0: float, v0: float, t: float, g1: float, g2: float
                  ) -> tuple[np.ndarray, np.ndarray]:
    """``x'' = g1`` for x < 0, ``g2`` for x > 0, from ``x0 < 0``, ``v0 > 0`` over ``t``
    (crossing x = 0 once): the end state and its Jacobian, both in closed form."""
    tau = (-v0 + math.sqrt(v0 * v0 - 2 * g1 * x0)) / g1  # x0 + v0 tau + g1 tau^2 / 2 = 0
    vc = v0 + g1 * tau
    s = t - tau
    y = np.array([vc * s + 0.5 * g2 * s * s, vc + g2 * s])
    dtau = np.array([-1.0 / vc, -tau / vc])  # implicit derivative of the crossing condition
    dvc = np.array([0.0, 1.0]) + g1 * dtau
    jac = np.vstack([s * dvc - (vc + g2 * s) * dtau, dvc - g2 * dtau])
    return y, jac


def test_saltation_on_a_discontinuous_field() -> None:
    """E(s) S E(tau) is the closed-form Jacobian of a crossing with a jump in the field;
    without S (the identity of a continuous field) it is off by O(1)."""
    x0, v0, t, g1, g2 = -0.3, 0.8, 1.5, 0.4, -2.5
    y, jac = switched_flow(x0, v0, t, g1, g2)
    tau = (-v0 + math.sqrt(v0 * v0 - 2 * g1 * x0)) / g1
    vc = v0 + g1 * tau

    def e(h: float) -> np.ndarray:  # exp(A h), A = [[0, 1], [0, 0]] on both sides
        return np.array([[1.0, h], [0.0, 1.0]])

    s_mat = saltation(np.array([vc, g1]), np.array([vc, g2]), np.array([1.0, 0.0]))
    ours = e(t - tau) @ s_mat @ e(tau)
    assert np.max(np.abs(ours - jac)) <= 100 * EPS * np.max(np.abs(jac))
    assert np.max(np.abs(e(t - tau) @ e(tau) - jac)) > 0.1 * np.max(np.abs(jac))
    # the normal's sign and length do not matter
    assert np.allclose(saltation(np.array([vc, g1]), np.array([vc, g2]), np.array([-3.0, 0.0])),
                       s_mat, rtol=1e-15, atol=0.0)


def test_saltation_identity_and_grazing() -> None:
    f = np.array([0.0, 2.0])
    assert np.array_equal(saltation(f, f.copy(), np.array([1.0, 0.0])), np.eye(2))
    with pytest.raises(SolverError, match="grazing"):
        saltation(f, np.array([0.0, 3.0]), np.array([1.0, 0.0]))


def backlash_model(load: float, f_ratio: float = 0.8) -> SDOFModel:
    k = rectangular_stiffness(1.5, 1.0e9, 1.75e9)
    fn = math.sqrt(k.mean / 3.0) / (2 * math.pi)
    return SDOFModel(mass=3.0, stiffness=k, damping_ratio=0.06, static_load=load,
                     mesh_frequency=f_ratio * fn, backlash=10e-6)


def test_contact_fields_continuous_at_the_boundaries() -> None:
    """Each contact state's field is the model's right-hand side inside that state, and the
    fields of neighbouring states agree on their boundary (dead zone continuous, damping in
    every state): the saltation matrix of a contact change is the identity."""
    model = backlash_model(2000.0)
    b = float(model.backlash or 0.0)
    kt = float(model.stiffness(0.1))
    pcs = {st: _Piece(model, kt, st) for st in (BACK, GAP, DRIVE)}
    for st, x in ((DRIVE, 1.7 * b), (GAP, 0.3 * b), (BACK, -2.2 * b)):
        for v in (-0.3, 0.0, 0.45):
            ref = model.rhs(0.1 / model.mesh_frequency, np.array([x, v]))
            assert np.allclose(pcs[st].field(x, v), ref, rtol=4 * EPS, atol=0.0)
    for lo, hi, x in ((GAP, DRIVE, b), (BACK, GAP, -b)):
        for v in (-0.3, 0.45):
            assert np.array_equal(pcs[lo].field(x, v), pcs[hi].field(x, v))
            s_mat = saltation(pcs[lo].field(x, v), pcs[hi].field(x, v), np.array([1.0, 0.0]))
            assert np.array_equal(s_mat, np.eye(2))


def test_one_contact_state_is_the_matrix_exponential() -> None:
    """Heavy load, no contact change, inside one stiffness piece: the map is exp(A t) (and the
    state the augmented exponential's), from scipy.linalg, to rounding."""
    model = backlash_model(2.0e5)
    t1 = 0.9 * float(model.switching_times(0.0, 1 / model.mesh_frequency)[0])
    kt = float(model.stiffness(model.phase(0.5 * t1)))
    m, c, w, b = model.mass, model.damping, model.static_load, float(model.backlash or 0.0)
    y0 = model.initial_state() + np.array([0.0, 0.01])
    y, phi = flow_with_sensitivity(model, y0, t1)
    aug = np.array([[0.0, 1.0, 0.0], [-kt / m, -c / m, (w + kt * b) / m], [0.0, 0.0, 0.0]])
    ref = expm(aug * t1)
    assert np.max(np.abs(phi - ref[:2, :2]) / np.abs(ref[:2, :2]).max(axis=1)[:, None]) \
        <= 1e-13
    y_ref = ref[:2, :2] @ y0 + ref[:2, 2]
    assert np.all(np.abs(y - y_ref) <= 1e-13 * np.abs(y_ref))
    assert y[0] > b  # stayed in drive-flank contact


def test_sensitivity_across_stiffness_switches_and_contact_changes() -> None:
    """Over two mesh periods with separation: central differences of the exact flow
    (tolerance: its stated rounding over h plus the Richardson truncation estimate)."""
    model = backlash_model(500.0, 0.7)
    y0 = model.initial_state() + np.array([0.0, -4 * model.state_scale[1]])
    t1 = 2 / model.mesh_frequency
    assert model.switching_times(0.0, t1).size == 3
    traj, st = propagate_contact_exact(model, np.linspace(0.0, t1, 2001), y0=y0)
    assert st["n_contact_events"] >= 4 and np.min(traj[0]) < -float(model.backlash or 0.0)
    _y, phi = flow_with_sensitivity(model, y0, t1)
    scale = model.state_scale

    def central(h: float) -> np.ndarray:
        d = np.empty((2, 2))
        for j in range(2):
            e = np.zeros(2)
            e[j] = h * scale[j]
            d[:, j] = (flow_with_sensitivity(model, y0 + e, t1)[0]
                       - flow_with_sensitivity(model, y0 - e, t1)[0]) / (2 * e[j])
        return d / scale[:, None] * scale[None, :]

    d1, d2 = central(1e-4), central(2e-4)
    rounding = rounding_bound(traj, scale, int(st["n_segments"]))
    tol = rounding / 1e-4 + 2 * np.abs(d1 - d2)
    assert np.all(np.abs(phi / scale[:, None] * scale[None, :] - d1) <= tol)
