"""Status semantics of refused FMI calls, through fmpy: a call the FMU refuses while keeping
the instance usable returns fmi2Error (3), not fmi2Fatal (4), with one message naming the FMI
call and the reason, and the instance then runs on as if the call had not been made."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from gear_dyn.fmu.build import build_fmu
from gear_dyn.fmu.cosim import FmuSession

pytestmark = pytest.mark.fmu

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"
H = 1 / (16 * 23 * 3319 / 60)  # 16 steps per seed 002 mesh period
OUT = ["dte", "mesh_force", "state.x", "state.v"]


@pytest.fixture(scope="module")
def fmu(tmp_path_factory: pytest.TempPathFactory) -> Path:
    built = build_fmu(SCENES / "helicopter_tail.toml", tmp_path_factory.mktemp("st") / "h.fmu")
    if built.c_host_missing is not None:  # fmi2Error needs the boot library (see pyboot.c)
        pytest.skip(f"no boot library in the FMU, refusals stay fmi2Fatal: "
                    f"{built.c_host_missing}")
    return built.path


def _refused(s: Any, call: Callable[..., Any], *args: Any) -> str:
    """Make the call, expect status Error (3) and exactly one new message; return its text
    (``s``: an FMI 2 or FMI 3 session)."""
    from fmpy.fmi1 import FMICallException

    before = len(s.messages)
    with pytest.raises(FMICallException) as info:
        call(*args)
    assert info.value.status == 3, (info.value.status, s.messages[before:])
    new = s.messages[before:]
    assert len(new) == 1, new
    assert new[0][0] == 3
    return new[0][1]


def _steps(s: FmuSession, k0: int, n: int) -> list[list[float]]:
    rows = []
    for k in range(k0, k0 + n):
        s.fmu.doStep(k * H, H)
        rows.append(s.get(OUT))
    return rows


def test_refused_calls_are_fmi2_error_and_the_run_goes_on(fmu: Path) -> None:
    """doStep before initialization, from the wrong time and with a bad step; getReal of an
    Integer; setting a state that is not one: each refused with fmi2Error and one message
    naming the call; the run then gives exactly the undisturbed run's outputs. After
    terminate, doStep is refused the same way and fmi2Reset gives the run again."""
    with FmuSession(fmu) as ref:
        ref.instantiate()
        ref.initialize()
        normal = _steps(ref, 0, 8)
    with FmuSession(fmu) as s:
        s.instantiate()
        text = _refused(s, s.fmu.doStep, 0.0, H)
        assert text.startswith("fmi2DoStep refused:") and "initialize the FMU first" in text
        s.initialize()
        got = _steps(s, 0, 3)
        text = _refused(s, s.fmu.doStep, 7 * H, H)
        assert text.startswith("fmi2DoStep refused:") and "the FMU is at" in text, text
        text = _refused(s, s.fmu.doStep, 3 * H, -H)
        assert "communication step" in text and "valid range > 0 s" in text, text
        text = _refused(s, s.fmu.getReal, [s.vr("gear.teeth_pinion")])
        assert text.startswith("fmi2GetReal refused:") and "not a Real" in text, text
        state = s.fmu.deSerializeFMUstate(b"not a state")  # read lazily: refused when set
        text = _refused(s, s.fmu.setFMUstate, state)
        assert text.startswith("fmi2SetFMUstate refused:") and "not an FMU state" in text
        s.fmu.freeFMUstate(state)
        got += _steps(s, 3, 5)
        np.testing.assert_array_equal(np.array(got), np.array(normal))
        s.fmu.terminate()
        text = _refused(s, s.fmu.doStep, 8 * H, H)
        assert "doStep in state terminated" in text, text
        s.fmu.reset()
        s.initialize()
        np.testing.assert_array_equal(np.array(_steps(s, 0, 8)), np.array(normal))


@pytest.fixture(scope="module")
def fmu3(tmp_path_factory: pytest.TempPathFactory) -> Path:
    pytest.importorskip("pythonfmu3", reason="FMI 3 export needs pythonfmu3 (extra fmi3)")
    built = build_fmu(SCENES / "helicopter_tail.toml", tmp_path_factory.mktemp("st3") / "h.fmu",
                      fmi=3)
    if built.c_host_missing is not None:  # fmi3Error needs the boot library (see pyboot3.c)
        pytest.skip(f"no boot library in the FMU, refusals stay fmi3Fatal: "
                    f"{built.c_host_missing}")
    return built.path


def _steps3(s: Any, k0: int, n: int) -> list[list[float]]:
    rows = []
    for k in range(k0, k0 + n):
        s.fmu.doStep(k * H, H)
        rows.append(s.get(OUT))
    return rows


def test_fmi3_refused_calls_are_fmi3_error_and_the_run_goes_on(fmu3: Path) -> None:
    """The FMI 3 FMU (pythonfmu3): doStep before initialization, from the wrong time and with a
    bad step; getFloat64 of an Int32; setting a state that is not one: each refused with
    fmi3Error (3, not fmi3Fatal) and one message naming the FMI 3 call; the run then gives
    exactly the undisturbed run's outputs. After terminate, doStep is refused the same way and
    fmi3Reset gives the run again."""
    from gear_dyn.fmu.session3 import Fmu3Session

    with Fmu3Session(fmu3) as ref:
        ref.instantiate()
        ref.initialize()
        normal = _steps3(ref, 0, 8)
    with Fmu3Session(fmu3) as s:
        s.instantiate()
        text = _refused(s, s.fmu.doStep, 0.0, H)
        assert text.startswith("fmi3DoStep refused:") and "initialize the FMU first" in text
        s.initialize()
        got = _steps3(s, 0, 3)
        text = _refused(s, s.fmu.doStep, 7 * H, H)
        assert text.startswith("fmi3DoStep refused:") and "the FMU is at" in text, text
        text = _refused(s, s.fmu.doStep, 3 * H, -H)
        assert "communication step" in text and "valid range > 0 s" in text, text
        vr = s.vars["gear.teeth_pinion"].valueReference
        text = _refused(s, s.fmu.getFloat64, [vr])
        assert text.startswith("fmi3GetFloat64 refused:") and "not a Real" in text, text
        state = s.fmu.deserializeFMUState(b"not a state")  # read lazily: refused when set
        text = _refused(s, s.fmu.setFMUState, state)
        assert text.startswith("fmi3SetFMUState refused:") and "not an FMU state" in text
        s.fmu.freeFMUState(state)
        got += _steps3(s, 3, 5)
        np.testing.assert_array_equal(np.array(got), np.array(normal))
        s.fmu.terminate()
        text = _refused(s, s.fmu.doStep, 8 * H, H)
        assert "doStep in state terminated" in text, text
        s.fmu.reset()
        s.initialize()
        np.testing.assert_array_equal(np.array(_steps3(s, 0, 8)), np.array(normal))
