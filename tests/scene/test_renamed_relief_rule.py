"""The tip-relief rule of Wang et al. (2024) is ``wang2024``; its old name ``seed001`` still works
in the API, in a scene and on the command line, with a FutureWarning that says what to write."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from gear_dyn.cli import main
from gear_dyn.geometry import GearPair
from gear_dyn.modification.relief import RULES, recommended_relief
from gear_dyn.scene import parse_scene
from gear_dyn.scene.modification import relief_from_scene
from gear_dyn.scene.packaged import SCENES_DIR

OLD_NAME = r"'seed001' is the old name of the rule 'wang2024' \(Wang et al. 2024\)"
PAIR = GearPair(23, 64, 6e-3, math.radians(22.5), 50e-3)
SCENE = {
    "gear": {"teeth_pinion": 23, "teeth_gear": 64, "module": "6 mm",
             "pressure_angle": "22.5 deg", "face_width": "50 mm"},
    "operating": {"speed": "3319 rpm", "torque": "1474.4 N*m"},
}


def test_the_rule_is_named_after_the_paper() -> None:
    assert "wang2024" in RULES and "seed001" not in RULES


def test_old_name_in_the_api_warns_at_the_caller_and_gives_the_same_relief() -> None:
    new = recommended_relief(PAIR, 1474.4, "wang2024")
    with pytest.warns(FutureWarning, match=OLD_NAME) as record:
        old = recommended_relief(PAIR, 1474.4, "seed001")
    assert record[0].filename == __file__  # stacklevel: the warning names this line
    assert old == new  # same rule name, source, amounts, heights and lengths
    assert new.amount_pinion > 0 and new.length_pinion > 0


def test_old_name_in_a_scene_warns_with_the_key_path_and_gives_the_same_relief() -> None:
    new = relief_from_scene(parse_scene({**SCENE, "tip_relief": {"rule": "wang2024"}}, "n.toml"))
    with pytest.warns(FutureWarning, match=r"o\.toml: tip_relief\.rule = " + OLD_NAME):
        scene = parse_scene({**SCENE, "tip_relief": {"rule": "seed001"}}, "o.toml")
    assert scene.tables["tip_relief"]["rule"] == "wang2024"
    assert relief_from_scene(scene) == new


@pytest.mark.filterwarnings("default::FutureWarning")
def test_cli_shows_the_warning_as_one_line(tmp_path: Path,
                                           capsys: pytest.CaptureFixture[str]) -> None:
    text = (SCENES_DIR / "helicopter_tail_relief.toml").read_text(encoding="utf-8")
    assert 'rule = "wang2024"' in text  # the packaged scene uses the new name
    old = tmp_path / "old.toml"
    old.write_text(text.replace('rule = "wang2024"', 'rule = "seed001"'), encoding="utf-8")
    new = tmp_path / "new.toml"
    new.write_text(text, encoding="utf-8")
    assert main(["relief", str(new)]) == 0
    out_new = capsys.readouterr()
    assert main(["relief", str(old)]) == 0
    out_old = capsys.readouterr()
    assert out_old.out == out_new.out  # the same table
    lines = out_old.err.splitlines()
    warned = [line for line in lines if line.startswith("gear-dyn: warning: ")]
    assert len(warned) == 1, out_old.err
    assert "old.toml: tip_relief.rule = 'seed001'" in warned[0] and "'wang2024'" in warned[0]
