"""``gear-dyn scenes``, ``gear-dyn init FILE`` and ``gear-dyn scene keys [TABLE]``: finding,
starting and looking up scenes."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from gear_dyn.errors import InputError


def register(sub: Any) -> None:
    p = sub.add_parser(
        "scenes", help="list the packaged example scenes (run them by name from any folder)",
        description="List the scenes shipped with gear_dyn, one line each. Run one by name "
        "from any folder: gear-dyn run helicopter_tail --out out; in Python: "
        "gd.load_scene('helicopter_tail').",
    )
    p.set_defaults(func=run_scenes)
    p = sub.add_parser(
        "init", help="write a commented starter scene (with units) that loads and runs",
        description="Write a commented starter scene to FILE: a spur pair with every value in "
        "its unit, ready for gear-dyn run FILE --out DIR.",
    )
    p.add_argument("file", type=Path, nargs="?", default=Path("my_pair.toml"),
                   help="scene file to write (default my_pair.toml)")
    p.add_argument("--force", action="store_true", help="overwrite FILE if it exists")
    p.set_defaults(func=run_init)
    p = sub.add_parser(
        "scene", help="scene reference: gear-dyn scene keys [TABLE]",
        description="Look up the scene format (the same text as docs/scenes.md).",
    )
    keys_sub = p.add_subparsers(dest="scene_command", metavar="SUBCOMMAND",
                                parser_class=type(p))
    keys_sub.required = True
    k = keys_sub.add_parser(
        "keys", help="every table and key: type, unit, default, range, models",
        description="Print the scene reference: for each key its type, unit, default, valid "
        "range and the models that use it (all tables, or only TABLE).",
    )
    k.add_argument("table", nargs="?", default=None, help="one table, e.g. operating")
    k.set_defaults(func=run_keys)


def run_scenes(args: argparse.Namespace) -> int:
    from gear_dyn.scene.packaged import packaged_scenes

    rows = packaged_scenes()
    width = max(len(name) for name, _ in rows)
    for name, description in rows:
        print(f"{name:<{width}}  {description}")
    return 0


def run_init(args: argparse.Namespace) -> int:
    from gear_dyn.scene.packaged import STARTER_SCENE

    path: Path = args.file
    if path.suffix != ".toml":
        raise InputError(f"{path}: a scene file ends in .toml (e.g. my_pair.toml)")
    if path.exists() and not args.force:
        raise InputError(f"{path}: exists; choose another name or add --force to overwrite")
    try:
        path.write_text(STARTER_SCENE.format(name=path, stem=path.stem), encoding="utf-8")
    except OSError as exc:
        raise InputError(f"{path}: cannot write ({exc.strerror})") from None
    print(f"wrote {path}; run it: gear-dyn run {path} --out out")
    return 0


def run_keys(args: argparse.Namespace) -> int:
    from gear_dyn.scene.reference import scene_reference

    print(scene_reference(args.table), end="")
    return 0
