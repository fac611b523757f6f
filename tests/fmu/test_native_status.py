"""The native FMU (FMI 2 and 3) through fmpy's low-level API: every call the standard forbids
and every bad state is answered with Error (fmpy raises FMICallException with status 3) and
one logged message (status Error) that names the FMI call, and the instance then runs on as if
the call had not been made. The same calls under AddressSanitizer and UBSan: the C drivers of
tests/fmu/native_drivers.py (test_native_kernel.py, test_native_torsional.py)."""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import pytest
from native_harness import Slave

pytestmark = [pytest.mark.fmu,
              pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc) on PATH")]
fmpy = pytest.importorskip("fmpy")
from fmpy.fmi1 import FMICallException  # noqa: E402

SCENE = "helicopter_tail_backlash"
H = 1e-5  # s, below a mesh period (1/1272 s)


@pytest.fixture(scope="module")
def fmus(tmp_path_factory: pytest.TempPathFactory) -> dict[tuple[str, int], Path]:
    """The scene's FMU, FMI 2 and 3, and a second build of it (another instantiation token)."""
    from gear_dyn.fmu.export_fmu import build_native_fmu

    d = tmp_path_factory.mktemp("status")
    return {(tag, fmi): build_native_fmu(SCENE, d / f"{tag}{fmi}.fmu", fmi=fmi).path
            for tag in ("a", "b") for fmi in (2, 3)}


def _refused(run: Slave, call, *args, match: str) -> None:
    """``call(*args)`` fails with status Error and logs exactly one Error naming ``match``."""
    n = len(run.log)
    with pytest.raises(FMICallException, match="status 3"):
        call(*args)
    assert len(run.log) == n + 1, run.log[n:]
    status, msg = run.log[-1]
    assert status == 3 and match in msg, msg


@pytest.mark.parametrize("fmi", [2, 3])
def test_forbidden_steps_are_errors_and_the_run_goes_on(fmus, fmi: int) -> None:
    """doStep before initialization, with a step of 0, negative, NaN or infinite, from another
    time than the FMU's (at 5 h asked for 50 h) and after terminate: Error; between the refusals
    the run gives the undisturbed run's DTE bit for bit."""
    name = f"fmi{fmi}DoStep"
    clean = Slave(fmus["a", fmi], fmi)
    clean.start(None)
    expected = clean.steps(H, 10)
    clean.close()
    run = Slave(fmus["a", fmi], fmi)
    _refused(run, run.fmu.doStep, 0.0, H, match=f"{name}: called before initialization")
    run.start(None)
    for h in (0.0, -H, math.nan, math.inf):
        _refused(run, run.fmu.doStep, 0.0, h, match=f"{name}: communicationStepSize")
    got = run.steps(H, 5)
    _refused(run, run.fmu.doStep, 50 * H, H, match=f"{name}: currentCommunicationPoint = ")
    assert "but the FMU is at t = 5" in run.log[-1][1]
    got += run.steps(H, 5, k0=5)
    assert got == expected
    run.fmu.terminate()
    _refused(run, run.fmu.doStep, 10 * H, H, match=f"{name}: called after Terminate")
    run.fmu.freeInstance()


@pytest.mark.parametrize("fmi", [2, 3])
def test_bad_states_are_errors(fmus, fmi: int) -> None:
    """A serialized state cut short, with random bytes, with a table piece out of range or a
    NaN (a corrupted one), or of another build of the same scene (its token): Error on
    deserialization; the instance's own state then restores the run bit for bit."""
    import numpy as np

    names = {2: ("serializeFMUstate", "deSerializeFMUstate", "getFMUstate", "setFMUstate"),
             3: ("serializeFMUState", "deserializeFMUState", "getFMUState", "setFMUState")}[fmi]
    run, other = Slave(fmus["a", fmi], fmi), Slave(fmus["b", fmi], fmi)
    ser, deser, get, put = (getattr(run.fmu, n) for n in names)
    call = {2: "fmi2DeSerializeFMUstate", 3: "fmi3DeserializeFMUState"}[fmi]
    for r in (run, other):
        r.start(None)
        r.steps(H, 10)
    good = bytes(ser(get()))
    foreign = bytes(getattr(other.fmu, names[0])(getattr(other.fmu, names[2])()))
    assert len(foreign) == len(good)
    rng = np.random.default_rng(7)
    corrupt = bytearray(good)
    corrupt[100:] = rng.integers(0, 256, len(good) - 100, dtype=np.uint8).tobytes()
    cases = {"cut": (good[:-1], "a state of"), "random": (rng.bytes(len(good)), "not a gear"),
             "corrupt": (bytes(corrupt), ""), "foreign": (foreign, "the state of another FMU")}
    for blob, match in cases.values():
        _refused(run, deser, blob, match=f"{call}: refused: {match}")
    first = run.steps(H, 5, k0=10)
    put(deser(good))
    assert run.steps(H, 5, k0=10) == first
    other.close()
    run.close()


@pytest.mark.parametrize("fmi", [2, 3])
def test_instantiation_token_is_checked(fmus, fmi: int) -> None:
    """Instantiation with the token of another build: no instance, one Error message."""
    md_b = fmpy.read_model_description(str(fmus["b", fmi]))
    run = Slave(fmus["a", fmi], fmi)  # the right token instantiates
    run.close()
    log: list[tuple[int, str]] = []
    unzipped = fmpy.extract(str(fmus["a", fmi]))
    kw = dict(guid=md_b.guid, unzipDirectory=unzipped, instanceName="x",
              modelIdentifier=md_b.coSimulation.modelIdentifier)
    if fmi == 2:
        fmu = fmpy.fmi2.FMU2Slave(**kw)
        with pytest.raises(Exception, match="instantiate"):
            fmu.instantiate(loggingOn=True)
    else:
        fmu = fmpy.fmi3.FMU3Slave(**kw)
        with pytest.raises(Exception, match="instantiate"):
            fmu.instantiate(loggingOn=True, logMessage=lambda env, status, cat, msg:
                            log.append((status, msg.decode())))
        assert log == [(3, "the instantiationToken is not this FMU's (see its "
                           "modelDescription.xml)")]


@pytest.mark.parametrize("fmi", [2, 3])
def test_outputs_in_initialization_mode_are_the_start_state(fmus, fmi: int) -> None:
    """In initialization mode the outputs are those of the start state the values set so far
    give (hosts such as libcosim read them to start their connections): the same, bit for bit,
    as after ExitInitializationMode, also after an input is changed in initialization mode."""
    run = Slave(fmus["a", fmi], fmi)
    if fmi == 2:
        run.fmu.setupExperiment(startTime=0.0)
        run.fmu.enterInitializationMode()
    else:
        run.fmu.enterInitializationMode(startTime=0.0)
    run.set("operating.torque", 0.8 * run.get("operating.torque"))
    names = ["dte", "state.v", "mesh_force"]
    during = [run.get(n) for n in names]
    run.fmu.exitInitializationMode()
    assert [run.get(n) for n in names] == during
    assert during[0] != 0.0  # the static deflection, not a zeroed state
    run.close()
