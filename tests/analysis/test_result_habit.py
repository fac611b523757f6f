"""One habit for the public result types: ``plot(ax=None)``, ``to_dict()`` and ``rows()``.

Per type: ``to_dict()`` survives ``json.dumps`` and carries the key figures of the result
itself; ``rows()`` agrees, row for row and key for key, with the CSV that ``to_csv`` (the
CLI's writer) puts on disk.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import gear_dyn as gd
from gear_dyn.analysis.motion import DiagramOptions, bifurcation_diagram
from gear_dyn.analysis.sweep import RPM


def _csv_rows(path: Path) -> list[dict[str, str]]:
    lines = [ln for ln in path.read_text().splitlines() if not ln.startswith("#")]
    return list(csv.DictReader(lines))


def _agree(rows: list[dict[str, Any]], path: Path) -> None:
    """The rows are the file's: same length, same keys in order, same values (exact)."""
    back = _csv_rows(path)
    assert len(back) == len(rows) > 0
    assert list(back[0]) == list(rows[0])
    for r, b in zip(rows, back, strict=True):
        for k, v in r.items():
            assert (np.isnan(v) and b[k] == "nan") if v != v else float(b[k]) == v, k


@pytest.fixture(scope="module")
def sweep() -> Any:
    return gd.sweep_scene(gd.load_scene("helicopter_tail"), "3000 rpm:3600 rpm:3")


def test_sweep_result_habit(sweep, tmp_path) -> None:
    d = json.loads(json.dumps(sweep.to_dict()))
    value, speed, direction = sweep.peak()
    assert d["curves"][direction]["max_dynamic_factor"] == value
    assert d["curves"][direction]["max_dynamic_factor_speed_rpm"] == pytest.approx(speed / RPM)
    assert d["n_speeds"] == 3 and d["natural_frequency_hz"] == sweep.natural_frequency
    rows = sweep.rows()
    assert [r["dynamic_factor"] for r in rows] == sweep.curves[0].dynamic_factor.tolist()
    _agree(rows, sweep.to_csv(tmp_path / "sweep.csv"))


def test_sweep_cli_files_are_the_methods(sweep, tmp_path) -> None:
    """gear-dyn sweep's sweep.csv: rows() then the scene's ISO K_v column; its sweep.json:
    to_dict() plus the scene's figures."""
    from gear_dyn.cli.sweep import write_sweep_outputs

    write_sweep_outputs(sweep, gd.load_scene("helicopter_tail"), tmp_path / "out", "none")
    back = _csv_rows(tmp_path / "out" / "sweep.csv")
    rows = sweep.rows()
    assert len(back) == len(rows) and list(back[0]) == [*rows[0], "iso_6336_kv"]
    assert [float(b["rms_dte_m"]) for b in back] == [r["rms_dte_m"] for r in rows]
    written = json.loads((tmp_path / "out" / "sweep.json").read_text())
    up = sweep.to_dict()["curves"]["up"]
    assert written["curves"]["up"]["max_dynamic_factor"] == up["max_dynamic_factor"]
    assert set(sweep.to_dict()) <= set(written)


def test_bifurcation_diagram_habit(tmp_path) -> None:
    m = gd.SDOFModel(1.0, gd.rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
                     backlash=1e-3)
    diagram = bifurcation_diagram(gd.sdof_family(m, "speed", teeth=20), [43.0, 44.0],
                                  options=DiagramOptions(settle=20, samples=32), name="case")
    d = json.loads(json.dumps(diagram.to_dict()))
    up = diagram.curve("up")
    assert [p["period"] for p in d["curves"]["up"]] == up.period.tolist()
    assert [p["speed_rad_s"] for p in d["curves"]["up"]] == up.speed.tolist()
    rows = diagram.rows()
    assert len(rows) == 2 * 2 * 32
    path = diagram.to_csv(tmp_path / "samples.csv")
    assert path.read_text().startswith("# case: stroboscopic samples")
    _agree(rows, path)


def test_tolerance_result_habit(tmp_path) -> None:
    from gear_dyn.scene.tolerance import tolerance_scene

    res = tolerance_scene(gd.load_scene("helicopter_tail"), ["2500 rpm", "3300 rpm"],
                          samples=4, grade=7, samples_per_period=16)
    d = json.loads(json.dumps(res.to_dict()))
    k = res.stats("k_dyn")
    assert d["metrics"]["k_dyn"]["median"] == k["median"].tolist()
    assert d["speed_rad_per_s"] == res.speeds.tolist() and d["n_samples"] == 4
    rows = res.rows()
    assert [r["k_dyn_median"] for r in rows] == k["median"].tolist()
    _agree(rows, res.to_csv(tmp_path / "tolerance.csv"))


