"""Choices named after their paper: the tip-relief rule ``wang2024`` (Wang et al. 2024) and the
Weber modulus ``jiang2018`` (Jiang et al. 2018, eq. 11). Their old names ``seed001`` and ``seed``
still work in the API, in a scene and on the command line, with a FutureWarning that says what
to write."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from gear_dyn.cli import main
from gear_dyn.geometry import GearPair
from gear_dyn.modification.relief import RULES, recommended_relief
from gear_dyn.scene import build_pair, parse_scene, scene_stiffness
from gear_dyn.scene.modification import relief_from_scene
from gear_dyn.scene.packaged import SCENES_DIR
from gear_dyn.stiffness import build_stiffness
from gear_dyn.stiffness.weber import MODULI, weber_pair_stiffness

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


OLD_MODULUS = r"'seed' is the old name of the modulus 'jiang2018' \(Jiang et al. 2018, eq. 11\)"


def test_old_weber_modulus_in_the_api_warns_and_gives_the_same_stiffness() -> None:
    assert "jiang2018" in MODULI and "seed" not in MODULI
    s = PAIR.start_of_contact + 0.3 * PAIR.path_of_contact
    new = weber_pair_stiffness(PAIR, s, modulus="jiang2018")
    with pytest.warns(FutureWarning, match=OLD_MODULUS) as record:
        old = weber_pair_stiffness(PAIR, s, modulus="seed")
    assert record[0].filename == __file__
    assert old == new and new > 0
    # the default is that modulus: the same number, and unlike the plane-stress one
    assert weber_pair_stiffness(PAIR, s) == new
    assert weber_pair_stiffness(PAIR, s, modulus="plane_stress") < new
    with pytest.warns(FutureWarning, match="weber_modulus = " + OLD_MODULUS):
        k_old = build_stiffness(PAIR, "weber", weber_modulus="seed")
    assert k_old.mean == build_stiffness(PAIR, "weber").mean


def test_old_weber_modulus_in_a_scene_warns_with_the_key_path() -> None:
    table = {"method": "weber", "samples_per_cycle": 40}
    new = parse_scene({**SCENE, "stiffness": {**table, "weber_modulus": "jiang2018"}}, "n.toml")
    with pytest.warns(FutureWarning, match=r"o\.toml: stiffness\.weber_modulus = " + OLD_MODULUS):
        old = parse_scene({**SCENE, "stiffness": {**table, "weber_modulus": "seed"}}, "o.toml")
    assert old.tables["stiffness"] == new.tables["stiffness"]
    assert (scene_stiffness(old, build_pair(old)).mean
            == scene_stiffness(new, build_pair(new)).mean)
