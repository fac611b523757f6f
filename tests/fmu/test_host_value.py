"""Values a session hands to an FMU: the same rule for FMI 2 and FMI 3 variable types."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from gear_dyn.errors import InputError
from gear_dyn.fmu.session import host_value

ENUM = SimpleNamespace(type="Enumeration", declaredType=SimpleNamespace(items=[
    SimpleNamespace(name="auto", value="1"), SimpleNamespace(name="exact", value="2")]))


@pytest.mark.parametrize("kind", ["Integer", "Int32", "Int64"])
def test_integer_types_take_whole_numbers_only(kind: str) -> None:
    var = SimpleNamespace(type=kind)
    assert host_value("solver.periods", var, 40.0) == 40
    assert isinstance(host_value("solver.periods", var, 40.0), int)
    with pytest.raises(InputError, match=r"solver.periods = 2.5: expected a whole number"):
        host_value("solver.periods", var, 2.5)


def test_enumeration_by_name_or_number() -> None:
    assert host_value("solver.method", ENUM, "exact") == 2
    assert host_value("solver.method", ENUM, 1) == 1
    with pytest.raises(InputError, match="valid choices are auto, exact"):
        host_value("solver.method", ENUM, "Euler")


def test_reals_pass_unchanged() -> None:
    assert host_value("operating.torque", SimpleNamespace(type="Float64"), 2.5) == 2.5
    assert host_value("operating.torque", SimpleNamespace(type="Real"), 2.5) == 2.5
