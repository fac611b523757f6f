"""Speed sweeps (gear_dyn.analysis.sweep) and the ``gear-dyn sweep`` command.

References: run_scene at the same speed (a second method); the closed-form frequency response of
the constant-stiffness oscillator driven by a transmission error; coexisting stable orbits
checked by transient integration (hysteresis); the Dask executor against the local one.
"""

from __future__ import annotations

import concurrent.futures as cf
import csv
import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from gear_dyn.analysis.stability import flow_on_grid
from gear_dyn.analysis.sweep import (
    RPM,
    SweepOptions,
    hysteresis_ranges,
    jumps,
)
from gear_dyn.cli.app import main
from gear_dyn.errors import InputError
from gear_dyn.scene import build_model, load_scene, parse_scene, run_scene
from gear_dyn.scene.operating import parse_speed_range
from gear_dyn.scene.sweep import model_at_speed, sweep_scene
from gear_dyn.solvers import SolverSettings, integrate, time_grid

SCENES = Path(__file__).resolve().parents[2] / "gear_dyn" / "scenes"
TAIL = SCENES / "helicopter_tail.toml"
BACKLASH = SCENES / "helicopter_tail_backlash.toml"


def test_model_at_speed_is_run_scene_model() -> None:
    scene = load_scene(TAIL)
    for rpm in (800.0, 3319.0, 12345.0):
        w = rpm * RPM
        tables = {**scene.tables, "operating": {**scene.tables["operating"], "speed": w}}
        ref = build_model(replace(scene, tables=tables))
        got = model_at_speed(scene, w)
        for name in ("mesh_frequency", "mass", "damping", "static_load", "mean_stiffness"):
            # same expressions, so bitwise equal
            assert getattr(got, name) == getattr(ref, name)


def test_sweep_point_equals_run_scene() -> None:
    scene = load_scene(TAIL)
    w0 = scene.tables["operating"]["speed"]
    res = sweep_scene(scene, [w0 * 0.7, w0], si=True, workers=1)
    run = run_scene(scene)
    c = res.curves[0]
    # steady state (monodromy) vs 200-period exact transient: the transient's remainder is
    # rho^100 ~ 1e-38 at the window start, so only rounding separates them. run_scene's window
    # holds phase 0 at both ends; the sweep counts whole periods, so drop one end for RMS/mean
    x = run.outputs["dte"][run.steady][1:]
    assert c.peak_force_ratio[1] == pytest.approx(run.peak_force_ratio, rel=1e-9)
    # K_dyn: the same quasi-static reference (same model at f_n / 64, same settings) divides both
    assert c.dynamic_factor[1] == pytest.approx(run.dynamic_factor, rel=1e-9)
    assert res.stiffness_jump_factor == run.extra["stiffness_jump_factor"]
    assert c.ptp_dte[1] == pytest.approx(run.ptp_dte, rel=1e-9)
    assert c.rms_dte[1] == pytest.approx(np.std(x), rel=1e-9)
    assert c.mean_dte[1] == pytest.approx(np.mean(x), rel=1e-9)
    assert c.mesh_frequency[1] == run.mesh_frequency
    trans = sweep_scene(scene, [w0 * 0.7, w0], si=True, workers=1,
                        options=SweepOptions(method="transient"))
    for name in ("dynamic_factor", "peak_force_ratio", "rms_dte", "ptp_dte"):
        assert np.allclose(getattr(trans.curves[0], name), getattr(c, name), rtol=1e-9)
    # a second method at 0.7 w0: DOP853 at rtol 1e-12 (not the matrix exponentials of both paths
    # above) over 200 periods, the last 100 measured; its error ~1e-11 of the static deflection
    # and the transient's remainder rho^100 < 1e-30: tolerance 1e-7 leaves 1e4 of margin
    model = model_at_speed(scene, w0 * 0.7)
    t = time_grid(model.mesh_frequency, 200 / model.mesh_frequency, 64)
    y, _ = integrate(model, t, SolverSettings(method="DOP853", rtol=1e-12))
    out = model.outputs(t, y)
    win = slice(t.size - 1 - 100 * 64, t.size - 1)
    assert c.peak_force_ratio[0] == pytest.approx(np.max(out["mesh_force"][win])
                                                / model.static_load, rel=1e-7)
    assert c.rms_dte[0] == pytest.approx(np.std(out["dte"][win]), rel=1e-7)
    assert c.ptp_dte[0] == pytest.approx(np.ptp(out["dte"][win]), rel=1e-7)


