"""The sweep's dynamic factor is the run's K_dyn = F_max / F_qs,max (docs/dynamic_factor.md):
one quasi-static reference per sweep, K_dyn = 1 at crawl speed to the run's stated error, the
peak force ratio and the stiffness-jump factor reported beside it under their own names
(SweepResult, sweep.csv, sweep.json, the terminal, ``gear-dyn compare``)."""

from __future__ import annotations

import copy
import csv
import json
import tomllib
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import gear_dyn as gd
from gear_dyn.analysis.dynamic_factor import QS_SPEED_RATIO
from gear_dyn.analysis.sweep import RPM
from gear_dyn.cli.app import main
from gear_dyn.scene.iso import iso_kv_at
from gear_dyn.scene.packaged import scene_path


def _scene(name: str, **stiffness: Any) -> Any:
    d = tomllib.loads(scene_path(name).read_text())
    if stiffness:
        d = copy.deepcopy(d)
        d.setdefault("stiffness", {}).update(stiffness)
    return gd.parse_scene(d)


#: as tests/analysis/test_dynamic_factor_like_for_like.py: f_m / f_n = 0.013, below the
#: reference's 1/64, with 4096 samples per mesh period (54 per natural period)
CRAWL = ["100 rpm"]


@pytest.mark.parametrize(("name", "stiffness"), [
    ("helicopter_tail", {"method": "iso6336"}),
    ("helicopter_tail", {"method": "potential_energy"}),
    ("helicopter_tail_backlash", {}),
    ("helicopter_tail_relief", {}),
])
def test_quasi_static_sweep_gives_one(name: str, stiffness: dict[str, str]) -> None:
    res = gd.sweep_scene(_scene(name, **stiffness), CRAWL, samples_per_period=4096)
    qs = res.quasi_static
    assert qs is not None
    # the crawl speed is itself quasi-static with the reference's error terms (inertia,
    # ring-down left at the next jump, sampling of the peak): the two may differ by both
    tol = 2 * qs["estimated_error"]
    assert tol < 1e-2  # small enough for the test to mean something
    for c in res.curves:  # the backlash scene is swept up and down
        assert c.dynamic_factor[0] == pytest.approx(1.0, abs=tol)
        # what the ratio to W keeps is the stiffness-jump overshoot, stated beside it
        assert c.peak_force_ratio[0] == pytest.approx(res.stiffness_jump_factor, abs=tol)
    if name != "helicopter_tail_relief":  # a rectangular or potential-energy k(t): it jumps
        assert res.stiffness_jump_factor > 1 + tol


def test_one_reference_per_sweep_whatever_the_speeds() -> None:
    """The quasi-static peak force does not depend on speed: the reference of two sweeps over
    different ranges is the same run, at f_m = f_n / 64, and divides every speed alike."""
    scene = _scene("helicopter_tail")
    a = gd.sweep_scene(scene, "1000 rpm:3000 rpm:5")
    b = gd.sweep_scene(scene, "6000 rpm:12000 rpm:7")
    assert a.quasi_static is not None and b.quasi_static is not None
    for key in ("peak_force_ratio", "mesh_frequency_hz", "estimated_error"):
        assert a.quasi_static[key] == b.quasi_static[key]
    assert a.quasi_static["mesh_frequency_hz"] == pytest.approx(
        QS_SPEED_RATIO * a.natural_frequency, rel=1e-12)
    for c in (*a.curves, *b.curves):
        np.testing.assert_allclose(c.dynamic_factor * a.stiffness_jump_factor,
                                   c.peak_force_ratio, rtol=1e-14)
    assert "stiffness-jump factor 1.7500" in repr(a)


def test_sweep_outputs_name_both_figures(tmp_path: Path,
                                         capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "sw"
    assert main(["sweep", "helicopter_tail", "--speeds", "6000 rpm:9000 rpm:13", "--out",
                 str(out), "--no-progress"]) == 0
    text = capsys.readouterr().out
    summary = json.loads((out / "sweep.json").read_text())
    jump = summary["stiffness_jump_factor"]
    assert jump == pytest.approx(1.75, rel=summary["quasi_static"]["estimated_error"])
    assert summary["dynamic_factor_definition"].startswith("K_dyn = peak dynamic mesh force")
    up = summary["curves"]["up"]
    assert up["max_peak_force_ratio"] == pytest.approx(up["max_dynamic_factor"] * jump,
                                                       rel=1e-12)
    # ISO K_v at the speed of the peak, beside it
    scene = gd.load_scene("helicopter_tail")
    kv = float(iso_kv_at(scene, np.array([up["max_dynamic_factor_speed_rpm"] * RPM]))[0])
    assert up["iso_6336_kv_at_max"] == pytest.approx(kv, rel=1e-12)
    assert (f"max dynamic factor K_dyn, sweep up: {up['max_dynamic_factor']:.4f} at "
            f"{up['max_dynamic_factor_speed_rpm']:.0f} rpm, ISO K_v there {kv:.4f}; peak force "
            f"{up['max_peak_force_ratio']:.4f} W") in text
    assert f"stiffness-jump factor {jump:.4f} = quasi-static peak force / W" in text
    with (out / "sweep.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    for row in rows:
        assert float(row["peak_force_ratio"]) == pytest.approx(
            float(row["dynamic_factor"]) * jump, rel=1e-12)
    best = max(rows, key=lambda r: float(r["dynamic_factor"]))
    assert float(best["dynamic_factor"]) == pytest.approx(up["max_dynamic_factor"], rel=1e-12)
