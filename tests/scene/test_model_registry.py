"""One builder per model kind: the sdof kind is built by one function, whatever the import
order, and a second builder for a registered kind is refused."""

from __future__ import annotations

import pytest

from gear_dyn.errors import InputError
from gear_dyn.scene import MODEL_BUILDERS, build_model, load_scene, register_model
from gear_dyn.scene.modification import build_relief_sdof


def test_one_builder_per_kind() -> None:
    assert MODEL_BUILDERS["sdof"] is build_relief_sdof
    register_model("sdof", build_relief_sdof)  # the same builder again: accepted
    with pytest.raises(InputError, match="'sdof' registered twice"):
        register_model("sdof", lambda scene: None)
    assert MODEL_BUILDERS["sdof"] is build_relief_sdof
    # with and without [tip_relief], the one builder
    plain = build_model(load_scene("helicopter_tail"))
    relief = build_model(load_scene("helicopter_tail_relief"))
    assert type(plain).__name__ == "SDOFModel" and relief.mesh_frequency > 0
