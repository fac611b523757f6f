"""Stiffness in scenes and the ``gear-dyn stiffness`` command."""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path

import pytest

from gear_dyn.cli.app import main
from gear_dyn.scene import build_pair, run_scene
from gear_dyn.scene.loader import parse_scene
from gear_dyn.stiffness import build_stiffness, iso6336_stiffness

SCENE = Path(__file__).resolve().parents[2] / "gear_dyn" / "scenes" / "helicopter_tail.toml"


def _scene(stiffness: dict[str, object], gear: dict[str, object] | None = None) -> object:
    data = tomllib.loads(SCENE.read_text())
    data["stiffness"] = stiffness
    if gear:
        data["gear"].update(gear)
    return parse_scene(data, "helicopter_tail_test")


@pytest.mark.parametrize("method", ["iso6336", "rectangular", "potential_energy", "weber",
                                    "contact_line"])
@pytest.mark.parametrize("fourier", [None, 5])
def test_helicopter_tail_runs_with_each_method(method: str, fourier: int | None) -> None:
    # The helicopter tail scene of Jiang et al. (2018) simulates with every method (and its
    # 5-term Fourier fit, as the paper does); the run summary names the method, and the model's
    # mean stiffness is the method's mean (the Fourier fit keeps the mean exactly; the simulated
    # mean over whole periods matches to the sampling of the steady window, rel 1e-2).
    from gear_dyn.analysis.report import summarize

    st: dict[str, object] = {"method": method}
    if fourier:
        st["fourier_terms"] = fourier
    scene = _scene(st)
    result = run_scene(scene, periods=6, rtol=1e-6)
    summary = summarize(result)
    assert summary["stiffness_method"] == method
    assert summary["fourier_terms"] == fourier
    k = build_stiffness(build_pair(scene), method)
    assert summary["mean_mesh_stiffness_n_per_m"] == pytest.approx(k.mean, rel=1e-2)


def test_scene_options_reach_the_method() -> None:
    # [stiffness] keys for the geometric methods are passed through (here: a bore radius and
    # Weber's foundation option); a key the method does not take is a scene error.
    from gear_dyn.errors import SceneError
    from gear_dyn.scene import scene_stiffness

    scene = _scene({"method": "weber", "weber_foundation": True, "bore_radius_pinion": "20 mm"})
    pair = build_pair(scene)
    k = scene_stiffness(scene, pair)
    assert k.mean == pytest.approx(
        build_stiffness(pair, "weber", weber_foundation=True, bore_radius1=0.02).mean, rel=1e-12)
    with pytest.raises(SceneError, match="does not apply to method"):
        scene_stiffness(_scene({"method": "iso6336", "weber_slices": 3}), pair)


def test_cli_writes_files_and_json(tmp_path: Path) -> None:
    # The JSON numbers are those of the API (same code path), the ISO block equals the hand-checked
    # iso6336_stiffness, and the shaft offset of 0.3 mm of Jiang et al. (2018) shows up as
    # backlash and a lower contact ratio.
    scene_file = tmp_path / "tail_offset.toml"
    text = SCENE.read_text().replace('face_width = "50 mm"',
                                     'face_width = "50 mm"\ncenter_distance_offset = "0.3 mm"')
    scene_file.write_text(text)
    out = tmp_path / "out"
    code = main(["stiffness", str(scene_file), "--out", str(out), "--cycles", "3"])
    assert code == 0
    for name in ("stiffness.png", "components.png", "stiffness.csv", "stiffness.json"):
        assert (out / name).is_file()
    rep = json.loads((out / "stiffness.json").read_text())
    pair = build_pair(parse_scene(tomllib.loads(text), "t"))
    assert rep["operating"]["backlash_m"] == pytest.approx(pair.backlash, rel=1e-9)
    assert rep["operating"]["backlash_m"] == pytest.approx(2 * 0.3e-3 * math.sin(
        math.radians(22.5)), rel=0.02)
    assert rep["iso6336"]["k_mesh_n_per_m"] == pytest.approx(
        iso6336_stiffness(pair).k_mesh, rel=1e-12)
    for m in ("iso6336", "potential_energy", "weber", "contact_line"):
        s = rep["methods"][m]
        assert s["mean_n_per_m"] == pytest.approx(build_stiffness(pair, m).mean, rel=1e-12)
        tol = 1e-9 * s["max_n_per_m"]  # zone means of a flat zone equal min/max to rounding
        assert s["min_n_per_m"] - tol <= s["single_pair_n_per_m"] <= s["double_pair_n_per_m"]
        assert s["double_pair_n_per_m"] <= s["max_n_per_m"] + tol
    comp = rep["components_at_pitch_point"]
    total = comp["hertz_m_per_n"] + sum(
        comp[f"{t}_{g}_m_per_n"] for t in ("bending", "shear", "axial", "fillet")
        for g in ("pinion", "gear"))
    assert comp["pair_stiffness_n_per_m"] == pytest.approx(1 / total, rel=1e-12)
    header = (out / "stiffness.csv").read_text().splitlines()[0]
    assert header.startswith("phase_cycles,k_iso6336_n_per_m")


def test_cli_bad_method_is_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["stiffness", str(SCENE), "--out", str(tmp_path / "o"), "--methods", "fem"])
    assert code == 2
    err = capsys.readouterr().err
    assert "not a stiffness method" in err and err.count("\n") == 1
    assert not (tmp_path / "o").exists()


def test_component_split_follows_the_scene_options() -> None:
    """The pitch-point split of ``gear-dyn stiffness`` uses the scene's own tooth options: the
    components add up to the potential-energy curve it draws beside them. With plane strain
    the pair is 0.6 % stiffer here: the split must move with the curve (it ignored the options
    before, and stayed at the plane-stress split, 0.6 % off the curve)."""
    from gear_dyn.cli.stiffness import compute

    scene = _scene({"method": "potential_energy", "plane_strain": True})
    pair, curves, report = compute(scene, ["potential_energy"])
    comp = report["components_at_pitch_point"]
    total = comp["hertz_m_per_n"] + sum(
        comp[f"{t}_{g}_m_per_n"] for t in ("bending", "shear", "axial", "fillet")
        for g in ("pinion", "gear"))
    # every term the report lists, and only those, make up the pair compliance it reports
    assert 1.0 / total == pytest.approx(comp["pair_stiffness_n_per_m"], rel=1e-12)
    # the curve at the phase where one pair meshes at the pitch point, alone (single contact)
    p = ((pair.pitch_point - pair.start_of_contact) / pair.base_pitch) % 1.0
    assert pair.contact_ratio - 1.0 <= p < 1.0  # the pitch point is in single contact here
    k_curve = float(curves["potential_energy"](p))
    # the curve is sampled at 200 points per cycle and interpolated: 1e-4 covers that
    assert comp["pair_stiffness_n_per_m"] == pytest.approx(k_curve, rel=1e-4)
    default = compute(_scene({"method": "potential_energy"}), ["potential_energy"])[2]
    ratio = comp["pair_stiffness_n_per_m"] / default["components_at_pitch_point"][
        "pair_stiffness_n_per_m"]
    assert ratio > 1.003  # plane strain stiffens the pair: the options reached the split
