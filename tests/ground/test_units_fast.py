"""The pint-free reading of usual "number unit" texts gives exactly what pint gives."""

from __future__ import annotations

import pytest

from gear_dyn import units
from gear_dyn.errors import InputError

CASES = [(si, u) for si, table in units._FAST_UNITS.items() for u in table]
NUMBERS = ("6", "22.5", "2.07e5", "3319", "1474.4", "-0.3", ".5", "7850", "1E-3", "0")


@pytest.mark.parametrize(("si", "spelling"), CASES)
def test_fast_factor_is_pints(si: str, spelling: str) -> None:
    ureg = units.registry()
    assert units._FAST_UNITS[si][spelling] == float(ureg.Quantity(1, spelling).to(si).magnitude)


@pytest.mark.parametrize(("si", "spelling"), CASES)
def test_fast_value_equals_pint(si: str, spelling: str) -> None:
    ureg = units.registry()
    for number in NUMBERS:
        text = f"{number} {spelling}"
        fast = units._fast_quantity(text, si)
        assert fast is not None, text
        slow = float(ureg.Quantity(text).to(si).magnitude)
        assert fast == slow, (text, fast, slow)  # bit for bit: same float product
        assert units.parse_quantity(text, si, "x", "any") == slow


@pytest.mark.parametrize(("raw", "si"), [
    ("1500", "rad/s"), ("25 Hz", "rad/s"), ("6 kg", "m"), ("6mm", "m"), ("6 mm mm", "m"),
    ("nan mm", "m"), ("1_000 mm", "m"), ("200 Nm", "m"), ("3 inch", "m"), ("20 deg", ""),
])
def test_other_texts_go_to_pint(raw: str, si: str) -> None:
    assert units._fast_quantity(raw, si) is None


def test_torque_spellings_and_errors_unchanged() -> None:
    assert units.parse_quantity("200 Nm", "N*m", "torque", ">0") == 200.0
    assert units.parse_quantity("2 kNm", "N*m", "torque", ">0") == 2000.0
    with pytest.raises(InputError, match="give a unit"):
        units.parse_quantity("1500", "rad/s", "speed", ">0")
    with pytest.raises(InputError, match="ambiguous unit"):
        units.parse_quantity("25 Hz", "rad/s", "speed", ">0")
    with pytest.raises(InputError, match="wrong unit"):
        units.parse_quantity("6 kg", "m", "module", ">0")
