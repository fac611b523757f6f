"""The relief study's dynamic consequence: each design's single-DOF periodic steady state over a
speed range, checked against the static solution at low speed, against a transient run (a
second method) and for a ranking that follows its values."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gear_dyn.analysis.relief_study import relief_study
from gear_dyn.errors import InputError
from gear_dyn.geometry import GearPair
from gear_dyn.models.relief import slice_sdof
from gear_dyn.modification.analysis import rule_modifications
from gear_dyn.modification.slice_contact import SliceOptions
from gear_dyn.solvers import SolverSettings
from gear_dyn.solvers.simulate_bare import simulate_bare

#: the rail pair: 23/79, m_n 6 mm, 20 deg, helix 20 deg, B 70 mm, x = +0.3 / -0.1
RAIL = GearPair(23, 79, 6e-3, math.radians(20), 70e-3, math.radians(20), x1=0.3, x2=-0.1)
OPTS = SliceOptions(12, 16)
TORQUE = 2000.0
#: f_m / f_n of the speeds: two quasi-static ones and one below resonance
RATIOS = (1 / 200, 1 / 50, 0.5)


@pytest.fixture(scope="module")
def study():  # noqa: ANN201
    all_designs = rule_modifications(RAIL, TORQUE)
    designs = {k: all_designs[k] for k in ("unmodified", "handbook")}
    model, _ = slice_sdof(RAIL, 100.0, TORQUE, None, options=OPTS)
    speeds = [r * model.natural_frequency * 2 * math.pi / RAIL.z1 for r in RATIOS]
    return relief_study(RAIL, [TORQUE], designs, options=OPTS, speeds=speeds)


def test_low_speed_tends_to_the_static_solution(study) -> None:  # noqa: ANN001
    """Quasi-static, x = delta(p) (the loaded static TE) and k_t (x - e) = W exactly (e =
    delta - W / k_t): F_max / W -> 1 and p-p DTE -> PPTE. What is left is the damping force
    c (x' - e'), first order in f_m / f_n (2 xi f_m / f_n = 6e-4 at 1/200, times the TE's
    slope over its mean, of order 1), and the 64 samples per period against the TE's kinks:
    2e-3 on F/W, 6e-3 on the DTE; the error must also shrink from f_m / f_n = 1/50 to 1/200."""
    d = study.dynamics
    assert all(s == "periodic" for row in d.status for s in row)
    err_force = np.abs(d.peak_force_ratio[:, :2] - 1.0)
    err_dte = np.abs(d.ptp_dte[:, :2] / study.ppte[:, :1] - 1.0)
    assert np.all(err_force[:, 0] < 2e-3)
    assert np.all(err_dte[:, 0] < 6e-3)
    assert np.all(err_force[:, 0] < err_force[:, 1])
    assert np.all(err_dte[:, 0] < err_dte[:, 1])


def test_ranking_follows_the_values_and_a_transient_run(study) -> None:  # noqa: ANN001
    """The best design is the lowest peak F_max / W over the range; one design's value at the
    speed below resonance equals a transient run of the same model from the static state (24
    mesh periods: the free response decays by exp(-2 pi xi 20 f_n / f_m) ~ 3e-7 before the last
    4 are read), to 1e-4 on F/W and 1e-3 on the DTE (a few 1e-3 of the W/k_t offset)."""
    d = study.dynamics
    assert d.best == d.names[int(np.argmin(d.peak_force_ratio.max(axis=1)))]
    assert len(d.rows()) == 2 * len(RATIOS)
    assert study.to_dict()["dynamics"]["best"] == d.best
    i = d.names.index("handbook")
    model, _ = slice_sdof(RAIL, float(d.speed[-1]), TORQUE,
                          study.cases["handbook"].modification, options=OPTS)
    fm = model.mesh_frequency
    run = simulate_bare(model, 24 / fm, SolverSettings(method="LSODA", rtol=1e-9), 20 / fm)
    assert run.peak_force_ratio == pytest.approx(d.peak_force_ratio[i, -1], rel=1e-4)
    assert run.ptp_dte == pytest.approx(d.ptp_dte[i, -1], rel=1e-3)


def test_speeds_are_checked() -> None:
    with pytest.raises(InputError, match="speeds"):
        relief_study(RAIL, [TORQUE], {"unmodified": None}, options=OPTS, speeds=[-1.0])


def test_study_habit_json_rows_csv_and_plot(study, tmp_path) -> None:  # noqa: ANN001
    """to_dict survives json.dumps with the study's figures; rows() are the CSV's rows (the
    files the relief-study command writes); plot() draws the 4 panels with dynamics."""
    import csv
    import json

    d = json.loads(json.dumps(study.to_dict()))
    assert d["best"] == study.best
    assert [x["peak_to_peak_static_te_m"] for x in d["designs"]] == study.ppte.tolist()
    for obj, name in ((study, "study.csv"), (study.dynamics, "dynamics.csv")):
        rows = obj.rows()
        back = list(csv.DictReader(obj.to_csv(tmp_path / name).read_text().splitlines()))
        assert len(back) == len(rows) and list(back[0]) == list(rows[0])
        assert [str(r[k]) for r in rows for k in r] == [b[k] for b in back for k in b]
    fig = study.plot()
    assert len(fig.axes) == 4
