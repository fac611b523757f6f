"""``gear-dyn response``: the continuation's files, and user mistakes as exit 2."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import pytest

from gear_dyn.cli.app import main

RPM = 2 * math.pi / 60


def test_response_writes_the_curve_the_branch_and_its_folds(tmp_path: Path,
                                                             capsys: pytest.CaptureFixture[str]
                                                             ) -> None:
    out = tmp_path / "resp"
    # across the upper fold of the packaged backlash scene's resonance (about 6112 rpm)
    rc = main(["response", "helicopter_tail_backlash", "--speeds", "5800 rpm:6300 rpm",
               "--out", str(out), "--doublings", "0", "--diagram", "3"])
    assert rc == 0
    assert (out / "response.png").stat().st_size > 10_000
    # the orbits' stroboscopic samples over a brute-force diagram of 3 speeds (the figure's
    # artists: tests/plots/test_branch_samples_plot.py)
    assert (out / "bifurcation.png").stat().st_size > 10_000
    rows = list(csv.DictReader((out / "branch.csv").read_text().splitlines()))
    assert {"mu1_re", "mu1_im", "mu2_re", "mu2_im", "stable", "liouville_ok"} <= set(rows[0])
    assert all(r["liouville_ok"] == "True" for r in rows)
    assert {r["stable"] for r in rows} == {"True", "False"}
    data = json.loads((out / "branch.json").read_text())
    assert data["scene"] == "helicopter_tail_backlash"
    folds = [b for b in data["branches"][0]["bifurcations"] if b["kind"] == "fold"]
    assert len(folds) == 1
    assert 5800 * RPM < folds[0]["parameter"] < 6300 * RPM
    # the stated location error is far inside the 1e-8 relative the folds are located to
    assert folds[0]["parameter_error"] < 1e-8 * folds[0]["parameter"]
    assert f"fold at {folds[0]['parameter'] / RPM:.10g} rpm" in capsys.readouterr().out


@pytest.mark.parametrize(("argv", "match"), [
    (["helicopter_tail_backlash", "--speeds", "3000 rpm"], "expected LO:HI"),
    (["helicopter_tail_backlash", "--speeds", "3000:4000"], "give a unit"),
    (["eccentric_helical", "--speeds", "3000 rpm:4000 rpm"], "single-DOF mesh model"),
    (["helicopter_tail_backlash", "--speeds", "3000 rpm:4000 rpm", "--sweep", "1"],
     "--sweep 1: valid range 2..100000"),
    (["helicopter_tail_backlash", "--speeds", "3000 rpm:4000 rpm", "--diagram", "1"],
     "--diagram 1: valid range 2..100000"),
    (["helicopter_tail_backlash", "--speeds", "3000 rpm:4000 rpm", "--workers", "0"],
     "--workers = 0: valid range 1..4096"),
])
def test_user_mistakes_are_one_line_and_exit_2(tmp_path: Path, argv: list[str], match: str,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    rc = main(["response", *argv, "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2
    assert match in err and err.count("\n") == 1
    assert not (tmp_path / "o").exists()


def test_sweep_overlay_jumps_across_the_located_fold(tmp_path: Path) -> None:
    """``--sweep N``: the sweep's points and jumps drawn over the branch; the sweep up jumps
    between the two speeds that bracket the fold the continuation located (the sweep's own
    jump finder and the branch agree on where the jump is)."""
    import matplotlib.pyplot as plt

    from gear_dyn.analysis.continuation import continue_orbits
    from gear_dyn.plots.continuation import plot_branch
    from gear_dyn.scene import load_scene
    from gear_dyn.scene.sweep import SceneModels, sweep_scene

    out = tmp_path / "resp"
    assert main(["response", "helicopter_tail_backlash", "--speeds", "5800 rpm:6300 rpm",
                 "--doublings", "0", "--sweep", "11", "--quiet", "--out", str(out)]) == 0
    assert (out / "bifurcation.png").is_file()  # without --diagram too
    data = json.loads((out / "branch.json").read_text())
    fold = next(b["parameter"] for b in data["branches"][0]["bifurcations"] if b["kind"] == "fold")
    scene = load_scene("helicopter_tail_backlash")
    swept = sweep_scene(scene, "5800 rpm:6300 rpm:11")
    up = next(c for c in swept.curves if c.direction == "up")
    assert [(j.from_speed < fold < j.to_speed) for j in up.jumps] == [True]
    branch = continue_orbits(SceneModels.of(scene), 5800 * RPM, 6300 * RPM, doublings=0)
    fig = plot_branch(branch, sweep=swept)
    arrows = [a for a in fig.axes[0].texts if getattr(a, "arrow_patch", None) is not None]
    assert len(arrows) == sum(len(c.jumps) for c in swept.curves) >= 1  # all between orbits
    plt.close(fig)
