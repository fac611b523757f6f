"""One rule for the model at another speed (models.base.at_speed) and one speed range
(geometry.check_speed): every scan and family gives the same model and the same refusal."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gear_dyn import InputError, load_scene
from gear_dyn.analysis.continuation import sdof_family
from gear_dyn.analysis.executor import check_speeds
from gear_dyn.analysis.motion import bifurcation_diagram
from gear_dyn.analysis.sweep import sweep
from gear_dyn.geometry import MAX_SPEED, teeth_mesh_frequency
from gear_dyn.models.base import at_speed
from gear_dyn.scene import Scene
from gear_dyn.scene.build import build_model
from gear_dyn.scene.sweep import SceneModels


def test_model_at_speed_equals_the_scene_rebuilt_at_that_speed() -> None:
    """The fast path (f_m changed alone) against the scene built from scratch at the speed."""
    scene = load_scene("helicopter_tail_backlash")
    w = 4321 * 2 * math.pi / 60
    fast = SceneModels.of(scene)(w)
    op = {**scene.tables["operating"], "speed": w}
    slow = build_model(Scene(source=scene.source, tables={**scene.tables, "operating": op}))
    assert fast.mesh_frequency == pytest.approx(slow.mesh_frequency, rel=1e-15)
    y = np.array([1e-5, 0.01])
    for t in np.linspace(0.0, 1.0 / slow.mesh_frequency, 7):
        np.testing.assert_allclose(fast.rhs(t, y), slow.rhs(t, y), rtol=1e-12)
    fam = sdof_family(SceneModels.of(scene)(300.0), "speed",
                      teeth=scene.get("gear")["teeth_pinion"])
    assert fam(w).mesh_frequency == fast.mesh_frequency
    assert at_speed(fast, 20, 100.0).mesh_frequency == teeth_mesh_frequency(20, 100.0)


@pytest.mark.parametrize("bad", [0.0, -1.0, 2 * MAX_SPEED])
def test_every_scan_refuses_a_speed_out_of_range_alike(bad: float) -> None:
    factory = SceneModels.of(load_scene("helicopter_tail_backlash"))
    fam = sdof_family(factory(300.0), "speed", teeth=20)
    calls = [lambda: check_speeds([300.0, bad], "scan"), lambda: factory(bad), lambda: fam(bad),
             lambda: sweep(factory, [300.0, bad]),
             lambda: bifurcation_diagram(fam, [300.0, bad])]
    for call in calls:
        with pytest.raises(InputError, match=r"speed = .* rad/s is out of range: valid range "
                                             r"0 < x <= 100000 rad/s"):
            call()
    with pytest.raises(InputError, match="scan: no speeds given"):
        check_speeds([], "scan")


def test_model_at_torque_equals_the_pair_built_at_that_torque() -> None:
    """sdof_family over torque and the speed-torque family against sdof_from_pair (W = T / r_b1)
    at the same torque."""
    from gear_dyn import GearPair, rectangular_stiffness, sdof_from_pair
    from gear_dyn.analysis.continuation import SpeedTorqueFamily

    pair = GearPair(19, 48, 3.2e-3, math.radians(20), 16e-3)
    k = rectangular_stiffness(pair.total_contact_ratio, 2e8, 3e8)
    ref = sdof_from_pair(pair, 300.0, 100.0, k)
    built = sdof_from_pair(pair, 300.0, 250.0, k)
    by_torque = sdof_family(ref, "torque", base_radius=pair.rb1)(250.0)
    speeds = sdof_family(ref, "speed", teeth=pair.z1)
    both = SpeedTorqueFamily(speeds, torque_ref=100.0)(300.0, 250.0)
    for m in (by_torque, both):
        assert m.static_load == pytest.approx(built.static_load, rel=1e-15)
        assert m.mesh_frequency == pytest.approx(built.mesh_frequency, rel=1e-15)
    with pytest.raises(InputError, match="torque = -1 N\\*m is out of range"):
        SpeedTorqueFamily(speeds, torque_ref=100.0)(300.0, -1.0)
