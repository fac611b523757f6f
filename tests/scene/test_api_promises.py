"""The Python API keeps the CLI's promises: units on speeds and torques, plain numbers refused
(unless ``si=True``), unknown keywords refused with a did-you-mean, sweeps in ``gd`` with a short
repr and plot methods, ``gear-dyn run --speed/--torque``."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
from matplotlib.figure import Figure

import gear_dyn as gd
from gear_dyn.cli.app import main
from gear_dyn.geometry import mesh_frequency
from gear_dyn.scene.build import build_pair

RPM = 2 * math.pi / 60


@pytest.fixture(scope="module")
def scene() -> object:
    return gd.load_scene("helicopter_tail")


def test_run_scene_takes_speed_and_torque_with_units(scene: object) -> None:
    res = gd.run_scene(scene, speed="6000 rpm", torque="200 Nm", periods=20)
    pair = build_pair(scene)
    # the mesh frequency follows the speed given: f_m = z1 n / 60
    assert res.mesh_frequency == pytest.approx(mesh_frequency(pair, 6000 * RPM), rel=1e-12)
    assert res.mesh_frequency == pytest.approx(23 * 6000 / 60, rel=1e-12)
    # W = T1 / r_b1 with the torque given
    assert res.static_load == pytest.approx(200.0 / pair.rb1, rel=1e-12)
    assert res.extra["input_speed_rpm"] == pytest.approx(6000.0, rel=1e-12)
    # the same run in SI numbers, said so
    si = gd.run_scene(scene, speed=6000 * RPM, torque=200.0, si=True, periods=20)
    assert si.dynamic_factor == pytest.approx(res.dynamic_factor, rel=1e-12)


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"foo": 1}, r"run_scene: unknown keyword 'foo' \(valid: speed, torque, si,"),
    ({"sped": "1 rpm"}, r"unknown keyword 'sped'; did you mean 'speed'\?"),
    ({"perods": 3}, r"unknown keyword 'perods'; did you mean 'periods'\?"),
    ({"speed": 6000}, r'run_scene speed = 6000: give a unit, e\.g\. "6000 rpm".*si=True'),
    ({"torque": 200.0}, r'run_scene torque = 200: give a unit, e\.g\. "200 N\*m".*si=True'),
    ({"speed": "100 Hz"}, r"run_scene speed = '100 Hz': Hz is ambiguous"),
    ({"speed": "5 mm"}, r"run_scene speed = '5 mm': wrong unit"),
    ({"speed": "-5 rpm"}, r"run_scene speed = '-5 rpm' is out of range"),
])
def test_run_scene_refuses_what_a_scene_refuses(scene: object, kwargs: dict[str, object],
                                                match: str) -> None:
    with pytest.raises(gd.InputError, match=match):
        gd.run_scene(scene, **kwargs)


def test_sweep_scene_is_in_gd_and_takes_units(scene: object) -> None:
    assert {"sweep_scene", "SweepResult", "SweepOptions"} <= set(gd.__all__)
    by_text = gd.sweep_scene(scene, ["4000 rpm", "6275 rpm"])
    by_range = gd.sweep_scene(scene, "4000 rpm:6275 rpm:2")
    by_si = gd.sweep_scene(scene, np.array([4000.0, 6275.0]) * RPM, si=True)
    assert isinstance(by_text, gd.SweepResult)
    for other in (by_range, by_si):
        np.testing.assert_allclose(other.curves[0].speed, by_text.curves[0].speed, rtol=1e-12)
        np.testing.assert_array_equal(other.curves[0].dynamic_factor,
                                      by_text.curves[0].dynamic_factor)
    # 6275 rpm is 6275 rpm, not 6275 rad/s (59 922 rpm)
    assert by_text.curves[0].speed[1] == pytest.approx(6275 * RPM, rel=1e-12)


@pytest.mark.parametrize(("speeds", "kwargs", "match"), [
    ([4000, 6275], {}, r"sweep_scene speeds: plain numbers \(4000, \.\.\.\) have no unit; give "
                       r"strings with units, e\.g\. \['4000 rpm', \.\.\.\].*si=True"),
    (np.array([400.0, 600.0]), {}, r"plain numbers \(400\.0, \.\.\.\).*si=True"),
    (["4000 rpm", "100 Hz"], {}, r"sweep_scene speeds\[1\] = '100 Hz': Hz is ambiguous"),
    ([], {}, r"sweep_scene speeds: empty"),
    (["4000 rpm"], {"workres": 2}, r"unknown keyword 'workres'; did you mean 'workers'\?"),
])
def test_sweep_scene_refuses_plain_numbers(scene: object, speeds: object,
                                           kwargs: dict[str, object], match: str) -> None:
    with pytest.raises(gd.InputError, match=match):
        gd.sweep_scene(scene, speeds, **kwargs)


def test_sweep_repr_is_short_and_states_the_peak(scene: object) -> None:
    res = gd.sweep_scene(scene, "3000 rpm:9000 rpm:25")
    text = repr(res)
    assert len(text.splitlines()) <= 3 and len(text) < 300
    c = res.curves[0]
    i = int(np.nanargmax(c.dynamic_factor))
    assert f"max dynamic factor {c.dynamic_factor[i]:.4f}" in text
    assert f"at {c.speed[i] / RPM:.0f} rpm (up)" in text
    assert "25 speeds 3000-9000 rpm" in text and "'helicopter_tail'" in text


def test_sweep_plot_methods_take_ax(scene: object) -> None:
    res = gd.sweep_scene(scene, "3000 rpm:9000 rpm:9")
    assert isinstance(res.plot.response(), Figure)
    fig = Figure()
    axes = fig.subplots(3, 1)
    assert res.plot.response(ax=axes) is fig
    assert all(a.lines for a in axes)
    # the caller's figure gets no title
    assert fig._suptitle is None


def test_time_plot_takes_one_axes_per_panel_and_leaves_the_figure_alone(scene: object) -> None:
    res = gd.run_scene(scene, periods=20)
    fig = Figure()
    grid = fig.subplots(2, 2)
    # one row of a 2 x 2 grid: the whole run's DTE and force, nothing else touched
    assert res.plot.time(ax=grid[0, :]) is fig
    assert grid[0, 0].lines and grid[0, 1].lines
    assert not grid[1, 0].lines and not grid[1, 1].lines
    assert fig._suptitle is None and not any(a.get_title() for a in fig.axes)
    fig2 = Figure()
    ax = fig2.subplots()
    res.plot.spectrum(ax=ax)
    assert fig2._suptitle is None and not ax.get_title()
    with pytest.raises(ValueError, match=r"expected 2 Axes \(whole run: DTE, force\) or 4"):
        res.plot.time(ax=fig.subplots(1, 3))


def test_cli_run_speed_and_torque_flags(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "r"
    assert main(["run", "helicopter_tail", "--out", str(out), "--speed", "6000 rpm",
                 "--torque", "200 Nm", "--periods", "20"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["input_speed_rpm"] == pytest.approx(6000.0, rel=1e-12)
    assert summary["mesh_frequency_hz"] == pytest.approx(2300.0, rel=1e-12)
    text = capsys.readouterr().out
    assert f"f_n = {summary['natural_frequency_hz']:.0f} Hz" in text.splitlines()[0]
    for flag, value, match in (
            ("--speed", "6000", r'--speed = 6000: give a unit, e\.g\. "6000 rpm"'),
            ("--torque", "5 m", r"--torque = '5 m': wrong unit")):
        assert main(["run", "helicopter_tail", "--out", str(tmp_path / "x"), flag, value]) == 2
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1
        assert re.search(match, err), err
