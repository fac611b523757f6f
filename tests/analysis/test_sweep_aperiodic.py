"""Sweep points that are not period-1 or period-2 are classified, and hysteresis is claimed only
between two periodic orbits (gear_dyn.analysis.sweep, gear_dyn.analysis.motion).

Scene 1: the packaged backlash pair with constant mesh stiffness (1e9 N/m) and a 10 um
transmission error, at f_m / f_n = 1.55 and 1.6: heavy separation. Sweeping up, the pair stays
on a period-2 orbit; sweeping down, the sweep starts at 1.6 from the static state, finds no orbit
of one or two mesh periods after settling, and classifies the motion: a stable period-6 orbit,
confirmed by shooting over six mesh periods (before issue 25 this point was reported
``aperiodic``). Up and down are then two coexisting periodic orbits that differ: hysteresis.
Independent check: the flow from the down sweep's state (DOP853 with located contact changes,
a second integrator) returns to it after six mesh periods and not after one, two or three.

Scene 2 (tests/analysis/motion_cases.py): rectangular stiffness 0.5e9 / 1.5e9 N/m, damping ratio
0.02, at f_m / f_n = 1.94 and 1.98: chaos in both directions (positive Lyapunov exponents; every
one of 12 starts perturbed by 1e-13 is chaotic there, while at 2.0 and 2.02 a stable period-8
and period-4 orbit attract about one start in six, so those speeds' label depends on the last
bits of the transient). Up
and down differ, but neither is periodic: no hysteresis, the speeds are reported as aperiodic
with their motion's label (sweep summary and terminal alike). At 2.06..2.1 the same scene has a
stable period-4 orbit, reported as such in both directions.
"""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
from motion_cases import parametric_scene, speed_of

from gear_dyn.analysis.sweep import (
    RPM,
    SweepOptions,
    aperiodic_ranges,
    hysteresis_ranges,
    periodic_response,
    summarize_sweep,
    sweep_columns,
)
from gear_dyn.scene import build_model, parse_scene
from gear_dyn.scene.packaged import scene_path
from gear_dyn.scene.sweep import model_at_speed, sweep_scene
from gear_dyn.solvers import SolverSettings, integrate

RATIOS = (1.55, 1.6)  # f_m / f_n
CHAOS = (1.94, 1.98)


@pytest.fixture(scope="module")
def te_sweep():
    data = tomllib.loads(scene_path("helicopter_tail_backlash").read_text())
    data["stiffness"] = {"method": "rectangular", "single": "1e9 N/m", "double": "1e9 N/m"}
    data["transmission_error"] = {"cos": ["10 um"]}
    scene = parse_scene(data, "constant_stiffness_backlash.toml")
    rpm_n = build_model(scene).natural_frequency * 60 / 23  # f_m = f_n
    return scene, sweep_scene(scene, np.array(RATIOS) * rpm_n * RPM, si=True)


@pytest.fixture(scope="module")
def chaotic_sweep():
    scene = parametric_scene()
    return scene, sweep_scene(scene, [speed_of(scene, r) for r in CHAOS], si=True)


@pytest.mark.slow
def test_period_6_found_where_period_1_and_2_are_not(te_sweep) -> None:
    _scene, res = te_sweep
    up, down = res.curve("up"), res.curve("down")
    assert up.status == ("period-2", "period-2")
    assert down.status == ("period-6", "period-2")
    assert down.orbit_periods.tolist() == [6, 2] and down.motion == ("period-6", "period-2")
    assert periodic_response(up).tolist() == [True, True]
    assert periodic_response(down).tolist() == [True, True]
    # two coexisting stable orbits at 1.6 f_n that differ: that is hysteresis
    assert down.separation[0] > 0.3 > up.separation[1]
    assert abs(down.rms_dte[0] - up.rms_dte[1]) > 0.2 * up.rms_dte[1]
    top = float(up.speed[1] / RPM)
    assert hysteresis_ranges(res) == [[top, top]]
    assert aperiodic_ranges(res) == []


@pytest.mark.slow
def test_down_response_repeats_after_six_periods(te_sweep) -> None:
    scene, res = te_sweep
    up, down = res.curve("up"), res.curve("down")
    model = model_at_speed(scene, float(down.speed[0]))
    scale = np.asarray(model.state_scale, dtype=float)
    t = np.arange(7) / model.mesh_frequency  # 6 mesh periods, sampled once per period
    settings = SolverSettings(method="DOP853", rtol=1e-10)
    y, _ = integrate(model, t, settings, down.state[0])
    x = y / scale[:, None]
    # the sweep's orbit closes to ~100 rtol (1e-6 at the sweep's rtol 1e-8); the second
    # integrator adds ~1e-9 over six periods
    assert np.max(np.abs(x[:, 6] - x[:, 0])) < 1e-5
    assert min(np.max(np.abs(x[:, k] - x[:, 0])) for k in (1, 2, 3)) > 1e-2
    # the up sweep's state at the same speed: a two-period orbit of the same flow
    y2, _ = integrate(model, t[:3], settings, up.state[1])
    assert np.max(np.abs(y2[:, 2] - y2[:, 0]) / scale) < 1e-5
    assert np.max(np.abs(y2[:, 1] - y2[:, 0]) / scale) > 1e-2


