"""Folds followed in (speed, torque) (gear_dyn.analysis.continuation.fold_map) against
independent checks: the one-parameter speed branch of the model itself, the coexistence of two
stable orbits found by integration and shooting from two starts, and folds located on torque
branches at a fixed speed (a second continuation direction through the same fold curve).

The test model is backlash_oscillator.py's: m = 1 kg, a rectangular mesh stiffness (contact
ratio 1.6, 0.8e6 / 1.2e6 N/m; piecewise constant, so every map is the backlash oscillator's
piecewise closed form, route ``exact``), half gap 1 mm, 20 pinion teeth, base radius 0.05 m:
52 N m is its 1040 N load. Speeds as f_m / f_n.
"""

from __future__ import annotations

import json
import math

import matplotlib
import numpy as np
import pytest
from backlash_oscillator import TEETH, WN, oscillator

from gear_dyn import InputError, SDOFModel
from gear_dyn.analysis.continuation import (
    Branch,
    ContinuationSettings,
    FoldMap,
    SpeedTorqueFamily,
    continue_orbits,
    fold_map,
    sdof_family,
)
from gear_dyn.analysis.continuation.fold_curve import _match, fold_pairs
from gear_dyn.analysis.continuation.orbit import map_only
from gear_dyn.analysis.stability import shoot

RB = 0.05
T0 = 1040.0 * RB  # N m
WINDOW = (0.7 * WN / TEETH, 1.0 * WN / TEETH)
#: fewer, longer steps than the default: the folds are still located to locate_tol
SETTINGS = ContinuationSettings(step_max=0.2)


def _family() -> SpeedTorqueFamily:
    return SpeedTorqueFamily(sdof_family(oscillator(), "speed", teeth=TEETH), T0)


def _ratio(speed: float) -> float:
    return speed * TEETH / WN


@pytest.fixture(scope="module")
def fmap() -> FoldMap:
    """Three speed branches (about 8 s each on a loaded 2-core machine): 52 N m (two loops),
    250 N m (the second loop is gone: its cusp lies near 206 N m) and one bisection."""
    return fold_map(_family(), WINDOW, [T0, 250.0], settings=SETTINGS, cusp_bisections=1,
                    reference_torque=T0)


@pytest.fixture(scope="module")
def branch() -> Branch:
    """The model's own speed branch at 52 N m (sdof_family of the unscaled model)."""
    return continue_orbits(sdof_family(oscillator(), "speed", teeth=TEETH), *WINDOW,
                           settings=SETTINGS, doublings=0)


@pytest.mark.slow
def test_at_the_reference_torque_the_fold_curves_are_the_speed_branch_folds(fmap, branch
                                                                             ) -> None:
    """The folds of the map at 52 N m are those of the model's own speed branch (a separate
    run), to 1e-8 relative: the torque family reproduces the model at its own torque and
    every fold is located by the same bracketing."""
    pairs = fold_pairs(branch)
    assert len(pairs) == 2 == len(fmap.regions)
    for region, (lo, hi, *_rest) in zip(fmap.regions, pairs, strict=True):
        assert region.torque[0] == T0
        assert region.low[0] == pytest.approx(lo, rel=1e-8)
        assert region.high[0] == pytest.approx(hi, rel=1e-8)
        assert region.low_error[0] < 1e-8 * lo and region.high_error[0] < 1e-8 * hi


@pytest.mark.slow
def test_the_second_loop_ends_at_a_cusp_and_the_first_persists(fmap) -> None:
    first, second = fmap.regions
    assert first.torque[-1] == 250.0 and not first.cusps
    (cusp,) = second.cusps
    assert T0 < cusp.torque < 250.0
    assert cusp.torque_error <= (250.0 - T0) / 4  # one bisection of the T0..250 bracket
    assert second.torque.size == 2  # T0 and the bisection's torque, below the cusp
    # the two folds approach each other towards the cusp
    gaps = second.high - second.low
    assert np.all(np.diff(gaps) < 0)
    assert second.low[-1] <= cusp.speed <= second.high[-1]


def _stable_state(br: Branch, speed: float, upper: bool) -> np.ndarray:
    """State of the stable point of ``br`` nearest ``speed`` on the lower branch (full
    contact, below the grazing speed) or the upper one (teeth apart for part of the period)."""
    side = [p for p in br.points if p.stable and (p.separation > 0) == upper]
    return np.asarray(min(side, key=lambda p: abs(p.parameter - speed)).state)


