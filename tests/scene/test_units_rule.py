"""One unit rule for scenes, CLI options and API strings: a dimensional quantity needs its unit."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from gear_dyn.cli import main
from gear_dyn.errors import InputError, SceneError
from gear_dyn.scene import parse_scene
from gear_dyn.scene.operating import parse_speed_range
from gear_dyn.units import parse_quantity

BASE = {
    "gear": {"teeth_pinion": 23, "teeth_gear": 64, "module": "6 mm", "face_width": "50 mm"},
    "operating": {"speed": "3319 rpm", "torque": "1474.4 N*m"},
}


def _with(table: str, key: str, value: object) -> dict:
    return {**BASE, table: {**BASE.get(table, {}), key: value}}


@pytest.mark.parametrize(("table", "key", "value", "message"), [
    ("operating", "speed", 1500, 'operating.speed = 1500: give a unit, e.g. "1500 rpm" '
                                 '(or "1500 rad/s")'),
    ("operating", "speed", "1500", 'operating.speed = 1500: give a unit, e.g. "1500 rpm"'),
    ("operating", "torque", 200, 'operating.torque = 200: give a unit, e.g. "200 N*m"'),
    ("gear", "pressure_angle", 20, 'gear.pressure_angle = 20: give a unit, e.g. "20 deg" '
                                   '(or "20 rad")'),
    ("gear", "module", 6, 'gear.module = 6: give a unit, e.g. "6 mm"'),
    ("gear", "youngs_modulus", 2.07e11, 'gear.youngs_modulus = 2.07e+11: give a unit, e.g. '
                                        '"2.07e+11 Pa"'),
])
def test_plain_number_in_a_dimensional_key_is_refused(table: str, key: str, value: object,
                                                      message: str) -> None:
    with pytest.raises(SceneError) as info:
        parse_scene(_with(table, key, value), "s.toml")
    assert str(info.value).startswith(f"s.toml: {message}")


def test_dimensionless_keys_and_zero_stay_plain() -> None:
    sc = parse_scene({**BASE, "gear": {**BASE["gear"], "poisson": 0.29, "helix_angle": 0,
                                       "profile_shift_pinion": 0.2},
                      "damping": {"ratio": 0.05}})
    assert sc.tables["gear"]["helix_angle"] == 0.0
    assert sc.tables["gear"]["poisson"] == 0.29


@pytest.mark.parametrize("text", ["200 Nm", "200 N*m", "0.2 kNm", "200 N.m", "200 N·m",
                                  "200 N m"])
def test_nm_is_newton_metre_in_torque_keys(text: str) -> None:
    sc = parse_scene(_with("operating", "torque", text))
    assert sc.tables["operating"]["torque"] == pytest.approx(200.0, rel=1e-12)


def test_nm_is_not_a_length_anywhere() -> None:
    # pint alone reads Nm as nanometre; outside torque keys it is refused, never 3 nm
    with pytest.raises(InputError, match="wrong unit"):
        parse_quantity("3 Nm", "m", "gear.module", "0 < x <= 1 m")


def test_speed_range_follows_the_same_rule() -> None:
    with pytest.raises(InputError, match=r'START = 1500: give a unit, e\.g\. "1500 rpm" '
                                         r'\(or "1500 rad/s"\)'):
        parse_speed_range("1500:3000:10")
    assert parse_speed_range("1500 rpm:3000 rpm:2")[0] == pytest.approx(50 * math.pi)


def test_cli_refuses_plain_numbers_with_exit_2(tmp_path: Path,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    scene = tmp_path / "plain.toml"
    scene.write_text('[gear]\nteeth_pinion = 23\nteeth_gear = 64\nmodule = "6 mm"\n'
                     'face_width = "50 mm"\n[operating]\nspeed = 1500\ntorque = "200 Nm"\n')
    assert main(["run", str(scene), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert 'operating.speed = 1500: give a unit, e.g. "1500 rpm" (or "1500 rad/s")' in err
    ok = tmp_path / "ok.toml"
    ok.write_text(scene.read_text().replace("speed = 1500", 'speed = "1500 rpm"'))
    assert main(["sweep", str(ok), "--speeds", "1500:3000:10", "--out",
                 str(tmp_path / "s")]) == 2
    assert 'give a unit, e.g. "1500 rpm"' in capsys.readouterr().err
