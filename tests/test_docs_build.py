"""The docs build is nitpicky and hides nothing: every cross-reference must resolve.

The build command (``-n``: every reference resolves; ``-W``: a warning is an error) is the same
in CI, on the development page and in the README, and docs/conf.py suppresses no warning type;
the only references let through unresolved are names of other packages (no network for their
intersphinx inventories), never a name of gear_dyn. These checks read the sources and need no
docs build.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BUILD = re.compile(r"python -m sphinx( -\S+)* -b html docs docs/_build/html")


def _conf() -> dict[str, ast.expr]:
    tree = ast.parse((ROOT / "docs" / "conf.py").read_text(encoding="utf-8"))
    return {t.id: node.value for node in tree.body if isinstance(node, ast.Assign | ast.AnnAssign)
            for t in (node.targets if isinstance(node, ast.Assign) else [node.target])
            if isinstance(t, ast.Name) and node.value is not None}


def test_build_command_is_nitpicky_everywhere() -> None:
    commands = {}
    for name in (".ci/run", "docs/development.md", "README.md", "docs/conf.py"):
        found = {m.group(0) for m in BUILD.finditer((ROOT / name).read_text(encoding="utf-8"))}
        assert len(found) == 1, (name, found)
        commands[name] = found.pop()
    assert len(set(commands.values())) == 1, commands
    flags = set(next(iter(commands.values())).split())
    assert {"-n", "-W", "--keep-going"} <= flags, flags


def test_conf_suppresses_no_warning_type() -> None:
    conf = _conf()
    assert "suppress_warnings" not in conf
    assert "nitpick_ignore_regex" not in conf
    assert conf.get("nitpicky") is None or ast.literal_eval(conf["nitpicky"]) is True


def test_nitpick_ignore_names_only_other_packages() -> None:
    entries = ast.literal_eval(_conf()["nitpick_ignore"])
    assert entries, "nitpick_ignore is expected to hold the external names"
    for role, target in entries:
        assert role.startswith("py:"), (role, target)
        assert re.fullmatch(r"[A-Za-z_][\w.]*", target), target   # one exact dotted name
        assert target.split(".")[0] != "gear_dyn", f"a gear_dyn name left unresolved: {target}"
