"""The FMU's stepper (no FMU yet): it must reproduce solve_ivp and restore its state exactly."""

from __future__ import annotations

import pickle
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scene_cases import edited_scene

from gear_dyn.fmu.inputs import input_changes
from gear_dyn.fmu.stepper import Stepper
from gear_dyn.scene import build_pair, build_plan, load_scene
from gear_dyn.solvers import integrate, time_grid

pytestmark = pytest.mark.fmu

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"


@pytest.fixture(scope="module")
def heli():  # type: ignore[no-untyped-def]
    scene = load_scene(SCENES / "helicopter_tail.toml")
    return scene, build_plan(scene)


def _run(stepper: Stepper, grid: np.ndarray) -> np.ndarray:
    return np.array([stepper.y] + [stepper.advance(t) for t in grid[1:]]).T


@pytest.mark.parametrize("method", ["DOP853", "LSODA"])
def test_kept_solver_reproduces_solve_ivp(heli, method: str) -> None:  # type: ignore[no-untyped-def]
    """One solver object stepped to each communication point, restarted only at the switching
    instants, takes the very steps solve_ivp takes piece by piece: the states agree to
    rounding (1e-12 of the static deflection; both read the dense output at the same times)."""
    _, plan = heli
    model = plan.model
    settings = replace(plan.settings, method=method)
    grid = time_grid(model.mesh_frequency, 6 / model.mesh_frequency, 16)
    y_ref, _ = integrate(model, grid, settings)
    y = _run(Stepper(model, settings), grid)
    rel = np.max(np.abs(y - y_ref), axis=1) / model.state_scale
    assert np.all(rel < 1e-12)


def test_exact_stepping_matches_exact_propagator(heli) -> None:  # type: ignore[no-untyped-def]
    """Exact propagation step by step (state carried across communication points) against the
    one-shot exact propagator: both are exact, so only rounding differs (1e-11 relative over
    20 mesh periods of 2x2 products)."""
    _, plan = heli
    model = plan.model
    settings = replace(plan.settings, method="exact")
    grid = time_grid(model.mesh_frequency, 20 / model.mesh_frequency, 8)
    y_ref, _ = integrate(model, grid, settings)
    y = _run(Stepper(model, settings), grid)
    rel = np.max(np.abs(y - y_ref), axis=1) / model.state_scale
    assert np.all(rel < 1e-11)


@pytest.mark.parametrize("method", ["DOP853", "BDF", "LSODA", "exact"])
def test_snapshot_restores_the_integrator_exactly(heli, method: str) -> None:  # type: ignore[no-untyped-def]
    """A pickled snapshot taken mid-run, restored later, continues bit for bit: the solver's
    step size, stages and (LSODA) work arrays come back, not only the model state."""
    _, plan = heli
    model = plan.model
    settings = replace(plan.settings, method=method)
    grid = time_grid(model.mesh_frequency, 3 / model.mesh_frequency, 16)
    st = Stepper(model, settings)
    for t in grid[1:20]:
        st.advance(t)
    snap = pickle.loads(pickle.dumps(st.snapshot()))
    first = np.array([st.advance(t) for t in grid[20:]])
    st.restore(snap)
    again = np.array([st.advance(t) for t in grid[20:]])
    np.testing.assert_array_equal(first, again)
    fresh = Stepper(model, settings)  # into another stepper of the same model, too
    fresh.restore(snap)
    np.testing.assert_array_equal(first, np.array([fresh.advance(t) for t in grid[20:]]))


def test_speed_input_keeps_mesh_phase_continuous(heli) -> None:  # type: ignore[no-untyped-def]
    """A new pinion speed changes f_m and W = T1 / r_b1 but not the mesh phase at the change
    instant (the stiffness seen just before and after the change is the same value)."""
    scene, plan = heli
    model, pair = plan.model, build_pair(scene)
    t = 3.3 / model.mesh_frequency
    ch = input_changes(model, pair, 400.0, 2000.0, t)
    new = replace(model, **ch)
    assert new.mesh_frequency == pytest.approx(pair.z1 * 400.0 / (2 * np.pi), rel=1e-15)
    assert new.static_load == pytest.approx(2000.0 / pair.rb1, rel=1e-15)
    assert float(new.phase(t)) == pytest.approx(float(model.phase(t)), abs=1e-12)


