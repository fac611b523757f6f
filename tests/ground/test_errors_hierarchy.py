"""The error hierarchy and what its messages say: field, value, unit and valid range for user
errors; the solver's own message and what to try for solver failures."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pytest

from gear_dyn.analysis.study import simulate
from gear_dyn.errors import GearDynError, InputError, SceneError, SolverError, check_range
from gear_dyn.geometry import GearPair
from gear_dyn.models.base import ModelDefaults
from gear_dyn.scene import parse_scene
from gear_dyn.scene.fields import Field
from gear_dyn.scene.validated import scene_error
from gear_dyn.solvers import SolverSettings


def test_hierarchy() -> None:
    """User errors are ValueErrors, solver failures RuntimeErrors, both GearDynErrors, and
    neither is the other (so the CLI can map them to exit codes 2 and 3)."""
    assert issubclass(InputError, ValueError) and issubclass(InputError, GearDynError)
    assert issubclass(SceneError, InputError)
    assert issubclass(SolverError, RuntimeError) and issubclass(SolverError, GearDynError)
    assert not issubclass(SolverError, ValueError) and not issubclass(InputError, RuntimeError)


@pytest.mark.parametrize(("value", "needle"), [
    (-2.0, "face_width = -2 m is out of range: valid range 0 < x <= 10 m"),
    (math.nan, "face_width = nan m is out of range"),
    (math.inf, "face_width = inf m is out of range"),
    ("abc", "face_width = 'abc': expected a number in m, valid range 0 < x <= 10 m"),
    (None, "face_width = None: expected a number in m"),
    (True, "face_width = True: expected a number in m, not a boolean"),
    ([1.0], "face_width = [1.0]: expected a number in m"),
])
def test_check_range_names_field_value_unit_and_range(value: Any, needle: str) -> None:
    with pytest.raises(InputError) as info:
        check_range("face_width", value, "m", low=0.0, high=10.0, low_open=True)
    assert needle in str(info.value)


def test_check_range_accepts_and_converts() -> None:
    assert check_range("x", 3, "m", low=0) == 3.0 and isinstance(check_range("x", 3), float)
    assert check_range("x", np.float32(0.5), "", low=0.0, high=1.0) == 0.5


@pytest.mark.parametrize(("raw", "needle"), [
    ("6 kg", "f.toml: gear.module = '6 kg': wrong unit; expected a length (e.g. '6 mm')"),
    ("6 mm mm", "wrong unit"),
    ("six mm", "not a number with a unit"),
    ("nan mm", "must be a finite number"),
    (math.nan, "must be a finite number"),
    ("-6 mm", "is out of range: valid range 0 < x <= 1000 mm"),  # in the unit written
    ("2 m", "'2 m' is out of range: valid range 0 < x <= 1 m"),
    ("1e-40 m", "below the smallest meaningful magnitude"),
    (True, "expected a length"),
    (0.006, 'f.toml: gear.module = 0.006: give a unit, e.g. "0.006 m" (or "0.006 mm"'),
    ("6", 'f.toml: gear.module = 6: give a unit, e.g. "6 mm" (or "6 um" or "6 m")'),
    ([6], "expected a length"),
    ({"a": 1}, "expected a length"),
])
def test_scene_field_messages(raw: Any, needle: str) -> None:
    """A scene value: file and key path, the value as written, the unit expected, the range."""
    f = Field("module", "m", default=None, low=0.0, high=1.0, low_open=True)
    with pytest.raises(SceneError) as info:
        f.parse(raw, "f.toml: gear.module")
    msg = str(info.value)
    assert msg.startswith("f.toml: gear.module") and needle in msg


def test_unknown_keys_and_tables_suggest_the_right_one() -> None:
    base = {"gear": {"teeth_pinion": 20, "teeth_gear": 40, "module": "2 mm",
                     "face_width": "10 mm"},
            "operating": {"speed": "100 rad/s", "torque": "1 N*m"}}
    with pytest.raises(SceneError, match=r"s.toml: gear.modul: unknown key; did you mean "
                       r"'module'\?"):
        parse_scene({**base, "gear": {**base["gear"], "modul": 1}}, "s.toml")
    with pytest.raises(SceneError, match=r"s.toml: \[operatng\]: unknown table; did you mean "
                       r"\[operating\]\?"):
        parse_scene({**base, "operatng": {}}, "s.toml")
    with pytest.raises(SceneError, match=r"s.toml: operating.torque: missing required key"):
        parse_scene({**base, "operating": {"speed": "100 rad/s"}}, "s.toml")
    with pytest.raises(SceneError, match=r"s.toml: \[operating\]: missing required table"):
        parse_scene({"gear": base["gear"]}, "s.toml")
    with pytest.raises(SceneError, match=r"s.toml: solver.method = 'dop853': valid choices "
                       r"are .*did you mean 'DOP853'\?"):
        parse_scene({**base, "solver": {"method": "dop853"}}, "s.toml")
    with pytest.raises(SceneError, match=r"s.toml: gear.teeth_pinion = 20.5: expected a whole"):
        parse_scene({**base, "gear": {**base["gear"], "teeth_pinion": 20.5}}, "s.toml")


@pytest.mark.parametrize(("kw", "needle"), [
    ({"z1": 9}, "z1 = 9: the pinion is undercut"),
    ({"addendum_coef": 0.55}, "contact_ratio = 0.9874"),
    ({"x1": 1.4}, "x1 = 1.4: tip of pinion is pointed"),
    ({"center_distance": 0.0869}, "center_distance = 86.9 mm: teeth overlap (backlash -68"),
    ({"center_distance": 0.0864}, "center_distance = 86.4 mm: negative tip clearance"),
    ({"center_distance": 0.0885}, "contact_ratio = 0.9926"),
    ({"helix_angle": 1e-9}, "helix_angle = 1e-09 rad: valid range 0 (spur) or 0.0001"),
    ({"z1": 40, "z2": 200, "pressure_angle": math.radians(14.5), "x2": -0.8,
      "addendum_coef": 1.25}, "z1 = 40, z2 = 200: involute interference"),
])
def test_impossible_pairs(kw: dict[str, Any], needle: str) -> None:
    """Contact ratio below 1, undercut, pointed tip, overlapping teeth, negative tip clearance:
    each its own message (z 23/64 (or 9/64), m 2 mm, 20 deg; zero-backlash a_w = 87 mm, tip
    clearance c* m = 0.5 mm)."""
    args: dict[str, Any] = {"z1": 23, "z2": 64, "module": 2e-3,
                            "pressure_angle": math.radians(20), "face_width": 0.02, **kw}
    with pytest.raises(InputError) as info:
        GearPair(**args)
    assert needle in str(info.value)


def test_api_errors_from_a_scene_name_the_scene_keys() -> None:
    """GearPair's z1/x1 become gear.teeth_pinion/gear.profile_shift_pinion when the error comes
    from a scene; prose is left alone, SceneErrors pass through."""
    exc = InputError("z1 = 9: undercut (needs z1 >= 17.1 at x1 = 0, or x1 >= 0.47); "
                     "raise the speed")
    msg = str(scene_error("a.toml", exc))
    assert msg == ("a.toml: gear.teeth_pinion = 9: undercut (needs gear.teeth_pinion >= 17.1 at "
                   "gear.profile_shift_pinion = 0, or gear.profile_shift_pinion >= 0.47); "
                   "raise the speed")
    same = SceneError("b.toml: x")
    assert scene_error("a.toml", same) is same
    advice = InputError("contact_ratio = 0.9: check center_distance and addendum_coef")
    assert str(scene_error("a.toml", advice)) == (
        "a.toml: contact_ratio = 0.9: check gear.center_distance and gear.addendum_coef")
    prose = InputError("the torque and speed are fine")
    assert str(scene_error("a.toml", prose)) == "a.toml: the torque and speed are fine"


def test_scene_pair_errors_use_key_paths_throughout() -> None:
    """An impossible pair from a scene: every parameter named by its key path."""
    base = {"gear": {"teeth_pinion": 23, "teeth_gear": 64, "module": "2 mm",
                     "face_width": "20 mm", "profile_shift_pinion": 1.4},
            "operating": {"speed": "1000 rpm", "torque": "10 N*m"}}
    from gear_dyn.scene import build_pair

    with pytest.raises(SceneError) as info:
        build_pair(parse_scene(base, "p.toml"))
    msg = str(info.value)
    assert msg.startswith("p.toml: gear.profile_shift_pinion = 1.4: tip of pinion is pointed")
    assert "reduce gear.profile_shift_pinion or gear.addendum_coef" in msg
    assert " x1" not in msg


@dataclass(frozen=True)
class _Blowup(ModelDefaults):
    """y' = y^2, y(0) = 1: the exact solution 1 / (1 - t) blows up at t = 1 s."""

    state_labels: tuple[str, ...] = ("y",)
    mesh_frequency: float = 10.0
    static_load: float = 1.0
    state_scale: Any = field(default_factory=lambda: np.array([1.0]))

    def initial_state(self) -> Any:
        return np.array([1.0])

    def rhs(self, t: float, y: Any) -> Any:
        return y**2

    def jac(self, t: float, y: Any) -> Any:
        return np.array([[2 * y[0]]])

    def switching_times(self, t0: float, t1: float) -> Any:
        return np.empty(0)

    def outputs(self, t: Any, y: Any) -> dict[str, Any]:
        return {"dte": y[0], "mesh_force": y[0]}


def test_solver_failure_carries_scipys_message_and_advice() -> None:
    """Integrating through the blow-up: SolverError with solve_ivp's own reason and what to
    try next (a smaller tolerance, an implicit method)."""
    with np.errstate(over="ignore", invalid="ignore"), pytest.raises(SolverError) as info:
        simulate(_Blowup(), 2.0, SolverSettings(method="RK45", rtol=1e-6))
    msg = str(info.value)
    assert "RK45" in msg
    assert "Required step size is less than spacing between numbers" in msg or "non-finite" in msg
    assert "implicit method" in msg or "diverges" in msg


def test_solver_settings_messages() -> None:
    with pytest.raises(InputError, match=r"solver.rtol = 0.5 is out of range: valid range "
                       r"1e-13 <= x <= 0.01"):
        SolverSettings(rtol=0.5)
    with pytest.raises(InputError, match=r"solver.method = 'Euler': valid choices are"):
        SolverSettings(method="Euler")
