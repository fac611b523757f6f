"""CLI run/demo and the issue-2 bad-scene cases (exit code 2, one line naming the field)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from gear_dyn.cli.app import main
from gear_dyn.scene import load_scene, parse_scene

HELI = Path(__file__).resolve().parents[2] / "examples" / "scenes" / "helicopter_tail.toml"


def test_units_are_parsed_to_si() -> None:
    """'6 mm' -> 0.006 m, '3319 rpm' -> 347.57 rad/s, '22.5 deg' -> 0.3927 rad, '2.07e5 MPa'
    -> 2.07e11 Pa: pint conversions, exact to rounding."""
    s = load_scene(HELI)
    g = s.tables["gear"]
    assert g["module"] == pytest.approx(0.006, rel=1e-14)
    assert g["pressure_angle"] == pytest.approx(math.radians(22.5), rel=1e-14)
    assert g["youngs_modulus"] == pytest.approx(2.07e11, rel=1e-14)
    assert s.tables["operating"]["speed"] == pytest.approx(3319 * 2 * math.pi / 60, rel=1e-14)


def test_demo_writes_plots_csv_and_summary(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    out = tmp_path / "demo"
    assert main(["demo", "--out", str(out)]) == 0
    names = sorted(p.name for p in out.iterdir())
    assert names == ["spectrum.png", "summary.json", "time_history.png", "timeseries.csv"]
    s = json.loads((out / "summary.json").read_text())
    for key in ("mesh_frequency_hz", "output_speed_rpm", "contact_ratio",
                "mean_mesh_stiffness_n_per_m", "static_transmission_error_m", "dynamic_factor",
                "rms_dte_m"):
        assert isinstance(s[key], float)
    for key in ("method", "rtol", "atol", "nfev", "run_time_s"):
        assert key in s["solver"]
    # Jiang et al. (2018), Table 1 kinematics (exact fractions)
    assert s["mesh_frequency_hz"] == pytest.approx(23 * 3319 / 60, rel=1e-12)
    assert s["output_speed_rpm"] == pytest.approx(3319 * 23 / 64, rel=1e-12)
    # W / k_m is the static transmission error
    assert s["static_transmission_error_m"] == pytest.approx(
        s["static_load_n"] / s["mean_mesh_stiffness_n_per_m"], rel=1e-12)
    assert "time_history.png" in capsys.readouterr().out
    # the PNGs are real images
    assert (out / "spectrum.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


BAD = [
    ("module = \"6 mm\"", "module = \"-6 mm\"", "gear.module"),
    ("teeth_pinion = 23", "teeth_pinion = 0", "gear.teeth_pinion"),
    ("module = \"6 mm\"", "module = \"6 kg\"", "gear.module"),
    ("face_width = \"50 mm\"", "face_width = \"50 mm\"\nface_widht = 3", "face_widht"),
    ("torque = \"1474.4 N*m\"", "torque = \"lots\"", "operating.torque"),
    ("teeth_pinion = 23", "teeth_pinion = 10", "undercut"),
]


@pytest.mark.parametrize(("old", "new", "needle"), BAD)
def test_bad_scene_values_exit_2_with_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture, old: str, new: str, needle: str
) -> None:
    text = HELI.read_text()
    assert old in text
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace(old, new))
    out = tmp_path / "out"
    code = main(["run", str(bad), "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and "Traceback" not in err
    assert needle in err
    assert not out.exists()


def test_unknown_key_suggests_the_right_one() -> None:
    with pytest.raises(ValueError, match="did you mean 'face_width'"):
        parse_scene({"gear": {"teeth_pinion": 20, "teeth_gear": 40, "module": 0.002,
                              "face_widht": 0.01}, "operating": {"speed": 100, "torque": 1}})


def test_run_command_summary_states_method(tmp_path: Path) -> None:
    out = tmp_path / "run"
    assert main(["run", str(HELI), "--out", str(out), "--method", "LSODA", "--periods", "20",
                 "--rtol", "1e-6"]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["solver"]["method"] == "LSODA"
    assert s["solver"]["rtol"] == 1e-6


def test_speed_in_hz_is_refused_not_read_as_rad_per_s() -> None:
    """pint converts '10 Hz' to 10 rad/s (radian is dimensionless): 2 pi off for a shaft speed.
    The loader refuses it; '2 turn/s' is 4 pi rad/s exactly."""
    base = {"gear": {"teeth_pinion": 20, "teeth_gear": 40, "module": "2 mm",
                     "face_width": "10 mm"},
            "operating": {"speed": "10 Hz", "torque": "1 N*m"}}
    with pytest.raises(ValueError, match="operating.speed.*ambiguous"):
        parse_scene(base)
    base["operating"]["speed"] = "2 turn/s"
    assert parse_scene(base).tables["operating"]["speed"] == pytest.approx(4 * math.pi, rel=1e-14)
