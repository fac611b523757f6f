"""The stiffness a scene's pair gets by default, said on the terminal, and the spread between
methods explained by ``gear-dyn stiffness``."""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import pytest

from gear_dyn.cli.app import main
from gear_dyn.scene import build_pair, scene_stiffness
from gear_dyn.scene.build import scene_facts
from gear_dyn.scene.loader import parse_scene
from gear_dyn.stiffness import build_stiffness, iso6336_stiffness, mean_contact_line_length

RAIL = """
[scene]
name = "rail"
[gear]
teeth_pinion = 23
teeth_gear = 79
module = "6 mm"
pressure_angle = "20 deg"
helix_angle = "20 deg"
face_width = "70 mm"
profile_shift_pinion = 0.3
profile_shift_gear = -0.1
[operating]
speed = "4000 rpm"
torque = "2000 N*m"
[solver]
periods = 20
"""


def _rail(tmp_path: Path, extra: str = "") -> Path:
    path = tmp_path / "rail.toml"
    path.write_text(RAIL + extra)
    return path


def test_helical_scene_without_stiffness_table_gets_contact_line() -> None:
    scene = parse_scene(tomllib.loads(RAIL), "rail")
    pair = build_pair(scene)
    k = scene_stiffness(scene, pair)
    assert k.name == "contact_line"
    assert k.mean == pytest.approx(build_stiffness(pair, "contact_line").mean, rel=1e-12)
    facts = scene_facts(scene)
    assert facts["stiffness_method"] == "contact_line"
    assert facts["stiffness_choice"].startswith(
        "contact_line (helical pair, eps_beta = 1.27: contact-line length; set [stiffness]")
    spur = parse_scene(tomllib.loads(RAIL.replace('helix_angle = "20 deg"', "")), "spur")
    assert scene_stiffness(spur, build_pair(spur)).name == "iso6336"
    # a [stiffness] table with options but no method also takes the pair's default
    opts = parse_scene(tomllib.loads(RAIL + '[stiffness]\nper_length = "14 N/(mm*um)"\n'), "o")
    k = scene_stiffness(opts, pair)
    assert k.name == "contact_line"
    assert k.mean == pytest.approx(14e9 * mean_contact_line_length(pair), rel=1e-9)


def test_run_says_which_stiffness_and_why(tmp_path: Path,
                                          capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", str(_rail(tmp_path)), "--out", str(tmp_path / "o")]) == 0
    out = capsys.readouterr().out
    assert ("  stiffness: contact_line (helical pair, eps_beta = 1.27: contact-line length; set "
            "[stiffness] method to override)") in out
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert summary["stiffness_method"] == "contact_line"
    # given explicitly, the spur wave is kept and called what it is
    path = _rail(tmp_path, '[stiffness]\nmethod = "iso6336"\n')
    assert main(["run", str(path), "--out", str(tmp_path / "o2")]) == 0
    assert ("stiffness: iso6336 ([stiffness] method, as given; a spur wave for a helical pair"
            in capsys.readouterr().out)


def test_stiffness_command_explains_the_spread(tmp_path: Path,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    # eps_alpha and eps_beta printed; per method the mean, its ratio to ISO 6336-1 c_gamma b
    # (the hand-checked iso6336_stiffness) and what it includes and leaves out.
    path = _rail(tmp_path)
    assert main(["stiffness", str(path), "--out", str(tmp_path / "o"), "--quiet"]) == 0
    out = capsys.readouterr().out
    pair = build_pair(parse_scene(tomllib.loads(RAIL), "rail"))
    assert f"eps_alpha = {pair.contact_ratio:.4f}, eps_beta = {pair.overlap_ratio:.4f}" in out
    rep = json.loads((tmp_path / "o" / "stiffness.json").read_text())
    iso = iso6336_stiffness(pair).k_mesh
    assert list(rep["methods"]) == ["contact_line", "iso6336", "potential_energy", "weber"]
    for name, s in rep["methods"].items():
        assert s["ratio_to_iso"] == pytest.approx(build_stiffness(pair, name).mean / iso,
                                                  rel=1e-12)
        assert f"{name:17s} mean {s['mean_n_per_m']:.4g} N/m = {s['ratio_to_iso']:.3f} x ISO" in out
        assert f"    includes: {s['includes']}\n    leaves out: {s['leaves_out']}\n" in out
    assert rep["methods"]["weber"]["ratio_to_iso"] == pytest.approx(2.76, abs=0.01)


def test_sweep_says_which_stiffness(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _rail(tmp_path)
    assert main(["sweep", str(path), "--speeds", "1000 rpm:3000 rpm:3", "--out",
                 str(tmp_path / "s"), "--quiet"]) == 0
    assert ("  stiffness: contact_line (helical pair, eps_beta = 1.27: contact-line length"
            in capsys.readouterr().out)
