"""The docs build is nitpicky and hides nothing: every cross-reference must resolve.

The build command (``-n``: every reference resolves; ``-W``: a warning is an error) is the same
in CI, on the development page and in the README, and docs/conf.py suppresses no warning type;
the only references let through unresolved are names of other packages that have no inventory,
never a name of gear_dyn. The names of Python, NumPy, SciPy and Matplotlib resolve through
intersphinx from the local inventories of docs/_inventories/ (the build reads no network),
written by docs/_ext/external_inventories.py. These checks read the sources and need no docs
build.
"""

from __future__ import annotations

import ast
import io
import posixpath
import re
import sys
from pathlib import Path
from types import ModuleType

from sphinx.util.inventory import InventoryFile

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


def _inventories() -> ModuleType:
    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    try:
        import external_inventories
    finally:
        sys.path.remove(str(ROOT / "docs" / "_ext"))
    return external_inventories


def test_inventories_are_written_from_their_list() -> None:
    """Each shipped inventory is the script's output for its list (rerun the script after an
    edit), and Sphinx's own reader reads back every entry at an https address on the project's
    published docs."""
    inv = _inventories()
    for project, (root, _) in inv.PROJECTS.items():
        data = inv.inventory_path(project).read_bytes()
        assert data == inv.inventory_bytes(project), f"rerun external_inventories.py ({project})"
        read = InventoryFile.load(io.BytesIO(data), root, posixpath.join)
        names = {(role, name) for role, items in read.items() for name in items}
        assert names == {(role, name) for name, role, _, _ in inv.ENTRIES[project]}
        for items in read.values():
            for item in items.values():
                uri = getattr(item, "uri", None) or item[2]
                assert uri.startswith(root) and root.startswith("https://") and "#" in uri, uri


def test_intersphinx_reads_only_the_local_inventories() -> None:
    """conf.py maps every project to its published root and its local file, none to a URL
    fetched at build time; and nitpick_ignore holds no name that an inventory resolves."""
    inv = _inventories()
    src = (ROOT / "docs" / "conf.py").read_text(encoding="utf-8")
    assert "intersphinx_mapping = external_inventories.intersphinx_mapping()" in src
    for project, (root, local) in inv.intersphinx_mapping().items():
        assert root == inv.PROJECTS[project][0] and Path(local).is_file(), project
    held = {name for entries in inv.ENTRIES.values() for name, _, _, _ in entries}
    ignored = {target for _, target in ast.literal_eval(_conf()["nitpick_ignore"])}
    assert not ignored & held, ignored & held


def test_every_type_alias_has_its_target() -> None:
    """Each target of numpydoc's type aliases (its defaults and conf.py's own) is in an
    inventory with its role, so any aliased word in a docstring's type links and the nitpicky
    build does not fail on it."""
    from numpydoc.xref import DEFAULT_LINKS

    inv = _inventories()
    held = {(project, role, name) for project, entries in inv.ENTRIES.items()
            for name, role, _, _ in entries}
    roles = {"data": "py:data", "class": "py:class", "func": "py:function", "mod": "py:module",
             "ref": "std:label", "term": "std:term"}
    aliases = {**DEFAULT_LINKS, **ast.literal_eval(_conf()["numpydoc_xref_aliases"])}
    for word, target in aliases.items():
        m = re.fullmatch(r":(\w+):`(?:[^<`]*<)?([^<>`]+?)>?`", target)
        role, name = (roles[m.group(1)], m.group(2)) if m else ("py:*", target)  # bare: :obj:
        project, _, name = name.rpartition(":") if ":" in name else ("", "", name)
        found = {(p, r) for p, r, n in held if n == name}
        assert any((not project or p == project) and (r == role or role == "py:*" and
                   r.startswith("py:")) for p, r in found), (word, target)