def _te_scene(zeta: float, amp: float) -> dict:
    return {
        "gear": {"teeth_pinion": 23, "teeth_gear": 64, "module": "6 mm",
                 "pressure_angle": "22.5 deg", "face_width": "50 mm"},
        "operating": {"speed": "3000 rpm", "torque": "1000 N*m"},
        "stiffness": {"method": "rectangular", "single": "1e9 N/m", "double": "1e9 N/m"},
        "damping": {"ratio": zeta},
        "transmission_error": {"cos": [f"{amp} m"]},
        "solver": {"rtol": 1e-10},
    }


def test_linear_resonance_at_natural_frequency() -> None:
    zeta, amp = 0.02, 2e-6
    scene = parse_scene(_te_scene(zeta, amp))
    model = build_model(scene)
    fn = model.natural_frequency
    rpm_n = fn * 60 / 23  # speed with f_m = f_n
    speeds = np.linspace(0.9, 1.1, 41) * rpm_n * RPM
    res = sweep_scene(scene, speeds, si=True, workers=1)
    c = res.curves[0]
    assert res.natural_frequency == pytest.approx(math.sqrt(1e9 / model.mass) / (2 * math.pi))
    r = c.mesh_frequency / fn
    # base excitation through k e + c e': |X / e| = |1 + 2i zeta r| / |1 - r^2 + 2i zeta r|;
    # x is then a pure harmonic, RMS = amplitude / sqrt(2)
    h = np.abs((1 + 2j * zeta * r) / (1 - r**2 + 2j * zeta * r))
    # variational one-period map at rtol 1e-10, orbit sampled at 64 points per period
    assert np.allclose(c.rms_dte, amp * h / math.sqrt(2), rtol=1e-6)
    i = int(np.argmax(c.rms_dte))
    r_peak = math.sqrt(math.sqrt(1 + 8 * zeta**2) - 1) / (2 * zeta)  # closed-form maximum
    assert abs(r_peak - 1) < zeta**2  # the peak sits at f_n up to O(zeta^2)
    step = r[1] - r[0]
    assert abs(r[i] - 1) <= step / 2 + zeta**2
    # constant stiffness: no parametric excitation, multipliers exp(-zeta w_n T) in modulus
    assert np.allclose(c.spectral_radius, np.exp(-zeta * 2 * math.pi * fn / c.mesh_frequency),
                       rtol=1e-8)
    # the first mesh harmonic of the spectrum carries the whole response
    k1 = int(np.argmin(np.abs(res.orders - 1.0)))
    assert np.allclose(c.spectrum[:, k1], amp * h, rtol=1e-6)


def test_parametric_instability_flagged_not_integrated() -> None:
    scene = load_scene(TAIL)
    speeds = np.array([12000.0, 15000.0]) * RPM  # f_m / f_n = 1.58 (stable) and 1.97 (tongue)
    for method in ("steady", "transient"):
        c = sweep_scene(scene, speeds, si=True, workers=1,
                        options=SweepOptions(method=method)).curves[0]
        assert c.status[0] != "unstable" and c.status[1] == "unstable"
        assert c.spectral_radius[1] > 1 and np.isnan(c.rms_dte[1])
        assert np.isfinite(c.rms_dte[0])


