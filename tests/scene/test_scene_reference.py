"""docs/scenes.md is generated from the scene schema and kept in sync; the CLI prints the same."""

from __future__ import annotations

from pathlib import Path

import pytest

from gear_dyn.cli import main
from gear_dyn.scene import SECTIONS
from gear_dyn.scene.reference import scene_reference

DOC = Path(__file__).resolve().parents[2] / "docs" / "scenes.md"


def test_docs_scenes_md_is_in_sync() -> None:
    assert DOC.read_text() == scene_reference(), (
        "docs/scenes.md is out of date: python -m gear_dyn.scene.reference > docs/scenes.md")


def test_every_table_and_key_is_documented() -> None:
    text = scene_reference()
    for name, sec in SECTIONS.items():
        assert f"## [{name}]" in text
        part = scene_reference(name)
        for f in sec.fields:
            assert f"| `{f.name}` |" in part


def test_cli_scene_keys_prints_the_reference(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["scene", "keys"]) == 0
    assert capsys.readouterr().out == scene_reference()
    assert main(["scene", "keys", "tip_relief"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("## [tip_relief]") and "models: sdof" in out
    assert main(["scene", "keys", "nope"]) == 2
    assert "unknown table" in capsys.readouterr().err
