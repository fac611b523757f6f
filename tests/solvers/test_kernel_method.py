"""The ``kernel`` method (the native FMU's compiled stepper over the grid) against the Python
reference routes, each comparison within the sum of the two runs' stated errors."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from gear_dyn.analysis.accuracy import error_scale, error_series, relative_errors
from gear_dyn.errors import InputError
from gear_dyn.models.sdof import SDOFModel
from gear_dyn.scene import load_scene, run_scene
from gear_dyn.scene.build import build_model, build_plan
from gear_dyn.scene.operating import with_operating
from gear_dyn.solvers import SolverSettings, integrate, resolve_method, time_grid
from gear_dyn.solvers import kernel_method as kmod
from gear_dyn.solvers.kernel_method import kernel_form, shared_table, table_bound, table_ready
from gear_dyn.solvers.result import Result
from gear_dyn.stiffness.periodic import rectangular_stiffness


def _stated(r: Result) -> float:
    return float(r.extra["estimated_error"]["max_rel"])


def _dte_gap(sc_name: str, k: Result, ref: Result, speed: str | None = None) -> float:
    from gear_dyn.scene.operating import with_operating

    sc = with_operating(load_scene(sc_name), speed, None, function="test")
    model = build_plan(sc).model
    return relative_errors(model, k.t, k.y, ref.y)[0]


def test_backlash_scene_at_its_mesh_resonance_matches_exact_contact() -> None:
    """helicopter_tail_backlash near f_m = f_n: the teeth separate; the kernel (closed form on
    the flat pieces, contact changes located in C) against the closed form of exact_contact."""
    kw = {"speed": "7600 rpm", "periods": 80, "steady_periods": 40}
    sc = load_scene("helicopter_tail_backlash")
    k = run_scene(sc, method="kernel", **kw)  # type: ignore[arg-type]
    e = run_scene(sc, method="exact_contact", **kw)  # type: ignore[arg-type]
    assert k.stats.method == "kernel" and e.stats.method == "exact_contact"
    assert k.extra["contact"]["separation_share"] > 0.01  # the case must separate the teeth
    gap = _dte_gap("helicopter_tail_backlash", k, e, "7600 rpm")
    assert gap <= _stated(k) + _stated(e), (gap, _stated(k), _stated(e))
    assert _stated(k) < 1e-6
    default = run_scene(sc, **kw)  # type: ignore[arg-type]
    assert default.stats.method == "exact_contact"  # auto: the compiled contact walk


def test_eccentric_scene_matches_gauss() -> None:
    """eccentric_helical over 40 mesh periods: kernel (polynomial table in phase) against gauss
    (the model's own table in time, Gauss-Legendre step maps) at a tighter rtol."""
    sc = load_scene("eccentric_helical")
    kw = {"periods": 40, "steady_periods": 20}
    k = run_scene(sc, method="kernel", **kw)  # type: ignore[arg-type]
    g = run_scene(sc, method="gauss", rtol=1e-10, **kw)  # type: ignore[arg-type]
    gap = _dte_gap("eccentric_helical", k, g)
    est = k.extra["estimated_error"]
    assert gap <= _stated(k) + _stated(g), (gap, _stated(k), _stated(g))
    assert 0.0 < est["table_part"] < est["max_rel"] < 1e-6


def test_relief_scene_matches_its_linear_route() -> None:
    """helicopter_tail_relief: the loaded-contact tables (piecewise linear in phase, exact in
    the kernel's table) stepped by Runge-Kutta, against the auto route (linear: periodic)."""
    sc = load_scene("helicopter_tail_relief")
    kw = {"periods": 60, "steady_periods": 30}
    k = run_scene(sc, method="kernel", **kw)  # type: ignore[arg-type]
    ref = run_scene(sc, method="auto", **kw)  # type: ignore[arg-type]
    assert ref.stats.method == "periodic"
    gap = _dte_gap("helicopter_tail_relief", k, ref)
    assert gap <= _stated(k) + _stated(ref), (gap, _stated(k), _stated(ref))
    assert k.extra["estimated_error"]["table_part"] < 1e-12  # exact table: rounding only


def _backlash(phase0: float = 0.0) -> SDOFModel:
    return SDOFModel(mass=3.0, stiffness=rectangular_stiffness(1.58, 0.7e9, 1.24e9),
                     damping_ratio=0.06, static_load=1000.0, mesh_frequency=2900.0,
                     backlash=1e-5, phase0=phase0)


def test_a_run_from_a_later_start_and_phase() -> None:
    """A grid that starts at t0 > 0 from a given state, on a model with a phase offset: the
    kernel starts at the model's phase there (as a sweep or a continuation restarts)."""
    m = _backlash(phase0=0.3)
    t = 2.37 / m.mesh_frequency + time_grid(m.mesh_frequency, 20 / m.mesh_frequency, 64)
    y0 = m.initial_state() + np.array([0.0, -3.0 * m.state_scale[1]])
    y, st = integrate(m, t, SolverSettings(method="kernel"), y0)
    y_e, _ = integrate(m, t, SolverSettings(method="exact_contact"), y0)
    assert st["n_events"] > 10
    gap = relative_errors(m, t, y, y_e)[0]
    assert gap < 1e-7, gap  # both closed form on this table; the contact instants located
    x = error_series(m, t, y)
    assert np.all(np.isfinite(x)) and error_scale(m) > 0


def test_auto_choice_and_refusal(monkeypatch: pytest.MonkeyPatch) -> None:
    """auto: the kernel for the eccentric torsional model on any span, whether or not the
    pair's table is built (the choice does not depend on what ran before in the process),
    exact_contact for backlash; exact for the linear model; ``kernel`` asked for a model it
    does not step names what it steps."""
    bl = _backlash()
    t = time_grid(bl.mesh_frequency, 10 / bl.mesh_frequency, 64)
    assert resolve_method(bl, t, "auto") == "exact_contact"
    assert resolve_method(replace(bl, backlash=None), t, "auto") == "exact"
    ecc = build_plan(load_scene("eccentric_helical")).model
    hunting = ecc.mesh.hunting_period
    short = np.linspace(0.0, 0.01 * hunting, 50)
    # the pair's table dropped (kernel_method._TABLES is process-global): a short run of a pair
    # without one takes the kernel, and so does the same run once the table is built
    fresh = replace(ecc, torque=ecc.torque * 1.0137)
    with kmod._LOCK:
        for split in (False, True):
            kmod._TABLES.pop((kmod.table_key(fresh), split), None)
    assert not table_ready(fresh)
    assert resolve_method(fresh, short, "auto") == "kernel"
    assert table_ready(fresh)
    assert resolve_method(fresh, short, "auto") == "kernel"
    assert resolve_method(ecc, np.linspace(0.0, hunting, 50), "auto") == "kernel"
    slow = build_model(with_operating(load_scene("eccentric_helical"), ecc.speed / 64, si=True))
    assert resolve_method(slow, short * 64, "auto") == "kernel"
    # without the compiled library auto goes on to gauss (this model is affine in the state)
    monkeypatch.setattr(kmod, "_available", lambda: False)
    assert resolve_method(fresh, short, "auto") == "gauss"
    monkeypatch.undo()
    ideal = build_plan(load_scene("eccentric_helical_ideal")).model
    with pytest.raises(InputError, match="does not apply to the TorsionalModel"):
        integrate(ideal, np.linspace(0.0, 1e-3, 5), SolverSettings(method="kernel"))


def test_table_bound_grows_with_the_table_error() -> None:
    """The table part of the stated error: zero for an exact table, positive for a fitted one,
    and larger for a lighter damping (the dynamic amplification 1 + 1/(2 xi))."""
    bl = _backlash()
    t = time_grid(bl.mesh_frequency, 5 / bl.mesh_frequency, 16)
    y, _ = integrate(bl, t, SolverSettings(method="kernel"))
    assert table_bound(bl, t, y) == 0.0
    ecc = build_plan(load_scene("eccentric_helical")).model
    t = time_grid(ecc.mesh_frequency, 5 / ecc.mesh_frequency, 16)
    y, _ = integrate(ecc, t, SolverSettings(method="kernel"))
    assert kernel_form(ecc).table_error > 0.0
    light = replace(ecc, damping_ratio=0.01)
    assert table_bound(light, t, y) > table_bound(ecc, t, y) > 0.0


def test_shared_table_holds_at_another_speed() -> None:
    """The torsional table is one of the mesh phase: built at the scene's speed, it meets its
    stated error against the pair rebuilt at 1/64 of that speed (the quasi-static reference's),
    de_ecc/dp = (de_ecc/dt) / f_m at the slow f_m, at phases off its nodes and check points."""
    scene = load_scene("eccentric_helical")
    ecc = build_plan(scene).model
    slow = build_model(with_operating(scene, ecc.speed / 64, si=True))
    tab = shared_table(ecc)
    assert shared_table(slow) is tab
    phase = np.random.default_rng(7).uniform(0.0, float(tab.period), 2000)
    ex = slow.excitations(phase / slow.mesh_frequency)
    exact = np.array([ex["e_ecc"], ex["e_ecc_rate"] / slow.mesh_frequency, ex["stiffness"],
                      ex["phi1"], ex["phi2"]])
    x_s = slow.static_load / slow.mean_stiffness
    scale = np.array([x_s, x_s, slow.mean_stiffness, slow.pair.rb1, slow.pair.rb2])
    err = np.max(np.abs(tab.evaluate(phase) - exact), axis=1) / scale
    stated = np.array([tab.max_error[q] for q in ("e_ecc", "de_dp", "stiffness", "phi1", "phi2")])
    # the check points are where the error peaks: off them it is below the stated figure (a
    # 1e-15 margin for rounding of k and the arms, whose errors are near it)
    assert np.all(err <= stated + 1e-15), (err, stated)


def test_check_run_states_the_run_error() -> None:
    """The check run (every step halved: on the table split at every piece's middle, which is
    the same table, at a 32 times tighter tolerance) states between one and four times the
    run's error against a run at the kernel's tightest tolerance (the estimate is twice the
    difference, the check's own error about 1/32 of the run's), on the packaged eccentric scene
    at rtol 1e-6."""
    from gear_dyn.solvers.kernel.run import run
    from gear_dyn.solvers.kernel.tables_torsional import split_table
    from gear_dyn.solvers.kernel_method import check_run, kernel_tolerance

    plan = build_plan(load_scene("eccentric_helical"))
    ecc = plan.model
    tab = shared_table(ecc)
    phase = np.random.default_rng(3).uniform(0.0, float(tab.period), 1000)
    whole, halves = tab.evaluate(phase), split_table(tab).evaluate(phase)
    assert np.allclose(halves, whole, rtol=1e-12, atol=1e-12 * np.max(np.abs(whole), axis=1,
                                                                      keepdims=True))
    t = time_grid(ecc.mesh_frequency, plan.t_end, plan.settings.samples_per_period)
    km = kernel_form(ecc)
    y0 = ecc.initial_state()
    y = run(km, t, y0, kernel_tolerance(ecc, km, 1e-6))[0]
    x, x_s = error_series(ecc, t, y), error_scale(ecc)
    err = float(np.max(np.abs(x - error_series(ecc, t, run(km, t, y0, 1e-14)[0])))) / x_s
    y_c, _, ex_c = check_run(ecc, t, y0, 1e-6)
    stated = 2 * float(np.max(np.abs(x - error_series(ecc, t, y_c, ex_c)))) / x_s
    assert err < stated < 4 * err, (err, stated)