def _settled_orbit(model: SDOFModel, y: np.ndarray) -> np.ndarray:
    """The attracting orbit reached from ``y``: 400 mesh periods of the closed-form flow,
    then shooting; asserts convergence and stability."""
    for _ in range(400):
        y = map_only(model, y, 1, "exact", 1e-10)
    sol = shoot(model, y, 1e-12, 30, 1, "exact")
    assert sol.converged
    assert np.max(np.abs(sol.multipliers)) < 1.0
    return np.asarray(sol.y0)


@pytest.mark.slow
def test_two_stable_orbits_inside_a_region_and_one_outside(fmap, branch) -> None:
    """Two starts, the states of the stable branch points nearest the test speed below and
    above the unstable stretch (lower and upper branch): integration and shooting from them
    reach two different stable orbits inside the first region, and one orbit outside every
    region."""
    fam = _family()
    torque = T0
    first, second = fmap.regions
    inside = 0.5 * (first.low[0] + second.low[0])  # in the first loop, below the second
    assert fmap.coexisting(inside, torque)
    assert sum(r.contains(inside, torque) for r in fmap.regions) == 1
    outside = first.low[0] * 0.97
    assert not fmap.coexisting(outside, torque)
    for speed, n_orbits in ((inside, 2), (outside, 1)):
        model = fam(speed, torque)
        starts = [_stable_state(branch, inside, upper=False), _stable_state(branch, inside,
                                                                          upper=True)]
        orbits = [_settled_orbit(model, y) for y in starts]
        apart = np.max(np.abs(orbits[0] - orbits[1]) / model.state_scale)
        # distinct orbits differ by O(1) in scaled units; one orbit by the shooting tolerance
        assert (apart > 0.1) if n_orbits == 2 else (apart < 1e-6)


@pytest.mark.slow
def test_folds_of_torque_branches_at_fixed_speed_lie_on_the_fold_curves() -> None:
    """Second method: at a fixed speed, a branch in torque folds where the fixed speed
    crosses a fold curve. The speed branch at each of those torques has a fold at that
    speed. Both folds are located to 1e-10 relative in their own parameter (locate_tol) and
    the fold curve's relative slope (T / s) ds/dT is O(1) here, so they agree to 1e-9 with
    room (measured: 6e-13)."""
    model = oscillator()
    speed = 0.9 * WN / TEETH
    fam_t = sdof_family(model.at_mesh_frequency(TEETH * speed / (2 * math.pi)), "torque",
                        base_radius=RB)
    br_t = continue_orbits(fam_t, 60.0, 150.0, parameter="torque", settings=SETTINGS,
                           doublings=0)
    folds = br_t.of_kind("fold")
    assert len(folds) == 2
    fm = fold_map(_family(), WINDOW, [f.parameter for f in folds], settings=SETTINGS,
                  cusp_bisections=0)
    assert len(fm.folds) == 2  # the speed branches at the two fold torques, in order
    for speeds_at in fm.folds:
        assert min(abs(s / speed - 1.0) for s in speeds_at) < 1e-9


@pytest.mark.slow
def test_rows_json_repr_and_plot(fmap) -> None:
    matplotlib.use("Agg")
    rows = fmap.rows()
    kinds = {r["kind"] for r in rows}
    assert kinds == {"low", "high", "cusp"}
    assert len([r for r in rows if r["kind"] == "cusp"]) == 1
    json.dumps(fmap.to_dict())
    assert repr(fmap).startswith("FoldMap(2 jump regions") and "cusp at" in repr(fmap)
    fig = fmap.plot()
    ax = fig.axes[0]
    assert ax.get_xlabel() == "pinion speed (rpm)"
    assert sum(p.get_label().startswith("jump region") for p in ax.patches) == 2
    assert any("cusp" in t.get_text() for t in ax.texts)


def test_a_loop_born_inside_a_wider_one_is_a_new_loop() -> None:
    """The packaged backlash scene between 300 and 400 N m (fold speeds in rpm): a small loop
    appears inside the wide one; the wide one keeps its track (matched by fold speeds, not by
    midpoints, which lie nearer the small loop's)."""
    prev = [(3467.0, 3555.0, 0.0, 0.0), (4725.0, 6112.0, 0.0, 0.0)]
    new = [(3467.0, 3555.0, 0.0, 0.0), (4964.0, 6112.0, 0.0, 0.0), (5334.0, 5546.0, 0.0, 0.0)]
    assert sorted(_match(prev, new, 6500.0)) == [(0, 0), (1, 1)]
    assert sorted(_match(new, prev, 6500.0)) == [(0, 0), (1, 1)]


