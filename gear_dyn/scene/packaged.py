"""The example scenes shipped inside the package (gear_dyn/scenes/*.toml)."""

from __future__ import annotations

from pathlib import Path

#: folder of the packaged scenes
SCENES_DIR = Path(__file__).resolve().parent.parent / "scenes"


def scene_path(name: str) -> Path:
    """Path of a scene shipped with the package (gear_dyn/scenes/NAME.toml)."""
    return SCENES_DIR / f"{name}.toml"
