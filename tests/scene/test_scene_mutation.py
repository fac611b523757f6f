"""Mutating every key of every example scene: the loader and model builders end in a result or
a documented error (InputError / SolverError), never another exception.

Also the helpers shared with test_cli_errors.py: a tiny TOML writer and the mutations.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest
from scene_cases import (
    dump_toml,
    example_scenes,
    load,
    mutated_scenes,
)

from gear_dyn.errors import InputError, SceneError, SolverError
from gear_dyn.scene import build_plan, parse_scene


def test_every_example_scene_is_found_and_valid() -> None:
    """The mutation tests below cover what examples/scenes holds; the originals are valid."""
    scenes = example_scenes()
    assert len(scenes) >= 2
    for path in scenes:
        plan = build_plan(parse_scene(load(path), path.name))
        assert plan.t_end > 0


def test_toml_writer_round_trips() -> None:
    """dump_toml is the inverse of tomllib for every example scene (NaN aside)."""
    for path in example_scenes():
        data = load(path)
        assert tomllib.loads(dump_toml(data)) == data


@pytest.mark.parametrize("path", example_scenes(), ids=lambda p: p.stem)
def test_every_mutation_loads_and_builds_or_raises_a_documented_error(path: Path) -> None:
    """Each key deleted, negated, zeroed, NaN, inf, a string, a wrong or unknown unit, huge,
    tiny, a boolean, a list: parse_scene + build_plan give a plan or an InputError/SolverError
    (SceneError from parsing, naming the file), never another exception type."""
    data = load(path)
    bad: list[str] = []
    n = 0
    for label, scene in mutated_scenes(data):
        n += 1
        try:
            plan = build_plan(parse_scene(scene, path.name))
        except SceneError as exc:
            if path.name not in str(exc):
                bad.append(f"{label}: SceneError without the file name: {exc}")
            continue
        except (InputError, SolverError):
            continue
        except Exception as exc:  # noqa: BLE001 - the point of the test
            bad.append(f"{label}: {type(exc).__name__}: {exc}")
            continue
        if not (plan.t_end > 0 and plan.model.mesh_frequency > 0):
            bad.append(f"{label}: nonsense plan t_end={plan.t_end}")
    assert n > 50
    assert not bad, "\n".join(bad)
