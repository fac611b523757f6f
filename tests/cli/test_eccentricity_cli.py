"""`gear-dyn excitation`, `gear-dyn run` with the torsional model, and the eccentricity tables."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from gear_dyn.cli.app import main
from gear_dyn.models.torsional import TorsionalModel
from gear_dyn.scene import build_model, load_scene, parse_scene

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"
ECCENTRIC = SCENES / "eccentric_helical.toml"
IDEAL = SCENES / "eccentric_helical_ideal.toml"


def test_excitation_command_writes_plots_csv_and_peak_table(tmp_path: Path,
                                                            capsys: pytest.CaptureFixture) -> None:
    out = tmp_path / "exc"
    assert main(["excitation", str(ECCENTRIC), "--out", str(out), "--samples-per-mesh", "16"]) == 0
    assert sorted(p.name for p in out.iterdir()) == [
        "excitation.csv", "excitation_spectrum.png", "excitation_time.png", "peaks.json"]
    rep = json.loads((out / "peaks.json").read_text())
    assert rep["mesh_frequency_hz"] == pytest.approx(450.0, rel=1e-14)
    assert rep["shaft_frequencies_hz"] == pytest.approx([25.0, 25.0 * 18 / 70], rel=1e-14)
    assert rep["duration_s"] == pytest.approx(1.4, rel=1e-12)  # one hunting period
    w2 = rep["signals"]["w2"]["peaks"]
    assert {p["label"] for p in w2[:2]} == {"f1", "f2"}
    labels = {p["label"] for p in rep["signals"]["friction_torque_pinion"]["peaks"]}
    assert {"fm", "2fm", "f1", "f2", "fm-f1", "fm+f2"} <= labels
    assert "w2:" in capsys.readouterr().out


def test_run_handles_the_torsional_model(tmp_path: Path) -> None:
    out = tmp_path / "run"
    assert main(["run", str(ECCENTRIC), "--out", str(out), "--periods", "12"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["mesh_frequency_hz"] == pytest.approx(450.0, rel=1e-12)
    assert math.isfinite(summary["dynamic_factor"])


def test_scene_without_eccentricity_or_friction_builds_no_machinery() -> None:
    raw = dict(load_scene(IDEAL).raw)
    raw.pop("friction")
    model = build_model(parse_scene(raw, "plain"))
    assert isinstance(model, TorsionalModel)
    assert not model.eccentric and model.friction is None
    assert model.eccentricity is None
    ideal = build_model(load_scene(IDEAL))
    assert isinstance(ideal, TorsionalModel) and not ideal.eccentric and ideal.friction == 0.05
    eccentric = build_model(load_scene(ECCENTRIC))
    assert isinstance(eccentric, TorsionalModel) and eccentric.eccentric
    # k_l from the contact_line method: mean k equals that method's mean (ISO c_gamma B)
    assert eccentric.mean_stiffness == pytest.approx(ideal.mean_stiffness, rel=1e-14)


@pytest.mark.parametrize(("table", "match"), [
    ({"eccentricity": {"pinion": "-0.1 mm"}}, "eccentricity.pinion"),
    ({"eccentricity": {"pinon": "0.1 mm"}}, "did you mean 'pinion'"),
    ({"eccentricity": {"pinion": "2 mm", "gear": "2 mm"}}, "half the module"),
    ({"friction": {}}, "friction.coefficient"),
    ({"friction": {"coefficient": 1.5}}, "friction.coefficient"),
])
def test_bad_tables_exit_2_with_one_line(tmp_path: Path, capsys: pytest.CaptureFixture,
                                         table: dict, match: str) -> None:
    text = ECCENTRIC.read_text()
    for name in table:  # drop the scene's own table of that name, append the bad one
        start = text.index(f"[{name}]")
        end = text.find("\n[", start + 1)
        text = text[:start] + (text[end + 1:] if end >= 0 else "")
    for name, body in table.items():
        text += f"\n[{name}]\n" + "".join(f'{k} = {json.dumps(v)}\n' for k, v in body.items())
    bad = tmp_path / "bad.toml"
    bad.write_text(text)
    assert main(["excitation", str(bad), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and match in err
    assert not (tmp_path / "o").exists()
