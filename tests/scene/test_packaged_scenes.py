"""Packaged scenes by name from any folder; ``gear-dyn scenes``; ``gear-dyn init``."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import gear_dyn as gd
from gear_dyn.cli import main
from gear_dyn.errors import SceneError
from gear_dyn.scene.packaged import SCENES_DIR, packaged_names


def test_scene_by_name_from_another_folder(tmp_path: Path,
                                           monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    by_name = gd.load_scene("helicopter_tail")
    by_path = gd.load_scene(SCENES_DIR / "helicopter_tail.toml")
    assert by_name.tables == by_path.tables
    assert gd.load_scene("helicopter_tail.toml").tables == by_path.tables
    # a file of that name in the current folder wins over the packaged scene
    (tmp_path / "helicopter_tail.toml").write_text(
        (SCENES_DIR / "helicopter_tail.toml").read_text().replace('"3319 rpm"', '"1000 rpm"'))
    assert gd.load_scene("helicopter_tail.toml").tables["operating"]["speed"] == pytest.approx(
        1000 * 3.141592653589793 / 30)


def test_unknown_name_lists_the_packaged_scenes(tmp_path: Path,
                                                monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SceneError, match=r"did you mean 'helicopter_tail'\?.*packaged scenes: "
                                         r"backlash_constant_stiffness, eccentric_helical"):
        gd.load_scene("helicoptr_tail")


def test_cli_runs_a_packaged_scene_by_name(tmp_path: Path,
                                           monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(["run", "helicopter_tail", "--out", "o", "--periods", "20"]) == 0
    assert json.loads(Path("o/summary.json").read_text())["mesh_frequency_hz"] == pytest.approx(
        3319 / 60 * 23, rel=1e-12)


def test_scenes_lists_every_packaged_scene(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["scenes"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [line.split()[0] for line in lines] == packaged_names()
    assert len(lines) == len(list(SCENES_DIR.glob("*.toml"))) >= 5
    assert all(len(line.split(None, 1)) == 2 for line in lines)  # each has a description


def test_init_writes_a_starter_scene_that_runs(tmp_path: Path,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "my_pair.toml"
    assert main(["init", str(path)]) == 0
    text = path.read_text()
    assert text.count("#") > 10 and '"1500 rpm"' in text and '"120 Nm"' in text
    scene = gd.load_scene(path)
    assert scene.tables["operating"]["torque"] == pytest.approx(120.0)
    assert main(["run", str(path), "--out", str(tmp_path / "o"), "--periods", "20"]) == 0
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert summary["mesh_frequency_hz"] == pytest.approx(1500 / 60 * 20, rel=1e-12)
    capsys.readouterr()
    assert main(["init", str(path)]) == 2  # never overwrites silently
    assert "--force" in capsys.readouterr().err
    assert main(["init", str(path), "--force"]) == 0
