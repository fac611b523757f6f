"""Shaft-speed spellings (RPM, rev/min, r/min), unknown units named, and ranges reported in the
unit the user wrote (gear_dyn.units)."""

from __future__ import annotations

import math

import pytest

from gear_dyn.errors import InputError
from gear_dyn.units import parse_quantity, range_in_user_unit

RPM = 2 * math.pi / 60  # rad/s per rpm


@pytest.mark.parametrize("text", ["4000 rpm", "4000 RPM", "4000 Rpm", "4000 rev/min",
                                  "4000 r/min", "4000 rev / min", "4000 revolution/minute"])
def test_speed_spellings_read_as_rpm(text: str) -> None:
    assert parse_quantity(text, "rad/s", "speed", "") == pytest.approx(4000 * RPM, rel=1e-12)


def test_rev_per_second_is_a_turn_per_second() -> None:
    assert parse_quantity("10 rev/s", "rad/s", "speed", "") == pytest.approx(20 * math.pi)


def test_rpm_spelling_only_in_speed_fields() -> None:
    # "RPM" is no length: outside a speed field it is an unknown unit, named as such
    with pytest.raises(InputError, match=r"length = '4 RPM': unknown unit 'RPM'; expected a "
                                         r"length"):
        parse_quantity("4 RPM", "m", "length", "")


@pytest.mark.parametrize(("text", "message"), [
    ("4000 rpn", r"speed = '4000 rpn': unknown unit 'rpn'; expected a rotational speed"),
    ("4000 m", r"speed = '4000 m': wrong unit; expected a rotational speed"),
    ("fast rpm", r"speed = 'fast rpm': not a number with a unit"),
])
def test_wrong_speed_units_get_the_right_message(text: str, message: str) -> None:
    with pytest.raises(InputError, match=message):
        parse_quantity(text, "rad/s", "speed", "")


@pytest.mark.parametrize(("raw", "unit", "low", "high", "expected"), [
    ("50 deg", "rad", 0.0, math.radians(45), "0 <= x <= 45 deg"),
    ("50 degree", "rad", -math.radians(45), math.radians(45), "-45 <= x <= 45 degree"),
    ("2 m", "m", 0.0, 1.0, "0 <= x <= 1 m"),
    ("2000 mm", "m", 0.0, 1.0, "0 <= x <= 1000 mm"),
    ("2e6 rpm", "rad/s", 0.0, 1e5, "0 <= x <= 954930 rpm"),
    ("2e6 RPM", "rad/s", 0.0, 1e5, "0 <= x <= 954930 RPM"),
    ("1e9 Nm", "N*m", 0.0, 1e8, "0 <= x <= 1e+08 Nm"),
    ("1e6 kN*m", "N*m", 0.0, 1e8, "0 <= x <= 100000 kN*m"),
    (0.9, "rad", 0.0, math.radians(45), "0 <= x <= 0.785398 rad"),  # SI number: SI range
    ("6 kg", "m", 0.0, 1.0, "0 <= x <= 1 m"),  # another dimension: the field's SI unit
])
def test_range_in_the_unit_written(raw: object, unit: str, low: float, high: float,
                                   expected: str) -> None:
    assert range_in_user_unit(raw, unit, low, high) == expected


def test_scene_range_message_in_degrees() -> None:
    from gear_dyn.scene.core import GEAR

    field = {f.name: f for f in GEAR.fields}["helix_angle"]
    with pytest.raises(InputError, match=r"'50 deg' is out of range: valid range "
                                         r"-45 <= x <= 45 deg$"):
        field.parse("50 deg", "f.toml: gear.helix_angle")
