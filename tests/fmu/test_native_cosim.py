"""`gear-dyn cosim` and `gear-dyn fmu check` on native FMUs (issue 23).

The verdict of cosim: at every communication step the DTE difference from solve_ivp stays
within the FMU's stated error (its modelDescription: 1e-9 of W/k_m for the exact single-DOF
FMU, 1e-6 for the torsional one) plus gear_dyn's estimate of the reference's own error. The
reference is the scene the FMU was built from (``resources/gear_dyn_native.json``), or a SCENE
given on the command line, which a native FMU does not take (its tables are fixed at build):
a scene with another damping ratio must fail, and pass again once the FMU's own damping
parameter is set to it. The reference (DOP853 at rtol 1e-12) has an estimated error below the
FMU's on every packaged scene, FMI 3 FMUs too, so that a PASS confirms the FMU's error.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from gear_dyn.cli.app import main
from gear_dyn.scene import build_plan, load_scene
from gear_dyn.scene.packaged import resolve_scene

pytestmark = [pytest.mark.fmu,
              pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc) on PATH")]
pytest.importorskip("fmpy")

SCENES = ("helicopter_tail", "eccentric_helical_ideal")
#: stated DTE errors of the two FMUs, of W/k_m (docs/native_fmu.md)
STATED = {"helicopter_tail": 1e-9, "eccentric_helical_ideal": 1e-6}


@pytest.fixture(scope="module")
def fmus(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """The native FMI 2 FMUs of the exact single-DOF scene and the error-free torsional one."""
    from gear_dyn.fmu.export_fmu import build_native_fmu

    d = tmp_path_factory.mktemp("native_cosim")
    return {name: build_native_fmu(name, d / f"{name}.fmu").path for name in SCENES}


def _cosim(fmu: Path, out: Path, *extra: str) -> tuple[int, dict]:
    """cosim over 6 mesh periods at two communication steps (16 and 8 per period)."""
    f_m = build_plan(load_scene(resolve_scene(fmu.stem))).model.mesh_frequency
    h = 1 / (16 * f_m)
    code = main(["cosim", str(fmu), *extra, "--out", str(out), "--periods", "6",
                 "--step", repr(h), "--step", repr(2 * h), "--quiet"])
    return code, json.loads((out / "summary.json").read_text())


@pytest.mark.parametrize("name", SCENES)
def test_cosim_of_a_native_fmu_passes(fmus: dict[str, Path], name: str,
                                      tmp_path: Path) -> None:
    """Against the scene stored in the FMU: PASS; the FMU's share of the bound is its stated
    error times the static deflection, and the reference's share is gear_dyn's estimate."""
    from gear_dyn.fmu.fmu_info import read_fmu

    info = read_fmu(fmus[name])
    assert info.backend == "native" and info.stated_error == STATED[name]
    assert info.spec["scene_name"] == name and "damping.ratio" in info.settable
    code, s = _cosim(fmus[name], tmp_path / "c")
    assert code == 0, s
    assert s["verdict"] == "PASS" and s["backend"] == "native"
    model = build_plan(load_scene(resolve_scene(name))).model
    x_s = model.static_load / model.mean_stiffness
    b = s["bounds"]
    assert b["fmu_m"] == pytest.approx(STATED[name] * x_s, rel=1e-12)
    assert 0 < b["reference_m"] < 1e-5 * x_s
    assert [st["n_steps"] for st in s["steps"]] == [48, 96]
    for st in s["steps"]:
        assert st["max_diff"]["dte"] <= b["allowed_dte_diff_m"]
    for f in ("overlay.png", "convergence.png", "steps.csv", "timeseries.csv"):
        assert (tmp_path / "c" / f).is_file(), f


def test_cosim_of_a_native_fmu_against_another_scene_fails(
        fmus: dict[str, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A scene with damping ratio 0.1 instead of 0.06: the FMU runs as built, so the DTE
    differs by far more than the allowed error (exit 3, verdict FAIL); with the FMU's
    damping.ratio set to 0.1 the same comparison passes."""
    text = resolve_scene("helicopter_tail").read_text()
    assert "ratio = 0.06" in text
    scene = tmp_path / "helicopter_tail_zeta.toml"
    scene.write_text(text.replace("ratio = 0.06", "ratio = 0.1"))
    fmu = fmus["helicopter_tail"]
    code, s = _cosim(fmu, tmp_path / "wrong", str(scene))
    assert code == 3 and s["verdict"] == "FAIL"
    assert "verdict: FAIL" in capsys.readouterr().out
    allowed = s["bounds"]["allowed_dte_diff_m"]
    assert all(st["max_diff"]["dte"] > 1e3 * allowed for st in s["steps"])
    code, s = _cosim(fmu, tmp_path / "set", str(scene), "--set", "damping.ratio=0.1")
    assert code == 0 and s["verdict"] == "PASS", s


def test_cosim_refuses_a_name_the_native_fmu_lacks(
        fmus: dict[str, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """--set of a pythonfmu parameter that the native FMU does not have: exit 2, one line
    naming it and the FMU's parameters."""
    assert main(["cosim", str(fmus["helicopter_tail"]), "--out", str(tmp_path / "o"),
                 "--set", "solver.method=DOP853"]) == 2
    err = capsys.readouterr().err
    assert "solver.method" in err and "damping.ratio" in err


def test_fmu_check_passes_on_the_native_torsional_fmu(fmus: dict[str, Path],
                                                      capsys: pytest.CaptureFixture[str]) -> None:
    """`gear-dyn fmu check` on the native torsional FMU: every check runs and passes, and the C
    host line says no libpython was loaded."""
    code = main(["fmu", "check", str(fmus["eccentric_helical_ideal"]), "--steps", "32"])
    out = capsys.readouterr().out
    assert code == 0, out
    for name in ("validation", "fmpy run", "stop-time independence", "C host"):
        assert name in out
    assert "SKIP" not in out and "FAIL" not in out and "verdict: PASS" in out
    assert "no libpython in the process" in out


@pytest.mark.parametrize("name", [
    *(p.stem for p in sorted(resolve_scene("helicopter_tail").parent.glob("*.toml"))
      if p.stem != "eccentric_helical"),
    pytest.param("eccentric_helical", marks=pytest.mark.slow)])  # a 15 s build
def test_cosim_reference_error_is_below_the_fmus(name: str, tmp_path: Path) -> None:
    """The FMI 3 native FMU of every packaged scene against the DOP853 reference at rtol
    1e-12 over 4 mesh periods: PASS, and the reference's estimated error lies below the FMU's
    stated one (``conclusive``), so the PASS confirms the FMU's error."""
    from gear_dyn.fmu.cosim import compare
    from gear_dyn.fmu.export_fmu import build_native_fmu

    fmu = build_native_fmu(name, tmp_path / f"{name}.fmu", fmi=3).path
    f_m = build_plan(load_scene(resolve_scene(name))).model.mesh_frequency
    report = compare(fmu, stop_time=4 / f_m)
    assert (report.reference_method, report.rtol) == ("DOP853", 1e-12)
    assert report.bounds is not None and report.bounds.conclusive, report.bounds
    assert report.passed, [s.max_diff["dte"] for s in report.steps]
    assert report.bounds.reference_basis.startswith(
        f"{report.bounds.reference / report.bounds.scale:.2g} W/k_m, solve_ivp DOP853")
