"""`gear-dyn bench` and the benchmark API: files, figures, recommendation, input errors.

Short spans (4 mesh periods) keep this fast; the recorded benchmark runs are in
benchmarks/results/. Every error figure checked here is against an independent reference.
"""

from __future__ import annotations

import csv
import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from gear_dyn.analysis.bench import BenchCase, recommend, reference_solution, run_bench
from gear_dyn.cli.app import main
from gear_dyn.scene import load_scene
from gear_dyn.scene.build import build_plan
from gear_dyn.solvers import SolverSettings, integrate, time_grid

SCENE = "examples/scenes/helicopter_tail.toml"


def test_cli_bench_writes_plot_tables_and_recommends_the_fastest(
        tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    """The recommendation is the fastest case of this run that meets the target, by the run
    times the table records (which method wins is a timing, not asserted: on a loaded
    machine a 0.4 ms exact run can lose a single timed repeat)."""
    out = tmp_path / "b"
    code = main(["bench", SCENE, "--out", str(out), "--periods", "4", "--repeats", "1",
                 "--rtols", "1e-5,1e-8", "--methods", "DOP853,LSODA"])
    assert code == 0
    for name in ("work_precision.png", "bench.csv", "bench.md", "bench.json"):
        assert (out / name).stat().st_size > 0
    rows = list(csv.DictReader((out / "bench.csv").read_text(encoding="utf-8").splitlines()))
    # exact + 2 methods x 2 rtols restarted + RK45 once x 2 rtols
    assert len(rows) == 1 + 4 + 2
    summary = json.loads((out / "bench.json").read_text(encoding="utf-8"))
    assert summary["reference"] == "exact propagator"
    ok = [r for r in rows if r["status"] == "ok" and float(r["err_max"]) <= 1e-6]
    fastest = min(ok, key=lambda r: float(r["run_time_s"]))
    rec = summary["recommendation"]["1e-06"]
    assert (rec["method"], rec["mode"], rec["rtol"]) == (
        fastest["method"], fastest["mode"], float(fastest["rtol"]))
    assert any(r["method"] == "exact" for r in ok)  # the exact propagator meets 1e-6
    md = (out / "bench.md").read_text(encoding="utf-8")
    assert "## Recommendation" in md and "gear-dyn bench" in md
    assert f"use {rec['method']}" in capsys.readouterr().out
    # every ODE case's error shrinks with the tolerance (independent reference: exact)
    for method in ("DOP853", "LSODA"):
        errs = [float(r["err_max"]) for r in rows if r["method"] == method]
        assert errs[1] < errs[0] / 10


def test_cli_bench_rejects_bad_input(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    assert main(["bench", SCENE, "--out", str(tmp_path / "x"), "--rtols", "abc"]) == 2
    assert main(["bench", SCENE, "--out", str(tmp_path / "x"), "--methods", "Euler",
                 "--periods", "4"]) == 2
    err = capsys.readouterr().err
    assert "--rtols" in err and "Euler" in err
    assert not (tmp_path / "x").exists()  # nothing written on failure


def test_smooth_reference_error_is_estimated_and_small() -> None:
    """Fourier stiffness: the reference is DOP853 at rtol 1e-13; its own error (difference from
    the rtol-1e-12 run) is 100x below the error of a typical run it is used to measure."""
    model = build_plan(load_scene(SCENE)).model
    fmodel = replace(model, stiffness=model.stiffness.truncated(5))
    t = time_grid(fmodel.mesh_frequency, 3 / fmodel.mesh_frequency, 64)
    ref = reference_solution(fmodel, t)
    assert ref.kind.startswith("DOP853") and ref.own_error < 1e-9
    y8, _ = integrate(fmodel, t, SolverSettings(method="DOP853", rtol=1e-8))
    err8 = np.max(np.abs(y8[0] - ref.y[0])) / (fmodel.static_load / fmodel.mean_stiffness)
    assert ref.own_error < err8 / 100


def test_run_bench_api_and_recommend() -> None:
    model = build_plan(load_scene(SCENE)).model
    ticks: list[tuple[int, int]] = []
    rep = run_bench(model, 3 / model.mesh_frequency, name="t", methods=("RK45",),
                    rtols=(1e-4, 1e-7), repeats=1, samples_per_period=32, baseline=False,
                    progress=lambda done, total: ticks.append((done, total)))
    labels = [c.label for c in rep.cases]
    assert labels == ["exact", "RK45", "RK45"]
    # progress: the reference, then one tick per case, ending at the total
    assert ticks == [(1, 4), (2, 4), (3, 4), (4, 4)]
    assert rep.cases[0].err_max < 1e-11  # the exact run states its rounding level
    best = rep.recommend(1e-6)
    assert best is not None and best.label == "exact"
    # smooth stiffness: the periodic step maps are benchmarked and win (reference DOP853)
    fmodel = replace(model, stiffness=model.stiffness.truncated(5))
    frep = run_bench(fmodel, 3 / model.mesh_frequency, methods=("LSODA",), rtols=(1e-6,),
                     repeats=1, samples_per_period=32, baseline=False)
    assert [c.label for c in frep.cases] == ["periodic", "LSODA"]
    # the maps' substeps are tied to rtol (solvers/periodic.py): the error stays below it, and
    # far below LSODA's at the same rtol
    assert frep.cases[0].err_max < 1e-6 and frep.cases[0].err_max < 1e-2 * frep.cases[1].err_max
    # recommend() picks the fastest case meeting the target and ignores failures
    mk = lambda m, tm, e, s="ok": BenchCase(m, "restart", 1e-6, tm, tm, 1, e, e, 0, 0, 0, 1, s)  # noqa: E731
    cases = [mk("A", 1.0, 1e-7), mk("B", 0.5, 1e-5), mk("C", 0.2, math.nan, "failed"),
             mk("D", 0.8, 5e-7)]
    pick = recommend(cases, 1e-6)
    assert pick is not None and pick.method == "D"
    assert recommend(cases, 1e-9) is None
