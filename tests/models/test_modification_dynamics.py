"""Tip relief in the single-DOF model: quasi-static limit and the nonlinear contact reference."""

from __future__ import annotations

import math

import pytest

from gear_dyn.analysis.study import simulate
from gear_dyn.errors import InputError
from gear_dyn.geometry import GearPair
from gear_dyn.models.relief import ContactSDOFModel, pair_stiffness_function, relief_sdof
from gear_dyn.modification import recommended_relief
from gear_dyn.solvers import SolverSettings

PAIR = GearPair(23, 64, 6e-3, math.radians(22.5), 50e-3, youngs_modulus1=207e9,
                youngs_modulus2=207e9)
TORQUE = 1474.4
FN = pair_stiffness_function(PAIR)


def test_static_states_agree_with_loaded_contact() -> None:
    """The nonlinear model's static state (bisection on sum K_j max(0, x - g_j) = W) and the
    linearised model's static solution W / k_t + e both equal the loaded-contact delta (exact
    sorted solution) at phase 0."""
    mod = recommended_relief(PAIR, TORQUE, "niemann").modification("linear")
    speed = 3319 * 2 * math.pi / 60
    lin, lc = relief_sdof(PAIR, speed, TORQUE, mod, FN)
    nl = ContactSDOFModel(PAIR, speed, TORQUE, mod, FN, table_points=4001)
    delta0 = float(lc.static_transmission_error().value(0.0))
    # bisection to 2^-200; the K and g tables are linear between 4001 points: ~1e-7 relative
    assert nl.initial_state()[0] == pytest.approx(delta0, rel=1e-6)
    assert nl.initial_state()[1] == 0.0
    x_lin = lin.static_load / float(lin.stiffness(0.0)) + float(lin.transmission_error.value(0.0))
    assert x_lin == pytest.approx(delta0, rel=1e-9)


def test_tangent_linearisation_matches_nonlinear_contact() -> None:
    """At the speed of Jiang et al. (2018) the tangent model's dynamic factor is within 1 % of the
    nonlinear contact model's (measured 0.3 %, benchmarks/results/relief.md); the secant K_TPM
    model misses by ~10 %."""
    mod = recommended_relief(PAIR, TORQUE, "dudley").modification("linear")
    speed = 3319 * 2 * math.pi / 60
    settings = SolverSettings(method="DOP853", rtol=1e-6, samples_per_period=64)
    kv = {}
    for lin in ("tangent", "secant"):
        model, _ = relief_sdof(PAIR, speed, TORQUE, mod, FN, samples_per_segment=16,
                               linearisation=lin)
        kv[lin] = simulate(model, 16 / model.mesh_frequency, settings,
                           8 / model.mesh_frequency).dynamic_factor
    nl = ContactSDOFModel(PAIR, speed, TORQUE, mod, FN)
    kv["contact"] = simulate(nl, 16 / nl.mesh_frequency, settings,
                             8 / nl.mesh_frequency).dynamic_factor
    assert kv["tangent"] == pytest.approx(kv["contact"], rel=0.01)
    assert abs(kv["secant"] - kv["contact"]) > 5 * abs(kv["tangent"] - kv["contact"])


def test_bad_linearisation_and_method() -> None:
    with pytest.raises(InputError, match="linearisation = 'x'"):
        relief_sdof(PAIR, 100.0, TORQUE, None, FN, linearisation="x")
    with pytest.raises(InputError, match="pair stiffness method = 'iso'"):
        pair_stiffness_function(PAIR, "iso")
