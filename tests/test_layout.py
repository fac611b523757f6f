"""The layout's promises: importing gear_dyn is cheap and side-effect free; no caller tests a
concrete model class; the layers hold (import-linter, when installed)."""

from __future__ import annotations

import ast
import json
import shutil
import subprocess
import sys
from pathlib import Path

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
        "summarize",
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
