"""The layout's promises: importing gear_dyn is cheap and side-effect free; no caller tests a
concrete model class; the layers hold (import-linter, when installed)."""

from __future__ import annotations

import ast
import json
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "gear_dyn"

PROBE = """
import json, os, sys
before = dict(os.environ)
import gear_dyn
heavy = sorted(m for m in ("matplotlib", "pint", "scipy", "scipy.integrate", "numpy")
               if m in sys.modules)
changed = sorted(k for k in set(before) | set(os.environ) if before.get(k) != os.environ.get(k))
print(json.dumps({"heavy": heavy, "changed": changed, "names": gear_dyn.__all__}))
"""


def test_import_gear_dyn_loads_nothing_heavy_and_changes_no_environment() -> None:
    out = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True,
                         check=True, timeout=120)
    got = json.loads(out.stdout)
    assert got["heavy"] == [] and got["changed"] == []
    # every public name still resolves (lazily)
    names = got["names"]
    check = f"import gear_dyn; print(all(getattr(gear_dyn, n) is not None for n in {names!r}))"
    ok = subprocess.run([sys.executable, "-c", check], capture_output=True, text=True,
                        check=True, timeout=120)
    assert ok.stdout.strip() == "True"


def test_public_api_names_unchanged() -> None:
    import gear_dyn

    assert set(gear_dyn.__all__) == {
        "FourierStiffness", "GearDynError", "build_stiffness", "GearPair", "InputError",
        "PeriodicStiffness", "PiecewiseStiffness", "Result", "SDOFModel", "SceneError",
        "SolverError",
        "SolverSettings", "iso6336_stiffness", "load_scene", "mesh_frequency", "output_speed",
        "parse_scene", "rectangular_stiffness", "run_scene", "sdof_from_pair", "simulate",
        "summarize", "sweep_scene", "SweepOptions", "SweepResult", "compare_scenes",
        "Comparison",
        "Branch", "ContinuationSettings", "continue_orbits", "sdof_family",
        "BifurcationDiagram", "DiagramOptions", "bifurcation_diagram", "Motion",
        "classify_motion",
        "FoldMap", "SpeedTorqueFamily", "fold_map",
    }
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        gear_dyn.nope  # noqa: B018


def _concrete_model_checks() -> list[str]:
    """``isinstance(x, SDOFModel | TorsionalModel | ...)`` anywhere outside models/."""
    found = []
    concrete = {"SDOFModel", "TorsionalModel", "ReliefSDOFModel", "ContactSDOFModel"}
    for path in PACKAGE.rglob("*.py"):
        if path.parent.name == "models":
            continue
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
                    and node.func.id == "isinstance" and len(node.args) == 2):
                names = {n.id for n in ast.walk(node.args[1]) if isinstance(n, ast.Name)}
                if names & concrete:
                    found.append(f"{path.relative_to(ROOT)}:{node.lineno}")
    return found


def test_no_caller_tests_a_concrete_model_class() -> None:
    assert _concrete_model_checks() == []


def test_every_model_offers_the_whole_protocol(heli_pair) -> None:  # type: ignore[no-untyped-def]
    from gear_dyn.models.base import Model
    from gear_dyn.scene import build_model, load_scene

    for scene in sorted((PACKAGE / "scenes").glob("*.toml")):
        model = build_model(load_scene(scene))
        assert isinstance(model, Model), scene.name
        t = np.array([0.0])
        assert tuple(model.outputs(t, model.initial_state()[:, None])) == model.output_names


def test_layers_contract() -> None:
    """The import-linter contract of pyproject.toml (run by .ci/run as well)."""
    exe = shutil.which("lint-imports")
    if exe is None:
        pytest.skip("import-linter is not installed (pip install import-linter); "
                    ".ci/run installs it and checks the contract")
    p = subprocess.run([exe], capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert p.returncode == 0, p.stdout[-3000:]


def import_cycles(graph: Any, package: str) -> list[list[str]]:
    """Every import cycle among the modules of ``package`` in a grimp graph: one chain
    ``[a, b, ..., a]`` per strongly connected component (Tarjan's algorithm, iterative)."""
    modules = sorted(m for m in graph.modules if m == package or m.startswith(package + "."))
    inside = set(modules)
    edges = {m: sorted(graph.find_modules_directly_imported_by(m) & inside) for m in modules}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    components: list[list[str]] = []
    for root in modules:
        if root in index:
            continue
        work = [(root, 0)]
        while work:
            node, i = work.pop()
            if i == 0:
                index[node] = low[node] = len(index)
                stack.append(node)
                on_stack.add(node)
            if i < len(edges[node]):
                work.append((node, i + 1))
                nxt = edges[node][i]
                if nxt not in index:
                    work.append((nxt, 0))
                elif nxt in on_stack:
                    low[node] = min(low[node], index[nxt])
                continue
            if low[node] == index[node]:
                comp = []
                while True:
                    m = stack.pop()
                    on_stack.discard(m)
                    comp.append(m)
                    if m == node:
                        break
                if len(comp) > 1 or node in edges[node]:
                    components.append(sorted(comp))
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[node])
    cycles = []
    for comp in components:
        a = comp[0]
        if a in edges[a]:  # imports itself
            cycles.append([a, a])
            continue
        b = next(m for m in edges[a] if m in comp)
        cycles.append([a, *graph.find_shortest_chain(importer=b, imported=a)])
    return cycles


def _chain_text(graph: Any, chain: list[str]) -> str:
    """``a -> b (line 12) -> ...``: each import with the line numbers where it is written."""
    parts = [chain[0]]
    for importer, imported in zip(chain[:-1], chain[1:], strict=True):
        lines = sorted({d["line_number"] for d in
                        graph.get_import_details(importer=importer, imported=imported)})
        parts.append(f"{imported} (line {', '.join(map(str, lines))} of {importer})")
    return " -> ".join(parts)


def test_import_cycle_finder_names_the_chain() -> None:
    """The cycle finder on a made-up graph: one cycle of three, one of two, a self-import, and
    modules outside the package that close no cycle of it."""
    grimp = pytest.importorskip("grimp", reason="grimp comes with import-linter (the test "
                                "extra); without it the cycle check cannot run")
    graph = grimp.ImportGraph()
    for importer, imported in [("p.a", "p.b"), ("p.b", "p.c"), ("p.c", "p.a"), ("p.c", "p.d"),
                               ("p.e", "p.f"), ("p.f", "p.e"), ("p.g", "p.g"),
                               ("p.d", "q.x"), ("q.x", "p.d")]:
        graph.add_import(importer=importer, imported=imported)
    cycles = import_cycles(graph, "p")
    assert sorted(cycles) == [["p.a", "p.b", "p.c", "p.a"], ["p.e", "p.f", "p.e"],
                              ["p.g", "p.g"]]


def test_gear_dyn_has_no_import_cycle() -> None:
    """No module of gear_dyn imports itself back through any chain, counting every import
    statement: at module level, inside functions and under ``if TYPE_CHECKING``."""
    grimp = pytest.importorskip("grimp", reason="grimp comes with import-linter (the test "
                                "extra); without it the cycle check cannot run")
    graph = grimp.build_graph("gear_dyn", exclude_type_checking_imports=False, cache_dir=None)
    cycles = import_cycles(graph, "gear_dyn")
    assert not cycles, "import cycles:\n" + "\n".join(_chain_text(graph, c) for c in cycles)