@pytest.fixture(scope="module")
def backlash_sweep():
    scene = load_scene(BACKLASH)
    speeds = np.arange(4600.0, 6401.0, 200.0) * RPM
    return scene, sweep_scene(scene, speeds, si=True, workers=1)


def test_backlash_hysteresis(backlash_sweep) -> None:
    scene, res = backlash_sweep
    assert res.nonlinear and [c.direction for c in res.curves] == ["up", "down"]
    up, down = res.curve("up"), res.curve("down")
    assert np.array_equal(up.speed, down.speed[::-1])
    ranges = hysteresis_ranges(res)
    assert ranges, "sweep up and sweep down must differ somewhere"
    # softening (contact loss): the upper branch reaches further down in speed, so the jump up
    # (sweep up) happens at a higher speed than the jump down (sweep down)
    # (jumps from the orbits: sweeping down there are two, off the top branch at its fold near
    # 5204 rpm onto a lower separating branch, then off that one at 4893 rpm into contact)
    j_up, j_down = jumps(up), jumps(down)
    assert [j["kind"] for j in j_up] == ["fold"] and [j["kind"] for j in j_down] == ["fold"] * 2
    assert j_up[0]["rms_dte_after_m"] > 1.5 * j_up[0]["rms_dte_before_m"]
    assert j_down[-1]["rms_dte_after_m"] < j_down[-1]["rms_dte_before_m"] / 1.5
    assert j_up[0]["from_rpm"] > j_down[-1]["from_rpm"]
    # at a speed inside the hysteresis range both orbits are stable and both persist: start a
    # transient on each (perturbed by 1 %) and it must come back to its own orbit
    rpm = 5400.0
    assert ranges[0][0] <= rpm <= ranges[0][1]
    iu = int(np.argmin(np.abs(up.speed / RPM - rpm)))
    id_ = int(np.argmin(np.abs(down.speed / RPM - rpm)))
    assert up.rms_dte[iu] < 0.5 * down.rms_dte[id_]
    assert up.spectral_radius[iu] < 1 and down.spectral_radius[id_] < 1
    assert up.separation[iu] == 0 and down.separation[id_] > 0.3
    model = model_at_speed(scene, rpm * RPM)
    spp = res.settings.samples_per_period  # the sweep's sampling, so RMS values are comparable
    t = np.arange(150 * spp + 1) / (model.mesh_frequency * spp)
    for curve, i in ((up, iu), (down, id_)):
        y = flow_on_grid(model, 1.01 * curve.state[i], t, 1e-9)
        x = y[0, -spp:]
        # the settled transient (150 periods, rho^150 < 1e-30) against the sweep's orbit:
        # DOP853 at rtol 1e-9 here, 1e-8 in the sweep
        assert float(np.std(x)) == pytest.approx(curve.rms_dte[i], rel=1e-6)
        # and it is still the orbit the sweep found (not the other branch)
        assert np.allclose(y[:, -1], curve.state[i], rtol=1e-5, atol=1e-6 * model.state_scale)


def test_backlash_markers(backlash_sweep) -> None:
    _scene, res = backlash_sweep
    down = res.curve("down")
    # the upper branch separates the teeth; its largest swings reach the back flanks
    assert np.nanmax(down.separation) > 0.5
    assert np.nanmax(down.backside) > 0
    assert all(s in ("periodic", "settled") for c in res.curves for s in c.status)