def test_bad_input_is_refused_naming_the_field() -> None:
    with pytest.raises(InputError, match="torques: 1 given"):
        fold_map(_family(), WINDOW, [T0])
    with pytest.raises(InputError, match="torque"):
        fold_map(_family(), WINDOW, [T0, -1.0])
    with pytest.raises(InputError, match="the window is empty"):
        fold_map(_family(), (WINDOW[0], WINDOW[0]), [T0, 2 * T0])
    with pytest.raises(InputError, match="torque_ref"):
        SpeedTorqueFamily(sdof_family(oscillator(), "speed", teeth=TEETH), 0.0)
    assert _family()(WINDOW[0], 2 * T0).static_load == pytest.approx(2080.0, rel=1e-15)
    assert _ratio(WINDOW[1]) == pytest.approx(1.0)


@pytest.mark.slow
def test_rows_and_json_name_both_speed_units_the_frequency_ratio_and_the_tolerance(fmap, branch
                                                                                   ) -> None:
    """fold_curve rows: speed in rad/s and rpm, f_m / f_n from the oscillator's own f_n
    (f_m = z1 omega / 2 pi), the stability either side of each fold and the locate tolerance;
    a cusp states its torque error and the folds' half gap, but no speed error (the half gap
    is not a bound). branch.json rows the same units."""
    rows = fmap.rows()
    fn = WN / (2 * math.pi)
    assert fmap.natural_frequency == pytest.approx(fn, rel=1e-12)
    for r in rows:
        assert r["speed_rpm"] == pytest.approx(r["speed_rad_s"] * 60 / (2 * math.pi), rel=1e-15)
        assert r["frequency_ratio"] == pytest.approx(_ratio(r["speed_rad_s"]), rel=1e-12)
        assert r["locate_tol"] == SETTINGS.locate_tol
    folds = [r for r in rows if r["kind"] != "cusp"]
    assert {r["stability"] for r in folds} == {"stable->unstable", "unstable->stable"}
    (cusp,) = [r for r in rows if r["kind"] == "cusp"]
    assert math.isnan(cusp["speed_error_rad_s"]) and cusp["fold_half_gap_rad_s"] > 0
    assert fmap.to_dict()["cusps"][0]["half_gap"] == cusp["fold_half_gap_rad_s"]
    data = branch.to_dict()
    assert data["natural_frequency_hz"] == pytest.approx(fn, rel=1e-12)
    for b in data["branches"][0]["bifurcations"]:
        assert b["speed_rad_s"] == b["parameter"]
        assert b["speed_rpm"] == pytest.approx(b["parameter"] * 60 / (2 * math.pi), rel=1e-15)
        assert b["frequency_ratio"] == pytest.approx(_ratio(b["parameter"]), rel=1e-12)


def test_the_scene_family_takes_its_torque_from_the_scene() -> None:
    """A scene's speed family knows its torque (operating.torque = 368.6 N m): the torque
    family reads it, refuses a contradicting torque_ref (which would scale every load by the
    wrong factor) and doubles the load at twice the torque; a family that does not know its
    torque needs torque_ref."""
    from gear_dyn.scene import load_scene
    from gear_dyn.scene.sweep import SceneModels

    models = SceneModels.of(load_scene("helicopter_tail_backlash"))
    fam = SpeedTorqueFamily(models)
    assert fam.reference == models.torque == 368.6
    w = 5000 * 2 * math.pi / 60
    assert fam(w, 2 * 368.6).static_load == pytest.approx(2 * models(w).static_load,
                                                          rel=1e-15)
    assert SpeedTorqueFamily(models, 368.6).reference == 368.6
    with pytest.raises(InputError, match=r"torque_ref = 1474.4 N\*m: .* at 368.6 N\*m"):
        SpeedTorqueFamily(models, 1474.4)
    with pytest.raises(InputError, match="give torque_ref"):
        SpeedTorqueFamily(sdof_family(oscillator(), "speed", teeth=TEETH))
