"""ISO 6336-1 K_v in the CLI: the run prints it beside the simulated dynamic factor; the sweep
carries it per speed (CSV, sweep.json, terminal) and draws it beside the simulated one."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

import gear_dyn as gd
from gear_dyn.cli import main
from gear_dyn.scene import parse_scene
from gear_dyn.scene.iso import iso_kv_at, iso_kv_summary

RPM = 2 * np.pi / 60


def test_sweep_csv_has_kv_per_speed(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "sw"
    assert main(["sweep", "helicopter_tail", "--speeds", "3000 rpm:12000 rpm:4", "--out",
                 str(out), "--workers", "1", "--no-progress", "--chart", "none"]) == 0
    with (out / "sweep.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    scene = gd.load_scene("helicopter_tail")
    for row in rows:
        # second path: the scalar summary of the scene moved to that speed
        moved = parse_scene({**scene.raw, "operating": {**scene.raw["operating"],
                                                        "speed": f"{row['speed_rpm']} rpm"}})
        assert float(row["iso_6336_kv"]) == pytest.approx(iso_kv_summary(moved)["k_v"],
                                                          rel=1e-12)
    summary = json.loads((out / "sweep.json").read_text())
    rpm = np.linspace(3000, 12000, 600)
    assert summary["iso_6336_kv_max"] == pytest.approx(np.max(iso_kv_at(scene, rpm * RPM)))
    assert "ISO 6336-1 method B K_v: max" in capsys.readouterr().out


def test_response_plot_draws_kv_beside_the_dynamic_factor() -> None:
    from gear_dyn.plots.sweep import plot_sweep_response
    from gear_dyn.scene.sweep import sweep_scene

    scene = gd.load_scene("helicopter_tail")
    res = sweep_scene(scene, np.array([3000.0, 6000.0]) * RPM, si=True, workers=1, direction="up")
    rpm = np.linspace(3000, 6000, 50)
    kv = iso_kv_at(scene, rpm * RPM)
    fig = plot_sweep_response(res, iso_kv=(rpm, kv))
    lines = [ln for ln in fig.axes[0].lines if ln.get_label().startswith("ISO 6336-1 K_v")]
    assert len(lines) == 1
    assert np.allclose(lines[0].get_ydata(), kv) and np.allclose(lines[0].get_xdata(), rpm)


def test_run_prints_kv_beside_the_dynamic_factor(tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", "helicopter_tail", "--periods", "20", "--out", str(tmp_path / "r")]) == 0
    out = capsys.readouterr().out
    summary = json.loads((tmp_path / "r" / "summary.json").read_text())
    iso = summary["iso_6336_kv"]
    assert (f"ISO 6336-1 method B: K_v = {iso['k_v']:.4f} at N = n1/n_E1 = "
            f"{iso['resonance_ratio_n']:.3f}") in out
    assert "subcritical range N <= N_S (N_S = 0.85)" in out
    assert iso["formula"] in out and "grade 5 (assumed" in out
