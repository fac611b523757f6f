"""Scene-file helpers shared by the scene, CLI and FMU tests: the example scenes (also edited),
a TOML writer, and every single-key mutation of a scene (see tests/scene/test_scene_mutation.py)."""


from __future__ import annotations

import copy
import math
import re
import tomllib
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from gear_dyn.scene import load_scene, parse_scene

ROOT = Path(__file__).resolve().parents[1]
SCENES_DIR = ROOT / "examples" / "scenes"

#: every documented outcome of a CLI run: ok, user error, solver failure
DOCUMENTED_EXIT_CODES = (0, 2, 3)


def example_scenes() -> list[Path]:
    """Every scene shipped in examples/scenes (picked up automatically)."""
    return sorted(SCENES_DIR.glob("*.toml"))


def edited_scene(name: str, **changes: dict[str, Any] | None) -> Any:
    """The example scene ``name`` parsed again from its SI tables, with the keys of each
    ``changes`` table set in the scene's table of that name (None: the table dropped)."""
    scene = load_scene(SCENES_DIR / f"{name}.toml")
    tables = {k: {kk: vv for kk, vv in v.items() if vv is not None}
              for k, v in scene.tables.items()}
    for table, keys in changes.items():
        if keys is None:
            tables.pop(table)
        else:
            tables.setdefault(table, {}).update(keys)
    return parse_scene(tables, si=True)


def _toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_key(k)} = {_toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def _key(k: str) -> str:
    return k if re.fullmatch(r"[A-Za-z0-9_-]+", k) else _toml_value(k)


def dump_toml(data: dict[str, Any]) -> str:
    """TOML text of a scene dict: top-level scalars first, then one [table] per dict value."""
    lines = [f"{_key(k)} = {_toml_value(v)}" for k, v in data.items() if not isinstance(v, dict)]
    for name, table in data.items():
        if isinstance(table, dict):
            lines.append(f"\n[{_key(name)}]")
            lines.extend(f"{_key(k)} = {_toml_value(v)}" for k, v in table.items())
    return "\n".join(lines) + "\n"


def load(path: Path) -> dict[str, Any]:
    with path.open("rb") as fh:
        return tomllib.load(fh)


def _split_unit(s: str) -> tuple[str, str]:
    m = re.fullmatch(r"\s*([-+]?[0-9.]+(?:[eE][-+]?[0-9]+)?)\s*(.*)", s)
    if m is None:
        return "", s
    return m.group(1), m.group(2)


#: the mutations the issue names: delete, negate, NaN, a string, a wrong unit, huge
CORE_MUTATIONS = ("delete", "negate", "nan", "string", "wrong_unit", "huge")


def core_mutations(value: Any) -> Iterator[tuple[str, Any]]:
    """The six named mutations of one value (the ones that do not apply to it are skipped)."""
    for label, new in mutations(value):
        if label in CORE_MUTATIONS:
            yield label, new


def mutations(value: Any) -> Iterator[tuple[str, Any]]:
    """(label, new value) pairs for one key; the value None means "delete the key"."""
    yield "delete", None
    if isinstance(value, bool):
        yield "flip", not value
        yield "number", 1.5
    elif isinstance(value, int | float):
        yield "negate", -value
        yield "zero", 0
        yield "nan", math.nan
        yield "inf", math.inf
        yield "string", "lots"
        yield "wrong_unit", f"{abs(value) or 1} kg*s"
        yield "huge", 10**18 if isinstance(value, int) else 1e300
        yield "tiny", 1e-300
        yield "bool", True
    elif isinstance(value, str):
        num, unit = _split_unit(value)
        if num:
            yield "negate", f"-{num.lstrip('+-')} {unit}"
            yield "nan", f"nan {unit}"
            yield "huge", f"1e300 {unit}"
            yield "tiny", f"1e-300 {unit}"
            yield "wrong_unit", f"{num} kg*s"
            yield "no_unit", num
            yield "bad_unit", f"{num} furlongs per fortnight^2"
        else:
            yield "typo", value[:-1] if len(value) > 1 else value + "x"
        yield "string", "lots"
        yield "number", 3.0
        yield "list", [value]
    elif isinstance(value, list):
        yield "empty", []
        yield "negate", [(-x if isinstance(x, int | float) and not isinstance(x, bool) else x)
                         for x in value]
        yield "nan", [math.nan for _ in value]
        yield "strings", ["lots" for _ in value]
        yield "scalar", 1.0
        yield "huge", [1e300 for _ in value]
    elif isinstance(value, dict):
        yield "string", "lots"
    else:
        yield "string", "lots"


def mutated_scenes(
    data: dict[str, Any], core: bool = False
) -> Iterator[tuple[str, dict[str, Any]]]:
    """Every (label, scene) with one key of one table mutated, plus table-level mutations.

    ``core`` restricts the key mutations to :data:`CORE_MUTATIONS`.
    """
    mutate = core_mutations if core else mutations
    for table, content in data.items():
        if not isinstance(content, dict):
            for label, new in mutate(content):
                d = copy.deepcopy(data)
                if new is None:
                    del d[table]
                else:
                    d[table] = new
                yield f"{table}:{label}", d
            continue
        d = copy.deepcopy(data)
        del d[table]
        yield f"[{table}]:delete", d
        d = copy.deepcopy(data)
        d[table] = "lots"
        yield f"[{table}]:not_a_table", d
        d = copy.deepcopy(data)
        d[table] = {**content, "unknwn_key": 1.0}
        yield f"[{table}]:unknown_key", d
        for key, value in content.items():
            for label, new in mutate(value):
                d = copy.deepcopy(data)
                if new is None:
                    del d[table][key]
                else:
                    d[table][key] = new
                yield f"{table}.{key}:{label}", d
    d = copy.deepcopy(data)
    d["no_such_table"] = {"x": 1}
    yield "[no_such_table]:added", d


# ---------------------------------------------------------------------------------------------
# the tests: every mutation of every example scene, loaded and built in-process (no solving)

