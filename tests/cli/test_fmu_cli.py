"""`gear-dyn fmu build/validate` and `gear-dyn cosim`: files, numbers and exit codes."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from gear_dyn.cli.app import main

pytestmark = pytest.mark.fmu

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"
F_M = 23 * 3319 / 60  # mesh frequency of Jiang et al. (2018), Hz


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("cli") / "heli.fmu"
    # the model name builds the helicopter tail drive of Jiang et al. (2018)
    # the pythonfmu FMU: cosim sets scene keys (solver.method, ...) that are its parameters
    assert main(["fmu", "build", "sdof", "--backend", "python", "--out", str(out)]) == 0
    return out


def test_build_and_validate(built: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert built.is_file()
    assert main(["fmu", "validate", str(built)]) == 0
    assert "no problems" in capsys.readouterr().out


def test_cosim_writes_the_comparison(built: Path, tmp_path: Path) -> None:
    """Two communication steps over 6 mesh periods: the FMU (exact propagation) against the
    reference, solve_ivp DOP853 at rtol 1e-12, within the verdict's bound at both steps (a kept
    state: the step adds no error)."""
    h = 1 / (16 * F_M)
    out = tmp_path / "cosim"
    code = main(["cosim", str(built), "--out", str(out), "--periods", "6",
                 "--step", repr(h), "--step", repr(4 * h)])
    assert code == 0
    for name in ("summary.json", "steps.csv", "timeseries.csv", "overlay.png",
                 "convergence.png"):
        assert (out / name).is_file(), name
    s = json.loads((out / "summary.json").read_text())
    assert (s["reference"], s["rtol"]) == ("solve_ivp DOP853", 1e-12)
    assert [st["n_steps"] for st in s["steps"]] == [24, 96]
    for st in s["steps"]:
        assert st["max_diff"]["dte"] <= s["bounds"]["allowed_dte_diff_m"]
    header = (out / "steps.csv").read_text().splitlines()[0]
    assert header.startswith("step_s,n_steps,fmu_run_time_s")


def test_cosim_with_a_scene_and_set(built: Path, tmp_path: Path) -> None:
    """A scene file's values are set on the FMU (here a heavier load and more damping) and
    --set changes the FMU's solver; the reference follows both (same tolerance as above)."""
    text = (SCENES / "helicopter_tail.toml").read_text()
    text = text.replace('torque = "1474.4 N*m"', 'torque = "2000 N*m"').replace(
        "ratio = 0.06", "ratio = 0.1")
    scene = tmp_path / "heavier.toml"
    scene.write_text(text)
    out = tmp_path / "c2"
    h = 1 / (16 * F_M)
    assert main(["cosim", str(built), str(scene), "--out", str(out), "--periods", "4",
                 "--step", repr(h), "--set", "solver.method=DOP853"]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["fmu_method"] == "DOP853"
    # the FMU's DOP853 at the scene's rtol against the reference's at 1e-12: the verdict's bound
    assert s["steps"][0]["max_diff"]["dte"] <= s["bounds"]["allowed_dte_diff_m"]


@pytest.mark.parametrize("argv, message", [
    (["fmu", "build", "helicopter_tail", "--out", "x.zip"], "must end in .fmu"),
    (["fmu", "build", "no_such_scene", "--out", "x.fmu"], "not a scene file"),
    (["fmu", "validate", "missing.fmu"], "FMU file not found"),
    (["fmu", "check", "missing.fmu"], "FMU file not found"),
    (["cosim", "missing.fmu", "--out", "d"], "FMU file not found"),
])
def test_bad_input_exit_2(argv: list[str], message: str, tmp_path: Path,
                          monkeypatch: pytest.MonkeyPatch,
                          capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    assert message in capsys.readouterr().err


def test_cosim_refuses_scene_parts_the_fmu_lacks(built: Path, tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    text = (SCENES / "helicopter_tail.toml").read_text() + '\n[backlash]\nhalf_gap = "0.1 mm"\n'
    scene = tmp_path / "backlash.toml"
    scene.write_text(text)
    assert main(["cosim", str(built), str(scene), "--out", str(tmp_path / "o")]) == 2
    assert "backlash.half_gap" in capsys.readouterr().err
    h = 1 / (16 * F_M)
    assert main(["cosim", str(built), "--out", str(tmp_path / "o"), "--step", repr(h),
                 "--step", repr(1.5 * h)]) == 2
    assert "integer multiple" in capsys.readouterr().err


def test_check_reports_every_check(built: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """`gear-dyn fmu check`: four report lines and a verdict; the C host line passes where a
    C compiler exists (else it is reported as not run, and the verdict says so)."""
    code = main(["fmu", "check", str(built), "--steps", "16"])
    out = capsys.readouterr().out
    assert code == 0, out
    for name in ("validation", "fmpy run", "stop-time independence", "C host"):
        assert name in out
    assert "verdict: PASS" in out
    assert "FAIL" not in out
