"""``gear-dyn bifurcation``: the diagram's files, its summary and its refusals.

Scene: the packaged backlash pair with rectangular stiffness 0.5e9 / 1.5e9 N/m and damping
ratio 0.02 (tests/analysis/motion_cases.py), at 17000..18400 rpm (f_m / f_n = 2.17..2.35): a
period-1 orbit above ~17750 rpm, period-2 below it (the period-doubling point between), swept
down; the up sweep, started from the static state at 17000 rpm, meets coexisting orbits
(period-6 at 17200 rpm) before it joins the period-2 orbit (docs/motion.md draws the whole
cascade).
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from gear_dyn.cli.app import main
from gear_dyn.scene.packaged import scene_path


def _scene(tmp_path: Path) -> Path:
    text = scene_path("helicopter_tail_backlash").read_text()
    text = text.replace('method = "iso6336"', 'method = "rectangular"\nsingle = "0.5e9 N/m"\n'
                        'double = "1.5e9 N/m"').replace("ratio = 0.06", "ratio = 0.02")
    path = tmp_path / "parametric.toml"
    path.write_text(text)
    return path


def test_writes_png_csv_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "bif"
    assert main(["bifurcation", str(_scene(tmp_path)), "--speeds", "17000 rpm:18400 rpm:8",
                 "--settle", "300", "--samples", "32", "--out", str(out), "--quiet"]) == 0
    text = capsys.readouterr().out
    assert "down: period-1 18400-17800 rpm; period-2 17600-17000 rpm" in text
    assert "period-1 17800-18400 rpm" in text.split("down:")[0]  # up, above the doubling
    assert (out / "bifurcation.png").stat().st_size > 10_000
    summary = json.loads((out / "bifurcation.json").read_text())
    assert [p["period"] for p in summary["curves"]["down"]] == [1] * 4 + [2] * 4
    assert [p["period"] for p in summary["curves"]["up"]][-4:] == [1] * 4
    with (out / "samples.csv").open() as fh:
        rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    assert len(rows) == 2 * 8 * 32
    # every period the command reports, the samples show: they repeat after p mesh periods
    # (to the orbit's closing, ~1e-8 of the 10 um state scale) and not after fewer
    for k in range(16):
        block = rows[32 * k: 32 * (k + 1)]
        x = np.array([float(r["x"]) for r in block])
        p = int(float(block[0]["period"]))
        if p:
            assert np.max(np.abs(x[p:] - x[:-p])) < 1e-11
            assert all(np.max(np.abs(x[d:] - x[:-d])) > 1e-8 for d in range(1, p))


def test_bad_values_are_one_line_and_exit_2(tmp_path: Path,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    scene = str(_scene(tmp_path))
    out = tmp_path / "bif"
    assert main(["bifurcation", scene, "--speeds", "16800 rpm:18400 rpm:3", "--samples", "8",
                 "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "samples = 8" in err
    assert main(["bifurcation", scene, "--speeds", "16800:18400:3", "--out", str(out)]) == 2
    assert capsys.readouterr().err.count("\n") == 1
    assert not out.exists()
