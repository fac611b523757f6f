"""The [lead_modification], [misalignment] and [slice_contact] tables: units, refusals, and the
single-DOF model a helical pair with [tip_relief] gets from the slice loaded contact."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scene_cases import edited_scene

from gear_dyn.errors import SceneError
from gear_dyn.models.relief import ReliefSDOFModel
from gear_dyn.modification.slice_contact import slice_contact
from gear_dyn.scene import build_model, build_pair, load_scene
from gear_dyn.scene.lead import flank_from_scene, slice_options_from_scene

RAIL = Path(__file__).resolve().parents[2] / "examples" / "scenes" / "rail_helical_ltca.toml"


def test_rail_scene_runs_on_the_slice_loaded_contact() -> None:
    scene = load_scene(RAIL)
    pair = build_pair(scene)
    assert pair.helix_angle == pytest.approx(math.radians(20))
    flank = flank_from_scene(scene, pair)
    assert flank.lead_pinion is not None and flank.lead_pinion.crowning == pytest.approx(8e-6)
    assert flank.misalignment is not None and flank.misalignment.f_ma == pytest.approx(10e-6)
    model = build_model(scene)
    assert isinstance(model, ReliefSDOFModel)
    assert model.summary_info()["stiffness_method"] == "slice LTCA (tangent)"
    # the model's stiffness and TE are the slice analysis at the scene's torque: its static
    # solution k_t (x - e) = W is the loaded static TE at every mesh position
    from gear_dyn.scene.modification import relief_from_scene

    flank = flank_from_scene(scene, pair, relief_from_scene(scene, pair))
    sc = slice_contact(pair, 2000.0, flank, options=slice_options_from_scene(scene))
    w = 2000.0 / pair.rb1
    x = w / model.stiffness(sc.phase) + model.transmission_error.value(sc.phase)
    np.testing.assert_allclose(x, sc.deflection[0], rtol=1e-9)


def test_lead_tables_refuse_bad_values() -> None:
    with pytest.raises(SceneError, match="end_relief_length"):
        build_model(edited_scene("rail_helical_ltca",
                                 lead_modification={"end_relief_gear": 5e-6}))
    with pytest.raises(SceneError, match="end_relief_length"):  # longer than half the face
        build_model(edited_scene("rail_helical_ltca",
                                 lead_modification={"end_relief_gear": 5e-6,
                                                    "end_relief_length_gear": 0.05}))
    with pytest.raises(SceneError, match="linearisation"):
        build_model(edited_scene("rail_helical_ltca", tip_relief={"linearisation": "secant"}))


def test_a_spur_pair_with_misalignment_only_uses_the_slice_contact() -> None:
    sc = edited_scene("helicopter_tail", stiffness=None, misalignment={"f_ma": 5e-6})
    model = build_model(sc)
    assert model.summary_info()["stiffness_method"] == "slice LTCA (tangent)"
