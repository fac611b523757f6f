"""Scene table [tip_relief] and the `gear-dyn relief` / `gear-dyn contact` commands."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from gear_dyn.cli.app import main
from gear_dyn.errors import SceneError
from gear_dyn.models.relief import ReliefSDOFModel, pair_stiffness_function
from gear_dyn.modification import loaded_contact, recommended_relief
from gear_dyn.scene import build_model, build_pair, load_scene, parse_scene
from gear_dyn.scene.modification import relief_from_scene

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "examples" / "scenes" / "helicopter_tail_relief.toml"

BASE = {
    "gear": {"teeth_pinion": 23, "teeth_gear": 64, "module": "6 mm",
             "pressure_angle": "22.5 deg", "face_width": "50 mm", "youngs_modulus": "207 GPa"},
    "operating": {"speed": "3319 rpm", "torque": "1474.4 N*m"},
}


def scene_with(**tables: dict) -> object:
    return parse_scene({**BASE, **tables}, "t.toml")


def test_custom_relief_from_height_and_length() -> None:
    sc = scene_with(tip_relief={"amount_pinion": "20 um", "height_pinion": "2.4 mm",
                                "amount_gear": "10 um", "length_gear": "4 mm",
                                "curve": "parabolic"})
    pair = build_pair(sc)
    mod = relief_from_scene(sc, pair)
    assert mod.pinion is not None and mod.gear is not None
    # height 2.4 mm on the pinion -> 4.7706 mm along the line of action (roll-angle form,
    # tested in test_modification_relief); the gear length is taken as given
    assert mod.pinion.length == pytest.approx(4.7706375e-3, rel=1e-6)
    assert mod.gear.length == pytest.approx(4e-3, rel=1e-12)
    assert mod.pinion.amount == pytest.approx(20e-6, rel=1e-12)
    assert mod.gear.curve == "parabolic"


def test_rule_relief_equals_recommendation() -> None:
    sc = scene_with(tip_relief={"rule": "niemann", "curve": "walker"})
    pair = build_pair(sc)
    mod = relief_from_scene(sc, pair)
    rec = recommended_relief(pair, 1474.4, "niemann")
    assert mod == rec.modification("walker")


@pytest.mark.parametrize(("tables", "match"), [
    ({"tip_relief": {"curve": "linear"}}, "needs amount_pinion and/or amount_gear"),
    ({"tip_relief": {"amount_gear": "10 um"}}, "exactly one of length_gear"),
    ({"tip_relief": {"amount_gear": "10 um", "length_gear": "3 mm", "height_gear": "1 mm"}},
     "exactly one of length_gear"),
    ({"tip_relief": {"rule": "dudley", "amount_gear": "10 um"}}, "only for rule = 'custom'"),
    ({"tip_relief": {"amount_gear": "10 um", "length_gear": "300 mm"}}, "relief length"),
    ({"tip_relief": {"rule": "niemann"}, "transmission_error": {"cos": ["1 um"]}},
     "cannot be combined"),
    ({"tip_relief": {"rule": "niemann"}, "stiffness": {"method": "iso6336"}},
     "mesh stiffness comes from the loaded contact"),
    ({"tip_relief": {"rule": "niemann"}, "scene": {"model": "torsional"}}, "sdof' only"),
])
def test_scene_mistakes_are_named(tables: dict, match: str) -> None:
    with pytest.raises(SceneError, match=match):
        build_model(scene_with(**tables))


def test_scene_builds_relief_model_with_loaded_stiffness() -> None:
    sc = load_scene(SCENE)
    model = build_model(sc)
    assert isinstance(model, ReliefSDOFModel)
    pair = build_pair(sc)
    mod = relief_from_scene(sc, pair)
    lc = loaded_contact(pair, pair_stiffness_function(pair), 1474.4, mod)
    ph = np.linspace(0.01, 0.99, 37)
    # the model carries the tangent stiffness and relief TE of the loaded contact: its static
    # solution W / k + e is the loaded static TE (1e-5: W / k_t and e are interpolated
    # separately between the same 48 samples per segment, delta directly)
    x_static = model.static_load / model.stiffness(ph) + model.transmission_error.value(ph)
    np.testing.assert_allclose(x_static, lc.static_transmission_error().value(ph), rtol=1e-5)
    assert model.summary_info()["stiffness_method"] == "loaded contact (tangent)"


def test_relief_command_table(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "relief.json"
    assert main(["relief", str(SCENE), "--json", str(out)]) == 0
    text = capsys.readouterr().out
    for rule in ("handbook", "dudley", "niemann", "wang2024"):
        assert rule in text
    tab = json.loads(out.read_text())
    pair = build_pair(load_scene(SCENE))
    for row in tab["rules"]:
        rec = recommended_relief(pair, 1474.4, row["rule"])
        assert row["amount_pinion_m"] == pytest.approx(rec.amount_pinion, rel=1e-15)
        assert row["length_gear_m"] == pytest.approx(rec.length_gear, rel=1e-15)
    assert tab["load_per_width_n_per_mm"] == pytest.approx(427.3623, rel=1e-6)


def test_contact_command_outputs(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "contact"
    assert main(["contact", str(SCENE), "--out", str(out), "--curve", "parabolic"]) == 0
    assert {p.name for p in out.iterdir()} == {"contact.json", "load_sharing.png",
                                               "stiffness.png", "path.csv", "face_load.png",
                                               "ltca.csv"}
    rep = json.loads((out / "contact.json").read_text())
    names = [r["case"] for r in rep["cases"]]
    assert names == ["unmodified", "scene relief", "handbook", "dudley", "niemann", "wang2024",
                     "kisssoft"]
    assert rep["method"] == "spur loaded contact"
    # the slice analysis of the same spur cases agrees with the spur rows: both sample the
    # same K(s); the slice analysis at 32 uniform phases plus the switching phases, the spur
    # one segment by segment, so its p-p TE lies within the spur value (sampling; 1e-4: the
    # one-sided samples next to the jumps sit at slightly different phases)
    for row in rep["cases"]:
        ltca = rep["ltca"][row["case"]]["summary"][0]
        # the mean of 32 uniform samples of a stiffness that jumps where a relieved pair picks
        # up load (phases the slice analysis does not locate): a few per cent
        assert ltca["mean_loaded_stiffness_n_per_m"] == pytest.approx(
            row["mean_loaded_stiffness_n_per_m"], rel=0.05)
        assert ltca["peak_to_peak_static_te_m"] <= row["peak_to_peak_static_te_m"] * (1 + 1e-4)
    pair = build_pair(load_scene(SCENE))
    unmod = rep["cases"][0]
    # unmodified single-contact zone B..D: E - p_b and A + p_b (1e-9 m: one-sided sampling)
    assert unmod["single_contact_start_m"] == pytest.approx(
        pair.end_of_contact - pair.base_pitch, abs=1e-9)
    assert unmod["single_contact_end_m"] == pytest.approx(
        pair.start_of_contact + pair.base_pitch, abs=1e-9)
    # a relief lowers the static TE fluctuation for every rule here (loads below the relief
    # amounts keep contact gradual)
    for row in rep["cases"][1:]:
        assert row["peak_to_peak_static_te_m"] < unmod["peak_to_peak_static_te_m"]
    # the rules used the requested curve; the scene's own relief keeps its linear curve
    assert rep["cases"][2]["curve_pinion"] == "parabolic"
    assert rep["cases"][1]["curve_pinion"] == "linear"
    assert "niemann" in capsys.readouterr().out


def test_contact_command_runs_a_helical_pair_on_the_slice_analysis(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    scene = tmp_path / "hel.toml"
    scene.write_text(SCENE.read_text().replace('face_width = "50 mm"',
                                               'face_width = "50 mm"\nhelix_angle = "15 deg"'))
    out = tmp_path / "o"
    assert main(["contact", str(scene), "--out", str(out)]) == 0
    assert {p.name for p in out.iterdir()} == {"contact.json", "stiffness.png", "ltca.csv",
                                               "face_load.png"}
    rep = json.loads((out / "contact.json").read_text())
    assert rep["method"] == "slice LTCA"
    keys = {"peak_to_peak_static_te_m", "mean_loaded_stiffness_n_per_m", "peak_stress_pa"}
    for row in rep["cases"]:
        assert keys <= set(row) and row["peak_stress_pa"] > 0
    text = capsys.readouterr().out
    assert "eps_beta" in text and "slice LTCA" in text


def test_zero_amount_relief_is_the_unmodified_pair() -> None:
    sc = scene_with(tip_relief={"amount_gear": "0 um", "length_gear": "3 mm"},
                    stiffness={"method": "potential_energy"})
    model = build_model(sc)
    plain = build_model(scene_with(stiffness={"method": "potential_energy"}))
    ph = np.linspace(0.0, 0.999, 101)
    # same single-pair function; sampling differs (48 per segment vs 200 per cycle): 1e-4
    np.testing.assert_allclose(model.stiffness(ph), plain.stiffness(ph), rtol=1e-4)
    assert model.transmission_error is None


def test_contact_command_dynamics(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """--dynamics runs every case through the single-DOF model with the scene's settings."""
    scene = tmp_path / "short.toml"
    text = SCENE.read_text()
    text = text[:text.index("[tip_relief]")] + text[text.index("[damping]"):]
    text = text.replace("periods = 40 ", "periods = 4 ").replace("steady_periods = 20",
                                                                 "steady_periods = 2")
    text = text.replace("samples_per_period = 64", "samples_per_period = 32")
    text = text.replace("rtol = 1e-7", "rtol = 1e-5")
    scene.write_text(text)
    out = tmp_path / "dyn"
    assert main(["contact", str(scene), "--out", str(out), "--dynamics"]) == 0
    dyn = json.loads((out / "dynamics.json").read_text())
    assert list(dyn) == ["unmodified", "handbook", "dudley", "niemann", "wang2024", "kisssoft"]
    assert (out / "dynamics.png").stat().st_size > 0
    # every peak force ratio is at least 1 (the peak force is at least the mean) and finite;
    # the dynamic factor is that over the case's own quasi-static peak
    for row in dyn.values():
        assert row["peak_force_ratio"] >= 1.0 and row["peak_force_ratio"] < 3.0
        assert row["dynamic_factor"] * row["stiffness_jump_factor"] == pytest.approx(
            row["peak_force_ratio"], rel=1e-12)
        assert row["solver"]["method"] == "DOP853"
    assert "F_max/W" in capsys.readouterr().out


