"""A response that is not periodic is never called hysteresis (gear_dyn.analysis.sweep.report).

Scene: the packaged backlash pair with constant mesh stiffness (1e9 N/m) and a 10 um
transmission error, at f_m / f_n = 1.55 and 1.6: heavy separation. Sweeping up, the pair stays
on a period-2 orbit; sweeping down, the sweep starts at 1.6 from the static state and finds no
orbit of one or two mesh periods there (``aperiodic``), then settles at 1.55 on the period-2
orbit of the up sweep. Up and down differ at 1.6, but one of them is not periodic: no
hysteresis, the speed is reported as aperiodic (sweep.json and the terminal summary alike).

Independent check: the flow of the model from the down sweep's state at 1.6 (the end of its
measured window) does not repeat after one or two mesh periods; the up sweep's state is a
two-period orbit of the same flow.
"""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

from gear_dyn.analysis.sweep import (
    RPM,
    aperiodic_ranges,
    hysteresis_ranges,
    periodic_response,
    summarize_sweep,
)
from gear_dyn.scene import build_model, parse_scene
from gear_dyn.scene.packaged import scene_path
from gear_dyn.scene.sweep import model_at_speed, sweep_scene
from gear_dyn.solvers import SolverSettings, integrate

RATIOS = (1.55, 1.6)  # f_m / f_n


@pytest.fixture(scope="module")
def aperiodic_sweep():
    data = tomllib.loads(scene_path("helicopter_tail_backlash").read_text())
    data["stiffness"] = {"method": "rectangular", "single": "1e9 N/m", "double": "1e9 N/m"}
    data["transmission_error"] = {"cos": ["10 um"]}
    scene = parse_scene(data, "constant_stiffness_backlash.toml")
    rpm_n = build_model(scene).natural_frequency * 60 / 23  # f_m = f_n
    return scene, sweep_scene(scene, np.array(RATIOS) * rpm_n * RPM, si=True)


def test_aperiodic_speed_is_not_hysteresis(aperiodic_sweep) -> None:
    _scene, res = aperiodic_sweep
    up, down = res.curve("up"), res.curve("down")
    assert up.status == ("period-2", "period-2")
    assert down.status == ("aperiodic", "period-2")
    assert periodic_response(up).tolist() == [True, True]
    assert periodic_response(down).tolist() == [False, True]
    # the two directions differ at 1.6 f_n (heavy separation on the down sweep) ...
    assert down.separation[0] > 0.3 > up.separation[1]
    assert abs(down.rms_dte[0] - up.rms_dte[1]) > 0.2 * up.rms_dte[1]
    # ... yet that is no hysteresis: one of them is not periodic
    top = float(up.speed[1] / RPM)
    assert hysteresis_ranges(res) == []
    assert aperiodic_ranges(res) == [[top, top]]
    summary = summarize_sweep(res)
    assert summary["hysteresis_ranges_rpm"] == []
    assert summary["aperiodic_ranges_rpm"] == [[top, top]]
    assert summary["curves"]["down"]["aperiodic_ranges_rpm"] == [[top, top]]
    assert summary["curves"]["up"]["aperiodic_ranges_rpm"] == []


def test_terminal_summary_says_not_periodic(aperiodic_sweep,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    from gear_dyn.cli.sweep import _print_summary

    scene, res = aperiodic_sweep
    _print_summary(res, scene, summarize_sweep(res), "none")
    out = capsys.readouterr().out
    assert "hysteresis" not in out
    top = round(float(res.curve("up").speed[1] / RPM))
    assert f"no period-1 or period-2 orbit (down): {top} rpm" in out


def test_down_response_repeats_after_neither_one_nor_two_periods(aperiodic_sweep) -> None:
    scene, res = aperiodic_sweep
    up, down = res.curve("up"), res.curve("down")
    model = model_at_speed(scene, float(down.speed[0]))
    scale = np.asarray(model.state_scale, dtype=float)
    t = np.arange(41) / model.mesh_frequency  # 40 mesh periods, sampled once per period
    settings = SolverSettings(method="auto", rtol=1e-10)
    y, _ = integrate(model, t, settings, down.state[0])
    x = y / scale[:, None]
    # a periodic orbit of the sweep closes to ~100 rtol; these miss by order one
    assert np.min(np.max(np.abs(x[:, 1:] - x[:, :-1]), axis=0)) > 1e-2
    assert np.min(np.max(np.abs(x[:, 2:] - x[:, :-2]), axis=0)) > 1e-2
    # the up sweep's state at the same speed: a two-period orbit of the same flow
    y2, _ = integrate(model, t[:3], settings, up.state[1])
    assert np.max(np.abs(y2[:, 2] - y2[:, 0]) / scale) < 1e-5
    assert np.max(np.abs(y2[:, 1] - y2[:, 0]) / scale) > 1e-2