def test_contact_changes_restart_the_solver_as_integrate_does() -> None:
    """Backlash with a light load and a 20 um transmission error: the teeth separate and
    re-engage. The stepper locates each contact change in the kept solver's dense output and
    restarts there, as integrate's event handling does, so both count the same changes and
    agree to rounding; a snapshot taken between changes restores exactly."""
    plan = build_plan(edited_scene("helicopter_tail_backlash", transmission_error={"cos": [20e-6]},
                                   operating={"torque": 50.0}))
    model = plan.model
    settings = replace(plan.settings, method="DOP853")
    grid = time_grid(model.mesh_frequency, 3 / model.mesh_frequency, 256)
    y_ref, stats = integrate(model, grid, settings)
    st = Stepper(model, settings)
    y = _run(st, grid)
    assert stats["n_contact_events"] >= 8
    assert st.n_events == stats["n_contact_events"]
    assert np.all(np.max(np.abs(y - y_ref), axis=1) / model.state_scale < 1e-12)
    st2 = Stepper(model, settings)
    for t in grid[1:400]:
        st2.advance(t)
    snap = pickle.loads(pickle.dumps(st2.snapshot()))
    first = np.array([st2.advance(t) for t in grid[400:]])
    st2.restore(snap)
    np.testing.assert_array_equal(np.array([st2.advance(t) for t in grid[400:]]), first)


def test_exact_stepping_at_an_incommensurate_step(heli) -> None:  # type: ignore[no-untyped-def]
    """A communication step that does not divide the mesh period: every step that holds a
    switching instant has new piece durations (new cached propagators), the others reuse
    them with the second-order remainder. Against the one-shot exact propagator: rounding
    only (1e-11 relative over 30 mesh periods, as above)."""
    _, plan = heli
    model = plan.model
    settings = replace(plan.settings, method="exact")
    h = 1 / (model.mesh_frequency * 7.3)
    grid = np.arange(220) * h
    y_ref, _ = integrate(model, grid, settings)
    st = Stepper(model, settings)
    y = _run(st, grid)
    rel = np.max(np.abs(y - y_ref), axis=1) / model.state_scale
    assert np.all(rel < 1e-11)
    assert sum(len(p.cache) for p in st._exps.values()) > 20  # noqa: SLF001 (many durations)


@pytest.mark.parametrize("n", [2, 4])
def test_cached_propagator_matches_expm(n: int) -> None:
    """expm(M s) z from the cache (grid value plus second-order remainder) against scipy's
    expm at durations on and off the grid, for two states (unrolled sums) and four (generic
    sums): rounding only (2e-14 relative; without the second-order term 1e-13)."""
    from scipy.linalg import expm

    from gear_dyn.solvers.exact import StepPropagator as _Propagator

    rng = np.random.default_rng(n)
    a = rng.normal(size=(n, n)) * 1e3 - 2e3 * np.eye(n)
    m = np.zeros((n + 1, n + 1))
    m[:-1, :-1], m[:-1, -1] = a, rng.normal(size=n)
    prop = _Propagator(m, 1e-15)
    assert prop.q > 0
    z = [*rng.normal(size=n).tolist(), 1.0]
    s0 = round(1e-4 / prop.q) * prop.q  # on the grid
    for s in (s0, s0 + 0.37 * prop.q, s0 - 0.49 * prop.q, 3.3e-5, s0 + 1e-19):
        ref = expm(m * s) @ np.array(z)
        got = np.array(prop.apply(s, z))
        assert got[-1] == 1.0
        assert np.max(np.abs(got - ref)) < 2e-14 * np.max(np.abs(ref))
    assert len(prop.cache) == 2  # on-grid and nearby durations share one matrix


def test_exact_stepping_without_eigendecomposition() -> None:
    """The plain torsional model (piecewise-constant stiffness, no eccentricity or friction)
    has rigid-body modes: its piece matrices have no usable eigendecomposition, so every
    piece takes the exact propagator's expm path (no cache). Against the one-shot exact
    propagator over 10 mesh periods: rounding (1e-11 relative, as above)."""
    plan = build_plan(edited_scene("eccentric_helical_ideal", friction=None,
                                   stiffness={"method": "iso6336"}))
    model = plan.model
    settings = replace(plan.settings, method="exact")
    grid = time_grid(model.mesh_frequency, 10 / model.mesh_frequency, 16)
    y_ref, _ = integrate(model, grid, settings)
    st = Stepper(model, settings)
    y = _run(st, grid)
    assert all(p.q == 0.0 for p in st._exps.values())  # noqa: SLF001 (the fallback path)
    rel = np.max(np.abs(y - y_ref), axis=1) / np.asarray(model.state_scale)
    assert np.all(rel < 1e-11)
