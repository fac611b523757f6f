"""``gear-dyn response ... --torques LO:HI:N``: the jump map's files, and user mistakes."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import pytest

from gear_dyn.cli.app import main

RPM = 2 * math.pi / 60


@pytest.mark.slow
def test_jump_map_at_the_scene_torque_has_the_response_folds(tmp_path: Path) -> None:
    """At the scene's own torque (368.6 N m) the fold curves pass through the folds of the
    response branch of the same run, to 1e-8 relative (the same scene model, the same
    bracketing)."""
    out = tmp_path / "resp"
    rc = main(["response", "helicopter_tail_backlash", "--speeds", "4700 rpm:6300 rpm",
               "--torques", "368.6 N*m:420 N*m:2", "--out", str(out), "--doublings", "0"])
    assert rc == 0
    assert (out / "jump_map.png").stat().st_size > 10_000
    rows = list(csv.DictReader((out / "fold_curve.csv").read_text().splitlines()))
    at_ref = sorted(float(r["speed_rad_s"]) for r in rows
                    if float(r["torque_n_m"]) == pytest.approx(368.6, rel=1e-12))
    data = json.loads((out / "branch.json").read_text())
    folds = sorted(b["parameter"] for b in data["branches"][0]["bifurcations"]
                   if b["kind"] == "fold")
    assert len(at_ref) == len(folds) >= 2
    for a, b in zip(at_ref, folds, strict=True):
        assert a == pytest.approx(b, rel=1e-8)
    assert {"speed_rpm", "speed_error_rad_s", "region", "kind", "frequency_ratio",
            "stability", "locate_tol"} <= set(rows[0])
    # the fold map as JSON, and branch.json with f_n and each fold in rad/s and rpm
    fmap = json.loads((out / "fold_map.json").read_text())
    assert fmap["scene"] == "helicopter_tail_backlash" and fmap["reference_torque_n_m"] == 368.6
    assert len(fmap["rows"]) == len(rows)
    assert data["natural_frequency_hz"] == pytest.approx(fmap["natural_frequency_hz"])
    for b in data["branches"][0]["bifurcations"]:
        assert b["speed_rpm"] == pytest.approx(b["speed_rad_s"] / RPM, rel=1e-15)


@pytest.mark.parametrize(("torques", "match"), [
    ("100 N*m:200 N*m", "expected LO:HI:N"),
    ("100:200:3", "give a unit"),
    ("100 N*m:200 N*m:1", "valid range 2..200"),
    ("100 N*m:100 N*m:3", "must differ"),
])
def test_torque_mistakes_are_one_line_and_exit_2(tmp_path: Path, torques: str, match: str,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    rc = main(["response", "helicopter_tail_backlash", "--speeds", "3000 rpm:4000 rpm",
               "--torques", torques, "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2
    assert match in err and err.count("\n") == 1
    assert not (tmp_path / "o").exists()
