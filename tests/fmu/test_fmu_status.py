"""Status semantics of refused FMI calls, through fmpy, for the FMI 2 and the FMI 3 pythonfmu
FMU: a call the FMU refuses fails (pythonfmu maps every Python exception to Fatal, 4) with one
message (status Error, 3) naming the FMI call and the reason, and the instance then runs on as
if the call had not been made (the native FMU returns fmi2Error/fmi3Error:
tests/fmu/test_native_fmu.py)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from gear_dyn.fmu.build import build_fmu
from gear_dyn.fmu.session3 import open_session

pytestmark = pytest.mark.fmu

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"
H = 1 / (16 * 23 * 3319 / 60)  # 16 steps per mesh period of helicopter_tail
OUT = ["dte", "mesh_force", "state.x", "state.v"]

#: fmpy's method names per FMI version: get Real/Float64, deserialize, set and free a state
CALLS = {2: ("getReal", "deSerializeFMUstate", "setFMUstate", "freeFMUstate"),
         3: ("getFloat64", "deserializeFMUState", "setFMUState", "freeFMUState")}
#: the FMI function names in the refusal messages
NAMES = {2: ("fmi2DoStep", "fmi2GetReal", "fmi2SetFMUstate"),
         3: ("fmi3DoStep", "fmi3GetFloat64", "fmi3SetFMUState")}


@pytest.fixture(scope="module", params=[2, 3])
def fmu(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory
        ) -> tuple[int, Path]:
    fmi = request.param
    if fmi == 3:
        pytest.importorskip("pythonfmu3", reason="FMI 3 export needs pythonfmu3 (extra fmi3)")
    built = build_fmu(SCENES / "helicopter_tail.toml", tmp_path_factory.mktemp("st") / "h.fmu",
                      fmi=fmi)
    return fmi, built.path


def _refused(s: Any, call: Callable[..., Any], *args: Any) -> str:
    """Make the call, expect status Fatal (4, pythonfmu's status of a raised exception), the
    slave's one message (status Error) and then only pythonfmu's technical one ("Fatal py
    exception encountered"); return the slave's text (``s``: an FMI 2 or FMI 3 session)."""
    from fmpy.fmi1 import FMICallException

    before = len(s.messages)
    with pytest.raises(FMICallException) as info:
        call(*args)
    assert info.value.status == 4, (info.value.status, s.messages[before:])
    new = s.messages[before:]
    assert new and new[0][0] == 3, new
    assert all(m[0] == 4 and m[1].startswith("Fatal py exception encountered") for m in new[1:])
    assert len(new) <= 2, new
    return new[0][1]


def _steps(s: Any, k0: int, n: int) -> list[list[float]]:
    rows = []
    for k in range(k0, k0 + n):
        s.fmu.doStep(k * H, H)
        rows.append(s.get(OUT))
    return rows


def test_refused_calls_are_error_and_the_run_goes_on(fmu: tuple[int, Path]) -> None:
    """doStep before initialization, from the wrong time and with a bad step; getReal
    (getFloat64) of an Integer; setting a state that is not one: each refused with one message
    naming the call; the run then gives exactly the undisturbed run's outputs.
    After terminate, doStep is refused the same way and reset gives the run again."""
    fmi, path = fmu
    get_real, deserialize, set_state, free_state = CALLS[fmi]
    do_step, get_name, set_name = NAMES[fmi]
    with open_session(path) as ref:
        ref.instantiate()
        ref.initialize()
        normal = _steps(ref, 0, 8)
    with open_session(path) as s:
        s.instantiate()
        text = _refused(s, s.fmu.doStep, 0.0, H)
        assert text.startswith(f"{do_step} refused:") and "initialize the FMU first" in text
        s.initialize()
        got = _steps(s, 0, 3)
        text = _refused(s, s.fmu.doStep, 7 * H, H)
        assert text.startswith(f"{do_step} refused:") and "the FMU is at" in text, text
        text = _refused(s, s.fmu.doStep, 3 * H, -H)
        assert "communication step" in text and "valid range > 0 s" in text, text
        vr = s.vars["gear.teeth_pinion"].valueReference
        text = _refused(s, getattr(s.fmu, get_real), [vr])
        assert text.startswith(f"{get_name} refused:") and "not a Real" in text, text
        state = getattr(s.fmu, deserialize)(b"not a state")  # read lazily: refused when set
        text = _refused(s, getattr(s.fmu, set_state), state)
        assert text.startswith(f"{set_name} refused:") and "not an FMU state" in text
        getattr(s.fmu, free_state)(state)
        got += _steps(s, 3, 5)
        np.testing.assert_array_equal(np.array(got), np.array(normal))
        s.fmu.terminate()
        text = _refused(s, s.fmu.doStep, 8 * H, H)
        assert "doStep in state terminated" in text, text
        s.fmu.reset()
        s.initialize()
        np.testing.assert_array_equal(np.array(_steps(s, 0, 8)), np.array(normal))