def test_chaotic_speeds_are_not_hysteresis(chaotic_sweep) -> None:
    _scene, res = chaotic_sweep
    up, down = res.curve("up"), res.curve("down")
    for c in (up, down):
        assert c.status == ("aperiodic", "aperiodic")
        assert all(m.startswith("chaotic, lambda = ") for m in c.motion)
        assert np.all(c.lyapunov > 3 * c.lyapunov_error) and np.all(c.lyapunov_error > 0)
        assert periodic_response(c).tolist() == [False, False]
    # the directions sample the same chaotic motion differently ...
    assert abs(up.rms_dte[0] - down.rms_dte[1]) > 0.05 * up.rms_dte[0]
    # ... which is no hysteresis
    lo, hi = (float(s / RPM) for s in up.speed)
    assert hysteresis_ranges(res) == []
    assert aperiodic_ranges(res) == [[lo, hi]]
    summary = summarize_sweep(res)
    assert summary["hysteresis_ranges_rpm"] == []
    assert summary["aperiodic_ranges_rpm"] == [[lo, hi]]
    # sweep.json and sweep.csv carry the labels and exponents
    labels = [m["label"] for m in summary["curves"]["up"]["motion"]]
    assert labels == list(up.motion)
    cols = sweep_columns(res)
    assert np.array_equal(cols["lyapunov_1_s"][:2], up.lyapunov)


def test_terminal_summary_says_not_periodic(chaotic_sweep,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    from gear_dyn.cli.sweep import _print_summary

    scene, res = chaotic_sweep
    _print_summary(res, scene, summarize_sweep(res), "none")
    out = capsys.readouterr().out
    assert "hysteresis" not in out
    lo, hi = (round(float(s / RPM)) for s in res.curve("up").speed)
    assert f"no period-1 or period-2 orbit (up): {lo}-{hi} rpm" in out


def test_period_4_is_reported_as_period_4() -> None:
    """Issue 25: where a stable period-4 orbit exists the sweep said "not periodic". On the
    parametric scene at f_m / f_n = 2.06..2.1 both directions now report it (status and
    orbit_periods 4, continued from speed to speed), and its figures are the orbit's: the RMS DTE
    over four mesh periods of a DOP853 run from the sweep's state (rtol 1e-11, a second
    integrator) agrees to 1e-6, and the f_m/4 order carries a large share of the spectrum.

    Each direction's first speed starts from the static state, and from there the motion passes
    through a chaotic transient of some hundreds of mesh periods before it settles on the orbit.
    The length of a chaotic transient hangs on rounding: with the default 100 settling periods
    one machine reported the down sweep's first speed chaotic, another period-4; with 300 it was
    still chaotic on the first, with 1000 period-4 on both. The test settles up to 10 000
    periods, so that what it checks is the sweep's report of the orbit, not the transient's luck."""
    scene = parametric_scene()
    res = sweep_scene(scene, [speed_of(scene, r) for r in (2.06, 2.08, 2.1)], si=True,
                      options=SweepOptions(settle_periods=10_000))
    for c in res.curves:
        assert c.status == ("period-4",) * 3 and c.orbit_periods.tolist() == [4, 4, 4]
        assert c.motion == ("period-4",) * 3 and np.all(c.stable)
        assert np.all(c.spectral_radius < 1.0)
    up = res.curve("up")
    model = model_at_speed(scene, float(up.speed[1]))
    spp = res.settings.samples_per_period
    t = np.arange(4 * spp + 1) / (model.mesh_frequency * spp)
    y, _ = integrate(model, t, SolverSettings(method="DOP853", rtol=1e-11), up.state[1])
    dte = model.outputs(t[:-1], y[:, :-1])["dte"]
    assert float(np.std(dte)) == pytest.approx(up.rms_dte[1], rel=1e-6)
    quarter = int(np.argmin(np.abs(res.orders - 0.25)))
    assert up.spectrum[1, quarter] > 0.1 * np.max(up.spectrum[1])
    assert hysteresis_ranges(res) == [] and aperiodic_ranges(res) == []
