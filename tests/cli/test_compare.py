"""gear-dyn compare: a thin shell over compare_scenes; its files and its ranked table."""

from __future__ import annotations

import csv
import json
import tomllib
from pathlib import Path

import pytest

from gear_dyn.cli.app import main
from gear_dyn.scene import load_scene
from gear_dyn.scene.sweep import sweep_scene

SCENES = Path(__file__).resolve().parents[2] / "gear_dyn" / "scenes"


def test_compare_writes_the_ranked_comparison(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                              monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MPLBACKEND", "Agg")
    a = SCENES / "helicopter_tail.toml"
    b = tmp_path / "damped.toml"
    b.write_text(a.read_text().replace("ratio = 0.06", "ratio = 0.12")
                 .replace('name = "helicopter_tail"', 'name = "damped"'))
    speeds = "7000 rpm:8000 rpm:5"
    out = tmp_path / "cmp"
    assert main(["compare", str(a), str(b), "--speeds", speeds, "--out", str(out),
                 "--quiet"]) == 0
    text = capsys.readouterr().out
    data = json.loads((out / "compare.json").read_text())
    assert data["scenes"] == ["helicopter_tail", "damped"] and data["baseline"] == "helicopter_tail"
    # more damping, lower peak force: the damped design ranks first
    assert data["ranking"] == ["damped", "helicopter_tail"]
    # the peaks of the scenes' own sweeps (their operating speed, 3319 rpm, lies outside)
    assert [d["peak_peak_force_ratio"] for d in data["designs"]] == [
        sweep_scene(load_scene(p), speeds).peak("peak_force_ratio").value for p in (a, b)]
    base, damped = data["designs"]
    assert damped["peak_peak_force_ratio_delta"] == pytest.approx(
        damped["peak_peak_force_ratio"] - base["peak_peak_force_ratio"], rel=1e-14)
    for key in ("operating_peak_force_ratio", "operating_rms_dte_m", "peak_rms_dte_m",
                "peak_contact_stress_pa", "peak_dynamic_factor", "iso_6336_kv_at_peak_force"):
        assert key in damped
    # the linear model's force goes negative at both resonance peaks: flagged and explained
    assert "linear_model_invalid_at_peak" in damped["flags"]
    assert "linear_model_invalid_at_peak" in data["flags"]
    assert "does not rank designs" in data["definitions"]["dynamic_factor"]
    with open(out / "compare.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["scene"] for r in rows] == ["damped", "helicopter_tail"]
    assert (out / "compare.png").stat().st_size > 0
    # the table: ranked, with the peak force, its change from the baseline and the flags
    lines = text.splitlines()
    assert lines[1].split()[:2] == ["1", "damped"]
    assert f"{damped['peak_peak_force_ratio']:.4f}" in lines[1]
    assert f"{damped['peak_peak_force_ratio_delta_pct']:+.1f} %" in lines[1]
    assert "linear_model_invalid_at_peak" in lines[1]
    assert "warning: damped: the mesh force of this linear model goes negative" in text
    assert "helicopter_tail stiffness: iso6336 ([stiffness] method, as given)" in text


def test_compare_names_two_scenes_of_one_name_by_their_files(
        tmp_path: Path, capsys: pytest.CaptureFixture[str],
        monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MPLBACKEND", "Agg")
    src = tomllib.loads((SCENES / "helicopter_tail.toml").read_text())
    assert src["scene"]["name"] == "helicopter_tail"
    twin = tmp_path / "twin.toml"
    twin.write_text((SCENES / "helicopter_tail.toml").read_text().replace("ratio = 0.06",
                                                                          "ratio = 0.08"))
    out = tmp_path / "o"
    assert main(["compare", "helicopter_tail", str(twin), "--speeds", "7000 rpm:8000 rpm:3",
                 "--out", str(out), "--quiet"]) == 0
    data = json.loads((out / "compare.json").read_text())
    assert data["scenes"] == ["helicopter_tail (helicopter_tail)", "helicopter_tail (twin.toml)"]


def test_compare_refuses_a_missing_scene(tmp_path: Path) -> None:
    assert main(["compare", str(tmp_path / "nope.toml"), "--speeds", "1000 rpm:2000 rpm:3",
                 "--out", str(tmp_path / "o")]) == 2


def test_compare_prints_the_backlash_hint(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                          monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MPLBACKEND", "Agg")
    out = tmp_path / "o"
    assert main(["compare", "helicopter_tail_backlash", "--speeds", "3000 rpm:3319 rpm:2",
                 "--out", str(out), "--quiet"]) == 0
    text = capsys.readouterr().out
    assert "warning: helicopter_tail_backlash: backlash with only the mesh stiffness" in text
    data = json.loads((out / "compare.json").read_text())
    assert any("does not scale with W" in w for w in data["warnings"])
