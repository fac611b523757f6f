"""``gear-dyn relief`` for a helical pair: the spur rules with what they assume, and the amounts
normal to the flank."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from gear_dyn.cli.app import main
from gear_dyn.geometry import GearPair
from gear_dyn.modification.relief import recommended_relief

KW = dict(z1=23, z2=79, module=6e-3, pressure_angle=math.radians(20), x1=0.3, x2=-0.1,
          helix_angle=math.radians(20))


def _scene(tmp_path: Path, face_width_mm: float, helix: str = "20 deg") -> Path:
    path = tmp_path / "rail.toml"
    path.write_text(f"""
[scene]
name = "rail"
[gear]
teeth_pinion = 23
teeth_gear = 79
module = "6 mm"
pressure_angle = "20 deg"
helix_angle = "{helix}"
face_width = "{face_width_mm!r} mm"
profile_shift_pinion = 0.3
profile_shift_gear = -0.1
[operating]
speed = "4000 rpm"
torque = "2000 N*m"
""")
    return path


def test_helical_relief_prints_the_rules_with_their_assumptions(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "relief.json"
    assert main(["relief", str(_scene(tmp_path, 70.0)), "--json", str(out), "--quiet"]) == 0
    text = capsys.readouterr().out
    assert "eps_b = 1.2701" in text
    assert ("helical pair (beta = 20 deg, eps_beta = 1.27): these are spur rules, applied in "
            "the transverse section") in text
    pair = GearPair(**KW, face_width=70e-3)
    tab = json.loads(out.read_text())
    assert tab["helical_caveat"] and tab["overlap_ratio"] == pytest.approx(pair.overlap_ratio)
    cos_bb = math.cos(pair.beta_b)
    for row in tab["rules"]:  # the rule's transverse values, and those x cos(beta_b)
        rec = recommended_relief(pair, 2000.0, row["rule"])
        assert row["amount_pinion_m"] == pytest.approx(rec.amount_pinion, rel=1e-15)
        assert row["amount_normal_gear_m"] == pytest.approx(rec.amount_gear * cos_bb, rel=1e-15)
    # the contact-line swing quoted: 14.2 % here, against 1/eps_a for a spur pair
    assert "L(t) swings by 14.2% of its mean 110.5 mm" in text
    assert f"(spur pair of this eps_a: {1 / pair.contact_ratio:.1%})" in text


def test_integer_overlap_ratio_has_a_constant_contact_line_length(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # With eps_beta = 1 the total contact-line length is constant (Liu et al. 2017): the swing
    # quoted is 0.0 % (the breakpoints of L(t) carry its extremes exactly; rounding only).
    pair = GearPair(**KW, face_width=70e-3)
    width_mm = pair.base_pitch / math.tan(pair.beta_b) * 1e3
    assert main(["relief", str(_scene(tmp_path, width_mm)), "--quiet"]) == 0
    assert "L(t) swings by 0.0% of its mean" in capsys.readouterr().out


def test_spur_relief_has_no_caveat(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "relief.json"
    assert main(["relief", str(_scene(tmp_path, 70.0, "0 deg")), "--json", str(out),
                 "--quiet"]) == 0
    text = capsys.readouterr().out
    assert "spur rules" not in text and "Cn1" not in text
    assert json.loads(out.read_text())["helical_caveat"] == []