def test_run_result_habit(tmp_path) -> None:
    m = gd.SDOFModel(0.5, gd.rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
    res = gd.simulate(m, 0.02)
    d = json.loads(json.dumps(res.to_dict()))
    assert d["rms_dte_m"] == res.rms_dte and d["dynamic_factor"] == res.dynamic_factor
    assert d["mesh_frequency_hz"] == 500.0
    rows = res.rows()
    assert len(rows) == res.t.size
    assert [r["dte"] for r in rows] == res.series("dte").tolist()
    path = res.to_csv(tmp_path / "timeseries.csv")
    assert path.read_text().splitlines()[2] == f"# dte: {d['dte_definition']}"
    _agree(rows, path)


def test_branch_habit(tmp_path) -> None:
    m = gd.SDOFModel(1.0, gd.rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
                     backlash=1e-3)
    branch = gd.continue_orbits(gd.sdof_family(m, "speed", teeth=20), 43.0, 44.5)
    d = json.loads(json.dumps(branch.to_dict()))
    assert len(d["points"]) == len(branch.points)
    assert [p["speed_rad_s"] for p in d["points"]] == branch.array("parameter").tolist()
    rows = branch.rows()
    back = _csv_rows(branch.to_csv(tmp_path / "branch.csv"))
    assert len(back) == len(rows) and list(back[0]) == list(rows[0])
    assert [str(r[k]) for r in rows for k in r] == [b[k] for b in back for k in b]


def test_motion_habit(tmp_path) -> None:
    m = gd.SDOFModel(1.0, gd.rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 136.9,
                     backlash=1e-3)
    motion = gd.classify_motion(m, m.initial_state(), settle=20, samples=32)
    d = json.loads(json.dumps(motion.to_dict()))
    assert (d["kind"], d["label"], d["period"]) == (motion.kind, motion.label, motion.period)
    assert max(abs(complex(*z)) for z in d["multipliers"]) == pytest.approx(
        d["spectral_radius"], rel=1e-12)
    assert d["state_si"] == motion.state.tolist()
    rows = motion.rows()
    assert [r["state_0"] for r in rows] == motion.samples[:, 0].tolist()
    _agree(rows, motion.to_csv(tmp_path / "motion.csv"))
    fig = motion.plot()
    assert fig.axes[0].get_title() == motion.label


def test_slice_contact_habit(tmp_path) -> None:
    import math

    from gear_dyn.geometry import GearPair
    from gear_dyn.modification.slice_contact import SliceOptions, slice_contact

    rail = GearPair(23, 79, 6e-3, math.radians(20), 70e-3, math.radians(20), x1=0.3, x2=-0.1)
    c = slice_contact(rail, [400.0, 2000.0], options=SliceOptions(slices=8, positions=12))
    d = json.loads(json.dumps(c.to_dict()))
    assert [s["peak_to_peak_static_te_m"] for s in d["summary"]] == c.peak_to_peak_te.tolist()
    rows = c.rows()
    assert len(rows) == 2 * c.phase.size
    assert [r["loaded_te_m"] for r in rows] == c.deflection.ravel().tolist()
    _agree(rows, c.to_csv(tmp_path / "ltca.csv"))
    fig = c.plot(title="rail")
    assert len(fig.axes) >= 2


def test_relief_case_habit(tmp_path) -> None:
    import math

    from gear_dyn.geometry import GearPair
    from gear_dyn.modification.analysis import relief_case
    from gear_dyn.stiffness.select import pair_stiffness_function

    tail = GearPair(23, 64, 6e-3, math.radians(22.5), 50e-3)
    case = relief_case("unmodified", tail, pair_stiffness_function(tail), 1474.4, None)
    d = json.loads(json.dumps(case.to_dict()))
    assert d["peak_stress_pa"] == float(np.max(case.stress)) == max(d["path"]["stress_pa"])
    assert d["path"]["sharing"] == case.path.sharing.tolist()
    rows = case.rows()
    assert len(rows) == case.path.position.size
    _agree(rows, case.to_csv(tmp_path / "path.csv"))
    assert len(case.plot().axes) == 2
