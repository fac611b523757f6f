"""One unit rule for scenes, CLI options and API strings (gear_dyn.units).

A dimensional value needs its unit; a plain number there is refused with the readings it could
have, never read in SI (``speed = 1500`` would be 14 324 rpm). "Nm" is newton-metre in torque
fields (pint alone reads it as nanometre). Zero needs no unit; dimensionless fields stay plain.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import pytest

import gear_dyn.units as units_mod
from gear_dyn.errors import InputError, SceneError
from gear_dyn.scene import parse_scene
from gear_dyn.scene.operating import parse_speed_range

ROOT = Path(__file__).resolve().parents[2]
HELI = ROOT / "gear_dyn" / "scenes" / "helicopter_tail.toml"


def _with(table: str, key: str, value: object) -> dict:
    data = tomllib.loads(HELI.read_text())
    data[table][key] = value
    return data


@pytest.mark.parametrize(("table", "key", "value", "readings"), [
    ("operating", "speed", 1500, ('"1500 rpm"', '"1500 rad/s"')),
    ("gear", "pressure_angle", 20, ('"20 deg"', '"20 rad"')),
    ("gear", "module", 6, ('"6 mm"', '"6 m"')),
    ("operating", "torque", 1474.4, ('"1474.4 N*m"', '"1474.4 kN*m"')),
    ("gear", "youngs_modulus", 207, ('"207 GPa"', '"207 MPa"')),
    ("operating", "speed", "1500", ('"1500 rpm"', '"1500 rad/s"')),  # a number in a string
])
def test_plain_number_in_a_dimensional_field_is_refused_with_its_readings(
        table: str, key: str, value: object, readings: tuple[str, str]) -> None:
    with pytest.raises(SceneError) as info:
        parse_scene(_with(table, key, value), "pair.toml")
    msg = str(info.value)
    assert msg.startswith(f"pair.toml: {table}.{key} = ") and "give a unit" in msg
    assert all(r in msg for r in readings), msg


def test_newton_metre_spelled_nm_in_torque_fields() -> None:
    for text, expected in (("200 Nm", 200.0), ("1.5 kNm", 1500.0), ("200 N*m", 200.0),
                           ("200 N m", 200.0)):
        scene = parse_scene(_with("operating", "torque", text), "pair.toml")
        assert scene.tables["operating"]["torque"] == pytest.approx(expected, rel=1e-12)
    with pytest.raises(SceneError, match="operating.torque = '200 nm': wrong unit"):
        parse_scene(_with("operating", "torque", "200 nm"), "pair.toml")  # nanometre


def test_zero_and_dimensionless_values_stay_plain() -> None:
    scene = parse_scene(_with("gear", "helix_angle", 0), "pair.toml")
    assert scene.tables["gear"]["helix_angle"] == 0.0
    scene = parse_scene(_with("gear", "center_distance_offset", "0"), "pair.toml")
    assert scene.tables["gear"]["center_distance_offset"] == 0.0
    scene = parse_scene(_with("gear", "poisson", 0.29), "pair.toml")  # dimensionless
    assert scene.tables["gear"]["poisson"] == pytest.approx(0.29)


def test_si_numbers_from_a_program_are_accepted() -> None:
    """Tables a program hands over (an FMU's stored scene, FMI parameters) are SI numbers."""
    data = _with("operating", "speed", 3319 * 2 * math.pi / 60)
    scene = parse_scene(data, "stored", si=True)
    assert scene.tables["operating"]["speed"] == pytest.approx(347.57, rel=1e-4)


def test_cli_speeds_follow_the_same_rule() -> None:
    with pytest.raises(InputError, match=r'--speeds START = 1500: give a unit, e\.g\. "1500 rpm"'):
        parse_speed_range("1500:3000:10")
    speeds = parse_speed_range("1500 rpm:3000 rpm:2")
    assert speeds.tolist() == pytest.approx([1500 * math.pi / 30, 3000 * math.pi / 30])


def test_cli_plain_speed_is_exit_2_one_line(tmp_path: Path) -> None:
    from gear_dyn.cli import main

    scene = tmp_path / "plain.toml"
    scene.write_text(HELI.read_text().replace('speed = "3319 rpm"', "speed = 3319"))
    import subprocess
    import sys

    p = subprocess.run([sys.executable, "-m", "gear_dyn.cli", "run", str(scene), "--out",
                        str(tmp_path / "o")], capture_output=True, text=True, timeout=300)
    assert p.returncode == 2 and p.stderr.count("\n") == 1
    assert 'operating.speed = 3319: give a unit, e.g. "3319 rpm"' in p.stderr
    assert not (tmp_path / "o").exists()
    assert main(["sweep", str(HELI), "--speeds", "1000:2000:3", "--out",
                 str(tmp_path / "s")]) == 2


@pytest.mark.parametrize(("raw", "unit", "message"), [
    # wrong dimension: the field, the text, what was expected and the valid range
    ("6 kg", "m", r"module = '6 kg': wrong unit; expected a length \(e\.g\. '6 mm'\), "
                  r"valid range > 0 m$"),
    # nanometre in a length-free field: the hint says where Nm means newton-metre
    ("200 Nm", "m**2", r"wrong unit; .*\(Nm is newton-metre only in torque fields\)"),
    # a number without a unit: the readings it could have, the usual one first
    ("1500", "rad/s", r'module = 1500: give a unit, e\.g\. "1500 rpm" \(or "1500 rad/s"\); '
                      r"a plain number is refused for a rotational speed"),
    ("25 Hz", "rad/s", r"ambiguous unit for a rotational speed .* rpm, rad/s or turn/s"),
    ("six mm", "m", r"module = 'six mm': not a number with a unit; expected a length"),
])
def test_parse_errors_name_field_value_unit_and_range(raw: str, unit: str, message: str) -> None:
    from gear_dyn.units import parse_quantity

    with pytest.raises(InputError, match=message):
        parse_quantity(raw, unit, "module", "> 0 m")


def test_torque_spellings_are_newton_metre() -> None:
    from gear_dyn.units import parse_quantity

    for raw, expected in (("200 Nm", 200.0), ("2 kNm", 2000.0), ("3 N.m", 3.0),
                          ("4 N·m", 4.0), ("1 MNm", 1e6)):
        assert parse_quantity(raw, "N*m", "torque", "> 0 N*m") == pytest.approx(expected,
                                                                                 rel=1e-15)


def test_registry_without_a_usable_cache_folder() -> None:
    """pint raises OSError when its cache folder cannot be made (here: the cache home is a
    file); the registry is then built from the definition files, with the same values."""
    import subprocess
    import sys
    import tempfile

    if not sys.platform.startswith("linux"):
        pytest.skip("XDG_CACHE_HOME places pint's cache folder on Linux only")
    with tempfile.NamedTemporaryFile() as not_a_folder:
        code = ("from gear_dyn.units import parse_quantity, registry\n"
                "print(registry()._diskcache, parse_quantity('6 mm', 'm', 'module', '> 0'))")
        env = {**__import__("os").environ, "XDG_CACHE_HOME": not_a_folder.name}
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                             env=env, check=True).stdout.split()
    assert out == ["None", "0.006"]