def test_dask_and_serial_identical(tmp_path: Path) -> None:
    from distributed import Client, LocalCluster

    tail = load_scene(TAIL)
    bl = load_scene(BACKLASH)
    sp_tail = np.linspace(2000, 16000, 12) * RPM
    sp_bl = np.array([5000.0, 6000.0, 6400.0]) * RPM
    serial = [sweep_scene(tail, sp_tail, si=True, block=3),
              sweep_scene(bl, sp_bl, si=True, block=2)]
    with LocalCluster(n_workers=1, processes=False, threads_per_worker=2,
                      dashboard_address=":0") as cluster, Client(cluster) as client:
        ex = client.get_executor()
        remote = [sweep_scene(tail, sp_tail, si=True, executor=ex, block=3),
                  sweep_scene(bl, sp_bl, si=True, executor=ex, block=2)]
        # the command line reaches the same scheduler by its address
        code = main(["sweep", str(TAIL), "--speeds", "2000 rpm:4000 rpm:3", "--out",
                     str(tmp_path / "d"), "--dask", cluster.scheduler_address, "--chart", "none",
                     "--no-progress"])
        assert code == 0
        assert json.loads((tmp_path / "d" / "sweep.json").read_text())["executor"] == (
            "ClientExecutor")
    assert remote[0].executor == "ClientExecutor"
    assert serial[0].executor == "serial"
    for a, b in zip(serial, remote, strict=True):
        for ca, cb in zip(a.curves, b.curves, strict=True):
            for name in ("speed", "dynamic_factor", "rms_dte", "ptp_dte", "spectral_radius",
                         "separation", "backside", "spectrum"):
                # the same code on the same inputs: bitwise equal (NaN where unstable)
                assert np.array_equal(getattr(ca, name), getattr(cb, name), equal_nan=True)
            assert ca.status == cb.status


def test_progress_and_thread_executor() -> None:
    scene = load_scene(TAIL)
    seen: list[tuple[int, int]] = []
    with cf.ThreadPoolExecutor(2) as ex:
        res = sweep_scene(scene, np.linspace(1000, 3000, 10) * RPM, si=True, executor=ex, block=4,
                          progress=lambda d, n: seen.append((d, n)))
    # (0, total) at the start (a bar from the first second), then one call per finished
    # block (4, 4 and 2 speeds), in sweep order (the executor's map)
    assert seen == [(0, 10), (4, 10), (8, 10), (10, 10)]
    assert res.curves[0].speed.size == 10 and res.executor == "ThreadPoolExecutor"


def test_parse_speed_range() -> None:
    assert np.allclose(parse_speed_range("500 rpm:6000 rpm:12") / RPM, np.linspace(500, 6000, 12))
    assert np.allclose(parse_speed_range("500 rpm:6000 rpm:3") / RPM, [500, 3250, 6000])
    assert np.allclose(parse_speed_range("10 turn/s:40 rad/s:2"), [20 * math.pi, 40])
    for bad, msg in (("500 rpm:6000 rpm", "START:STOP:N"),
                     ("500 rpm:6000 rpm:x", "whole number"), ("500 rpm:6000 rpm:1", "N"),
                     ("-5 rpm:6000 rpm:4", "out of range"), ("5 m:6000 rpm:4", "wrong unit"),
                     ("10 Hz:20 Hz:3", "turn/s"),
                     # a plain number is refused (one rule with the scene files)
                     ("1500:3000:10", r'START = 1500: give a unit, e\.g\. "1500 rpm" '
                                      r'\(or "1500 rad/s"\)'),
                     ("1500 rpm:3000:10", r'STOP = 3000: give a unit')):
        with pytest.raises(InputError, match=msg):
            parse_speed_range(bad)


def test_sweep_bad_input() -> None:
    scene = load_scene(TAIL)
    with pytest.raises(InputError, match="direction"):
        sweep_scene(scene, [100.0], si=True, direction="sideways", workers=1)
    with pytest.raises(InputError, match="sweep method"):
        SweepOptions(method="guess")
    with pytest.raises(InputError, match="speed"):
        sweep_scene(scene, [0.0, 100.0], si=True, workers=1)
    with pytest.raises(InputError, match="workers = 0"):
        sweep_scene(scene, [100.0], si=True, workers=0)
    with cf.ThreadPoolExecutor(1) as ex, pytest.raises(InputError, match="not both"):
        sweep_scene(scene, [100.0], si=True, workers=2, executor=ex)
    with pytest.raises(InputError, match="unknown keyword 'min_parallel_s'"):
        sweep_scene(scene, [100.0], si=True, min_parallel_s=0)


