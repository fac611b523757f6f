"""The compiled contact walk (gd_flow.c, gear_dyn.solvers.kernel.contact) on the packaged backlash
scene at its mesh resonance, against an event-locating DOP853 and against itself.

The reference (dop853_reference.py) is ``solve_ivp(DOP853)`` on the model's right-hand side,
restarted at every stiffness switch and contact change it locates itself, at rtol 1e-12 and
1e-13; its own error is the difference of the two. Each tolerance is the walk's stated error
(:func:`~gear_dyn.solvers.contact_exact.rounding_bound`, through ``estimate_error``) plus that
measured reference error, times two, as in test_contact_exact.py.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from dop853_reference import dop853_events

from gear_dyn.analysis.accuracy import estimate_error, relative_errors
from gear_dyn.errors import InputError
from gear_dyn.scene import build_model, load_scene
from gear_dyn.scene.packaged import scene_path
from gear_dyn.scene.sweep import model_at_speed
from gear_dyn.solvers import SolverSettings, time_grid
from gear_dyn.solvers.contact_exact import (
    flow_with_sensitivity,
    propagate_contact_exact,
    rounding_bound,
    walk,
)
from gear_dyn.solvers.kernel import contact as ck

Z1 = 23  # pinion teeth of the packaged scene


@pytest.fixture(scope="module")
def resonance():
    """The packaged backlash_constant_stiffness scene at f_m = f_n (the mesh resonance, where
    the teeth separate once per mesh period)."""
    scene = load_scene(scene_path("backlash_constant_stiffness"))
    fn = build_model(scene).natural_frequency
    return model_at_speed(scene, 2 * math.pi * fn / Z1)


def test_walk_matches_dop853_at_mesh_resonance(resonance) -> None:
    model = resonance
    t = time_grid(model.mesh_frequency, 30 / model.mesh_frequency, 64)
    y0 = model.initial_state()
    y, st = propagate_contact_exact(model, t, y0=y0)
    y12, ev12 = dop853_events(model, t, 1e-12, y0)
    y13, ev13 = dop853_events(model, t, 1e-13, y0)
    assert ev13.size >= 30, "the case must separate the teeth"
    ours = np.asarray(st["event_times"])
    assert ours.size == ev13.size
    ev_own = float(np.max(np.abs(ev12 - ev13)))
    assert np.max(np.abs(ours - ev13)) <= 10 * ev_own + 1e-12 / model.mesh_frequency
    ref_own = relative_errors(model, t, y12, y13)[0]
    est = estimate_error(model, t, y, SolverSettings(method="exact_contact"), st)["max_rel"]
    err = relative_errors(model, t, y, y13)[0]
    assert err <= 2 * (est + ref_own), (err, est, ref_own)


def test_period_sensitivities_of_one_walk_are_those_of_walks_per_period(resonance) -> None:
    """``marks`` cut one walk into mesh periods: each period's sensitivity equals that of a
    separate walk over that period from the same state (rounding: the states at the marks are
    the on-grid closed form, not the carried state, and their product is the whole walk's)."""
    model = resonance
    n, fm = 12, model.mesh_frequency
    w = walk(model, model.initial_state(), n / fm, marks=np.arange(1, n) / fm)
    phis = w.mark_sensitivities()
    assert phis.shape == (n, 2, 2)
    ys = w.on_grid(np.arange(n + 1) / fm)
    scale = np.asarray(model.state_scale, dtype=float)
    tol = 1e3 * rounding_bound(ys, scale, w.n_segments)
    total = np.eye(2)
    for k in range(n):
        _y, phi = flow_with_sensitivity(model, ys[:, k], (k + 1) / fm, k / fm)
        rel = np.abs(phis[k] - phi) * scale[None, :] / scale[:, None]
        assert float(np.max(rel)) <= tol * float(np.max(np.abs(phi) * scale[None, :]
                                                           / scale[:, None]))
        total = phis[k] @ total
    whole = w.sensitivity()
    assert np.max(np.abs(total - whole) / np.abs(whole).max(axis=1)[:, None]) <= tol
    assert np.array_equal(w.end, ys[:, -1]) or np.max(np.abs(w.end - ys[:, -1]) / scale) \
        <= tol


def test_segment_table_grows_when_the_walk_needs_more_room(resonance) -> None:
    """One stiffness piece holding more contact changes than the first table's room (64 + 4
    per piece): the kernel says so and the walk is run once more with the room it counted;
    the segments tile the span and end where the walk ends."""
    model = resonance
    fm = model.mesh_frequency
    y0 = model.initial_state()
    full = walk(model, y0, 40 / fm)
    mm, pieces = full._tables  # the model's piece table, as walk() exported it
    segs = ck.walk(mm, pieces, np.array([0.0, 40 / fm]), np.array([0]), *y0,
                   4 * float(np.spacing(40 / fm)), 1000)
    assert segs.status == ck.OK and segs.table.shape[0] > 68
    tab = segs.table
    assert np.allclose(tab[1:, 0], tab[:-1, 0] + tab[:-1, 3], rtol=1e-14, atol=0.0)
    assert tab[0, 0] == 0.0 and tab[-1, 0] + tab[-1, 3] == pytest.approx(40 / fm, rel=1e-14)
    u, ok = ck.on_grid(mm, pieces, tab, segs.ids, np.array([40 / fm]))
    scale = np.asarray(model.state_scale, dtype=float)
    assert ok and np.max(np.abs(u[:, 0] - segs.end) / scale) <= 1e-9


def test_bad_tables_and_marks_are_refused(resonance) -> None:
    model = resonance
    with pytest.raises(ValueError, match="tables of shapes"):
        ck.first_crossing(np.zeros(3), np.zeros((3, 9)), 0, 0.0, 0.0, 0.0, 1.0, 1e-12)
    with pytest.raises(ValueError, match="piece row"):
        ck.stays_inside(np.zeros(7), np.zeros((3, 9)), 3, 0.0, 0.0, 0.0)
    with pytest.raises(InputError, match="marks must increase"):
        walk(model, model.initial_state(), 1 / model.mesh_frequency, marks=np.array([2.0]))
    w = walk(model, model.initial_state(), 1 / model.mesh_frequency)
    with pytest.raises(InputError, match="without marks"):
        w.mark_sensitivities()


def test_uniform_grid_sampling_is_the_closed_form_at_each_time(resonance) -> None:
    """On a uniform grid the walk's segments are sampled by the addition theorems from
    tabulated terms; each state equals the closed form evaluated at its time alone (a grid
    of one time is evaluated directly) to rounding, and a grid off uniform (jittered) is
    evaluated directly, to the same states."""
    model = resonance
    t = time_grid(model.mesh_frequency, 20 / model.mesh_frequency, 64)
    w = walk(model, model.initial_state(), float(t[-1]), float(t[0]))
    y = w.on_grid(t)
    pick = np.arange(0, t.size, 7)
    direct = np.stack([w.on_grid(t[i:i + 1])[:, 0] for i in pick], axis=1)
    scale = np.max(np.abs(y), axis=1, keepdims=True)
    eps = np.finfo(float).eps
    assert np.max(np.abs(y[:, pick] - direct) / scale) <= 64 * eps
    rng = np.random.default_rng(3)
    dt = float(t[1] - t[0])
    jittered = np.sort(np.clip(t + rng.uniform(-0.3, 0.3, t.size) * dt, t[0], t[-1]))
    yj = w.on_grid(jittered)
    direct_j = np.stack([w.on_grid(jittered[i:i + 1])[:, 0] for i in pick], axis=1)
    assert np.max(np.abs(yj[:, pick] - direct_j) / scale) <= 64 * eps