def test_scene_tooth_options_reach_the_pair_stiffness() -> None:
    """[stiffness] with the same method as tip_relief.pair_stiffness passes its tooth options
    (here a bore) to the single-pair stiffness of the loaded contact."""
    from gear_dyn.scene.modification import scene_pair_function
    from gear_dyn.stiffness.potential_energy import potential_energy_pair_stiffness
    from gear_dyn.stiffness.tooth import ToothOptions

    sc = scene_with(tip_relief={"rule": "niemann"},
                    stiffness={"method": "potential_energy", "bore_radius_gear": "150 mm"})
    pair = build_pair(sc)
    fn = scene_pair_function(sc, pair)
    s = np.linspace(pair.start_of_contact, pair.end_of_contact, 7)
    expected = potential_energy_pair_stiffness(pair, s, ToothOptions(bore_radius2=0.15))
    np.testing.assert_allclose(fn(s), expected, rtol=1e-12)
    # and the option matters: the default body gives other values (> 1 % apart)
    assert np.all(np.abs(fn(s) / potential_energy_pair_stiffness(pair, s) - 1) > 0.01)
    bad = scene_with(tip_relief={"rule": "niemann"},
                     stiffness={"method": "potential_energy", "weber_slices": 10})
    with pytest.raises(SceneError, match="weber_slices"):
        build_model(bad)