def test_cli_sweep(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "sw"
    code = main(["sweep", str(TAIL), "--speeds", "3000 rpm:16000 rpm:14", "--out", str(out),
                 "--workers", "1", "--no-progress", "--chart", "both"])
    assert code == 0
    for name in ("response.png", "waterfall.png", "stability.png", "sweep.csv", "spectra.csv",
                 "sweep.json"):
        assert (out / name).stat().st_size > 0
    with (out / "sweep.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 14
    assert float(rows[0]["speed_rpm"]) == pytest.approx(3000)
    summary = json.loads((out / "sweep.json").read_text())
    assert summary["n_speeds"] == 14
    # the 15000 rpm point lies in the principal tongue (f_m / f_n = 1.97)
    assert any(a <= 15000 <= b for a, b in summary["curves"]["up"]["unstable_ranges_rpm"])
    assert summary["resonance_speed_rpm"] == pytest.approx(
        summary["natural_frequency_hz"] * 60 / 23, rel=1e-12)
    assert "parametric instability" in capsys.readouterr().out
    code = main(["sweep", str(TAIL), "--speeds", "3000 rpm:oops:4", "--out", str(out)])
    assert code == 2
    assert "--speeds STOP" in capsys.readouterr().err


def test_backlash_inside_parametric_tongue_period_two() -> None:
    # linear, the pair is unstable at 15000 rpm (f_m / f_n = 1.97); with backlash the response
    # is bounded by contact loss and settles on a period-2 orbit (subharmonic f_m / 2)
    scene = load_scene(BACKLASH)
    res = sweep_scene(scene, [15000 * RPM], si=True, workers=1, direction="up")
    c = res.curves[0]
    assert c.status == ("period-2",) and c.orbit_periods[0] == 2 and c.stable[0]
    half = int(np.argmin(np.abs(res.orders - 0.5)))
    one = int(np.argmin(np.abs(res.orders - 1.0)))
    assert c.spectrum[0, half] > 3 * c.spectrum[0, one]  # the subharmonic dominates
    # independent check: a transient started 1 % off the orbit returns to it after 200
    # periods, repeats after two mesh periods and not after one
    model = model_at_speed(scene, 15000 * RPM)
    spp = 64
    t = np.arange(200 * spp + 1) / (model.mesh_frequency * spp)
    y = flow_on_grid(model, 1.01 * c.state[0], t, 1e-9)
    scale = model.state_scale[:, None]
    assert np.max(np.abs(y[:, -1] - c.state[0]) / model.state_scale) < 1e-5
    assert np.max(np.abs(y[:, -1] - y[:, -1 - 2 * spp]) / model.state_scale) < 1e-6
    assert np.max(np.abs(y[:, -spp:] - y[:, -2 * spp:-spp]) / scale) > 0.1


def test_cli_where_the_sweep_runs_flags(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                        monkeypatch: pytest.MonkeyPatch) -> None:
    out = str(tmp_path / "o")
    base = ["sweep", str(TAIL), "--speeds", "3000 rpm:4000 rpm:3", "--out", out, "--no-progress"]
    # --workers and --dask exclude each other; the old threshold flag is gone: usage errors
    for extra, said in ((["--workers", "2", "--dask", "tcp://h:8786"], "not allowed with"),
                        (["--min-parallel", "0"], "unrecognized arguments")):
        assert main([*base, *extra]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and said in err
    assert main([*base, "--workers", "0"]) == 2
    assert "--workers = 0: valid range 1..4096" in capsys.readouterr().err
    # without the optional dask extra: one line naming what to install
    monkeypatch.setitem(__import__("sys").modules, "distributed", None)
    assert main([*base, "--dask", "tcp://h:8786"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and 'pip install "gear_dyn[dask]"' in err
    assert not (tmp_path / "o").exists()