@pytest.mark.parametrize("si", sorted(units_mod._PLAIN))
def test_plain_spellings_read_without_pint_are_pints_values_to_the_bit(si: str) -> None:
    """The plainest spellings are read from a table of factors, not by pint: each reading
    equals pint's (same factor, same product), for integers, decimals and exponents."""
    ureg = units_mod.registry()
    numbers = ["0", "1", "3000", "9500", "3319", "368.6", "2.07e5", "-1.5", ".25", "6.02E23",
               "1e-7", "7850"]
    for spelling in units_mod._PLAIN[si]:
        pint_spelling = "N*m" if spelling == "Nm" else spelling  # pint: Nm is nanometre
        for x in numbers:
            ours = units_mod.parse_quantity(f"{x} {spelling}", si, "f", "any")
            assert units_mod._plain_reading(f"{x} {spelling}", si) is not None
            theirs = float(ureg.Quantity(f"{x} {pint_spelling}").to(si).magnitude)
            assert ours == theirs, (x, spelling, si)


def test_other_spellings_still_go_through_pint() -> None:
    """Not in the table (a prefix, a compound, another dimension): pint reads or refuses it."""
    assert units_mod._plain_reading("1 N/(mm*um)", "N/m**2") is None
    assert units_mod.parse_quantity("1 N/(mm*um)", "N/m**2", "f", "any") == 1e9
    assert units_mod._plain_reading("6 mm", "rad") is None
    with pytest.raises(InputError, match="wrong unit"):
        units_mod.parse_quantity("6 mm", "rad", "pressure_angle", "0..45 deg")


def test_ranges_in_a_plain_spelling_are_pints() -> None:
    """A field's range in the unit the user wrote is the same from the table as from pint."""
    ureg = units_mod.registry()
    for si, spellings in units_mod._PLAIN.items():
        for spelling in spellings:
            pint_spelling = "N*m" if spelling == "Nm" else spelling
            assert units_mod._factor(spelling, si) == float(
                ureg.Quantity(1.0, pint_spelling).to(si).magnitude), (spelling, si)
    assert units_mod.range_in_user_unit("50 deg", "rad", 0.0, math.radians(45)) \
        == "0 <= x <= 45 deg"