def test_relief_study_command(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    scene = tmp_path / "hel.toml"
    scene.write_text(SCENE.read_text().replace('face_width = "50 mm"',
                                               'face_width = "50 mm"\nhelix_angle = "15 deg"'))
    out = tmp_path / "study"
    assert main(["relief-study", str(scene), "--out", str(out),
                 "--torques", "500 N*m:1500 N*m:3"]) == 0
    assert {p.name for p in out.iterdir()} == {"study.json", "study.csv", "study.png"}
    rep = json.loads((out / "study.json").read_text())
    names = [d["design"] for d in rep["designs"]]
    assert rep["best"] in names and rep["torque_n_m"] == pytest.approx([500.0, 1000.0, 1500.0])
    mean = {d["design"]: d["mean_ppte_m"] for d in rep["designs"]}
    assert mean[rep["best"]] == min(mean.values())
    assert "best (lowest PPTE over the range)" in capsys.readouterr().out
    assert main(["relief-study", str(scene), "--out", str(tmp_path / "bad"),
                 "--torques", "500:1500:3"]) == 2
    assert "--torques" in capsys.readouterr().err
    assert not (tmp_path / "bad").exists()


def test_relief_study_command_with_speeds(tmp_path: Path,
                                          capsys: pytest.CaptureFixture[str]) -> None:
    """--speeds adds each design's peak mesh force and p-p DTE over the range: dynamics.csv,
    the JSON block and the design with the lowest peak force, which is the minimum of the
    designs' peaks."""
    scene = tmp_path / "hel.toml"
    scene.write_text(SCENE.read_text().replace('face_width = "50 mm"',
                                               'face_width = "50 mm"\nhelix_angle = "15 deg"'))
    out = tmp_path / "study"
    assert main(["relief-study", str(scene), "--out", str(out), "--torques",
                 "1000 N*m:1500 N*m:2", "--speeds", "1000 rpm:5000 rpm:3"]) == 0
    assert {p.name for p in out.iterdir()} == {"study.json", "study.csv", "study.png",
                                              "dynamics.csv"}
    dyn = json.loads((out / "study.json").read_text())["dynamics"]
    assert dyn["speed_rpm"] == pytest.approx([1000.0, 3000.0, 5000.0])
    peaks = {d["design"]: d["max_peak_force_ratio"] for d in dyn["designs"]}
    assert peaks[dyn["best"]] == min(peaks.values())
    assert all(p > 1.0 for p in peaks.values())  # the static load is carried at least
    assert f"lowest peak mesh force over the speed range: {dyn['best']}" in \
        capsys.readouterr().out
    assert main(["relief-study", str(scene), "--out", str(tmp_path / "bad"),
                 "--speeds", "1000:5000:3"]) == 2
    assert "1000" in capsys.readouterr().err
    assert not (tmp_path / "bad").exists()
