"""The docs site covers the public API, and the README's commands and example work.

The API reference (docs/api/) is generated from the docstrings when the docs are built
(``python -m sphinx -n -W --keep-going -b html docs docs/_build/html``); these tests check its
sources, so a new public name without a line in the reference fails here, without a docs build.
Where the docs were built, the built inventory (objects.inv) is checked too.
"""

from __future__ import annotations

import importlib
import re
import zlib
from pathlib import Path
from typing import Any

import pytest

import gear_dyn

ROOT = Path(__file__).resolve().parents[1]
API = ROOT / "docs" / "api"
README = ROOT / "README.md"
INVENTORY = ROOT / "docs" / "_build" / "html" / "objects.inv"

#: the subpackages users import, and the ground modules, each with a page of the reference
PACKAGES = ("scene", "analysis", "solvers", "models", "stiffness", "modification", "eccentricity",
            "plots", "fmu", "geometry", "excitation", "units", "io", "errors")


def _canonical(name: str) -> str:
    """The documented location of a ``gd`` name: the module that defines it."""
    return f"{gear_dyn._EXPORTS[name]}.{name}"


def test_every_public_name_is_in_the_api_reference() -> None:
    """Each name of gear_dyn.__all__ is listed in docs/api/gd.rst at the module that defines it
    (the autosummary entry ``~module.name`` links to its documentation there)."""
    listed = set(re.findall(r"^\s+~?([\w.]+)\s*$", (API / "gd.rst").read_text(), re.M))
    missing = [name for name in gear_dyn.__all__ if _canonical(name) not in listed]
    assert not missing, f"add to docs/api/gd.rst: {[_canonical(n) for n in missing]}"
    stale = {entry for entry in listed if entry.startswith("gear_dyn.")} - {
        _canonical(name) for name in gear_dyn.__all__}
    assert not stale, f"docs/api/gd.rst lists names gear_dyn no longer exports: {sorted(stale)}"


def test_every_subpackage_has_a_page() -> None:
    listed = set(re.findall(r"^\s+(gear_dyn\.\w+)\s*$", (API / "index.rst").read_text(), re.M))
    assert {f"gear_dyn.{p}" for p in PACKAGES} <= listed


def _inventory() -> set[str]:
    """Object names in a Sphinx objects.inv (version 2: four header lines, then zlib)."""
    data = INVENTORY.read_bytes()
    body = data.split(b"\n", 4)[4]
    return {line.split(" ", 1)[0] for line in zlib.decompress(body).decode().splitlines()}


def test_built_reference_documents_every_public_name() -> None:
    if not INVENTORY.exists():
        pytest.skip("docs not built here (python -m sphinx -n -W --keep-going -b html docs "
                    "docs/_build/html): the sources are checked above")
    names = _inventory()
    missing = [_canonical(n) for n in gear_dyn.__all__ if _canonical(n) not in names]
    assert not missing, f"documented nowhere in the built docs: {missing}"
    # a subpackage's exports: on its page, or (constants) where its modules define them
    undocumented = []
    for package in PACKAGES:
        module = importlib.import_module(f"gear_dyn.{package}")
        for name in getattr(module, "__all__", ()):
            prefix, suffix = f"gear_dyn.{package}.", f".{name}"
            if not any(n.startswith(prefix) and n.endswith(suffix) for n in names):
                undocumented.append(f"gear_dyn.{package}.{name}")
    assert not undocumented, f"no documentation in the built docs: {undocumented}"


def _readme() -> str:
    return README.read_text(encoding="utf-8")


def test_readme_fits_one_screen_and_its_links_resolve() -> None:
    text = _readme()
    assert len(text.splitlines()) <= 150
    for target in re.findall(r"\]\(([^)#]+)\)", text):
        if "://" not in target:
            assert (ROOT / target).exists(), target


def test_quick_start_commands_and_ci() -> None:
    """The README's two quick-start commands use separate virtual environments, and .ci/run
    runs the test command exactly as the README gives it."""
    start = _readme().split("## Quick start", 1)[1].split("\n## ", 1)[0]
    commands = [ln for ln in re.findall(r"```bash\n(.*?)```", start, re.S)[0].splitlines()
                if ln.strip() and not ln.startswith("#")]
    assert len(commands) == 2, commands
    demo, tests = commands
    venvs = [re.findall(r"python3 -m venv (\S+)", c) for c in commands]
    assert len(venvs[0]) == len(venvs[1]) == 1 and venvs[0] != venvs[1], venvs
    assert "gear-dyn demo" in demo and "python -m pytest" in tests
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8").splitlines()
    assert tests in ci


def test_readme_python_example_runs(monkeypatch: pytest.MonkeyPatch) -> None:
    """The README's API example runs as written; the peak force it prints is the
    potential-energy pair's (the unmodified row of the tip-relief figures, 1.415 W), and the
    dynamic factor is that over the pair's quasi-static peak."""
    monkeypatch.setenv("MPLBACKEND", "Agg")
    code = re.findall(r"```python\n(.*?)```", _readme(), re.S)[0]
    assert len([ln for ln in code.splitlines() if ln.strip()]) <= 10
    namespace: dict[str, object] = {}
    exec(compile(code, "README.md", "exec"), namespace)  # noqa: S102
    model: Any = namespace["model"]
    first = gear_dyn.simulate(model, t_end=200 / model.mesh_frequency)
    assert first.peak_force_ratio == pytest.approx(1.415, abs=5e-4)
    assert first.dynamic_factor * first.extra["stiffness_jump_factor"] == pytest.approx(
        first.peak_force_ratio, rel=1e-12)
    assert type(namespace["fig"]).__name__ == "Figure"
