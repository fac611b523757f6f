"""gear-dyn compare: the peak table against the sweeps run on their own."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from gear_dyn.analysis.sweep import RPM
from gear_dyn.cli.app import main
from gear_dyn.scene import load_scene
from gear_dyn.scene.iso import iso_kv_at
from gear_dyn.scene.sweep import sweep_scene

SCENES = Path(__file__).resolve().parents[2] / "gear_dyn" / "scenes"


def test_compare_table_equals_separate_sweeps(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                              monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MPLBACKEND", "Agg")
    a = SCENES / "helicopter_tail.toml"
    b = tmp_path / "damped.toml"
    b.write_text(a.read_text().replace("ratio = 0.06", "ratio = 0.12")
                 .replace('name = "helicopter_tail"', 'name = "damped"'))
    speeds = "5000 rpm:9000 rpm:41"
    out = tmp_path / "cmp"
    assert main(["compare", str(a), str(b), "--speeds", speeds, "--out", str(out),
                 "--quiet"]) == 0
    text = capsys.readouterr().out
    data = json.loads((out / "compare.json").read_text())
    assert data["scenes"] == ["helicopter_tail", "damped"]
    assert (out / "compare.png").stat().st_size > 0 and (out / "compare.csv").exists()
    for path, row in zip((a, b), data["peaks"], strict=True):
        scene = load_scene(path)
        res = sweep_scene(scene, speeds)
        c = res.curves[0]
        i = int(np.nanargmax(c.dynamic_factor))
        # K_dyn, as gear-dyn run and sweep state it; the peak force / W and the stiffness-jump
        # factor beside it, and ISO K_v at the same speed
        assert row["max_dynamic_factor"] == c.dynamic_factor[i]
        assert row["max_dynamic_factor_speed_rpm"] == pytest.approx(c.speed[i] / RPM)
        assert row["max_peak_force_ratio"] == c.peak_force_ratio[i]
        assert row["stiffness_jump_factor"] == res.stiffness_jump_factor
        assert row["max_peak_force_ratio"] == pytest.approx(
            row["max_dynamic_factor"] * row["stiffness_jump_factor"], rel=1e-12)
        assert row["iso_6336_kv_at_max"] == pytest.approx(
            float(iso_kv_at(scene, c.speed[i:i + 1])[0]), rel=1e-12)
        for key in ("max_dynamic_factor", "iso_6336_kv_at_max", "max_peak_force_ratio",
                    "stiffness_jump_factor"):
            assert f"{row[key]:.4f}" in text
    assert "max K_dyn" in text and "ISO K_v there" in text
    assert "helicopter_tail stiffness: iso6336 ([stiffness] method, as given)" in text
    # more damping, lower peak: the table says which design is better
    assert data["peaks"][1]["max_dynamic_factor"] < data["peaks"][0]["max_dynamic_factor"]


def test_compare_refuses_a_missing_scene(tmp_path: Path) -> None:
    assert main(["compare", str(tmp_path / "nope.toml"), "--speeds", "1000 rpm:2000 rpm:3",
                 "--out", str(tmp_path / "o")]) == 2
