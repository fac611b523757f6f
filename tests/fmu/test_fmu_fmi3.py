"""The FMI 3.0 FMU (``gear-dyn fmu build --fmi 3``, pythonfmu3): valid for fmpy, the same
variables and outputs as the FMI 2 FMU of the same scene, slim, loadable outside Python."""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import numpy as np
import pytest

from gear_dyn.errors import InputError
from gear_dyn.fmu.build import build_fmu
from gear_dyn.fmu.session3 import Fmu3Session, fmi_version, open_session

pytest.importorskip("pythonfmu3", reason="FMI 3 export needs pythonfmu3 (extra fmi3)")

pytestmark = pytest.mark.fmu

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"
#: the helicopter tail scene (the demo) and its backlash variant
NAMES = ("helicopter_tail", "helicopter_tail_backlash")
AGREEMENT = 1e-12


@pytest.fixture(scope="module")
def fmus(tmp_path_factory: pytest.TempPathFactory) -> dict[str, dict[int, Path]]:
    """Each scene built once as FMI 2 and as FMI 3."""
    d = tmp_path_factory.mktemp("fmi3")
    return {name: {fmi: build_fmu(SCENES / f"{name}.toml", d / f"{name}_{fmi}.fmu", fmi=fmi).path
                   for fmi in (2, 3)} for name in NAMES}


def _spec_outputs(fmu: Path) -> tuple[list[str], float, float]:
    from gear_dyn.fmu.build import read_spec

    spec = read_spec(fmu)
    names = [v["name"] for v in spec["variables"] if v["causality"] == "output"]
    return names, 1 / (16 * spec["mesh_frequency"]), spec["mesh_frequency"]


def _rows(fmu: Path, names: list[str], stop: float | None, h: float, n: int,
          change_at: int | None = None) -> np.ndarray:
    """Outputs after initialization and each of ``n`` steps; with ``change_at`` the pinion
    speed input rises by 5 % before that step."""
    with open_session(fmu) as s:
        s.instantiate()
        s.initialize(0.0, stop)
        rows = [s.get(names)]
        for k in range(n):
            if k == change_at:
                speed = s.vars["operating.speed"].start
                s.set({"operating.speed": 1.05 * float(speed)})
            s.step(k * h, h)
            rows.append(s.get(names))
        s.terminate()
    return np.array(rows)


def _md(fmu: Path) -> ET.Element:
    return ET.fromstring(zipfile.ZipFile(fmu).read("modelDescription.xml"))


@pytest.mark.parametrize("name", NAMES)
def test_fmi3_gives_the_fmi2_outputs(fmus: dict[str, dict[int, Path]], name: str) -> None:
    """Same scene, same grid (96 steps, 16 per mesh period): the FMI 3 outputs equal the FMI 2
    outputs to 1e-12 of each output's largest value, without a stop time, with one announced
    (both FMUs), and with an input change after 40 steps. Both FMUs run in this one process."""
    f2, f3 = fmus[name][2], fmus[name][3]
    assert fmi_version(f3) == "3.0" and fmi_version(f2) == "2.0"
    names, h, _ = _spec_outputs(f3)
    n = 96
    ref = _rows(f2, names, None, h, n)
    scale = np.max(np.abs(ref), axis=0) + 1e-300
    for stop in (None, n * h):
        for fmu in (f3, f2):
            got = _rows(fmu, names, stop, h, n)
            assert np.all(np.abs(got - ref) <= AGREEMENT * scale), (fmu.name, stop)
    changed2 = _rows(f2, names, None, h, n, change_at=40)
    changed3 = _rows(f3, names, n * h, h, n, change_at=40)
    assert np.max(np.abs(changed2[-1] - ref[-1]) / scale) > 1e-6  # the input did act
    assert np.all(np.abs(changed3 - changed2) <= AGREEMENT * scale)


def test_fmi3_simulates_with_fmpy_simulate_fmu(fmus: dict[str, dict[int, Path]]) -> None:
    """fmpy's standard importer path (simulate_fmu, FMI 3) gives the FMI 2 FMU's outputs."""
    from fmpy import simulate_fmu

    f3 = fmus["helicopter_tail"][3]
    names, h, _ = _spec_outputs(f3)
    n = 32
    res = simulate_fmu(str(f3), stop_time=n * h, output_interval=h, output=names)
    ref = _rows(fmus["helicopter_tail"][2], names, None, h, n)
    got = np.column_stack([res[k] for k in names])
    assert got.shape == ref.shape
    np.testing.assert_allclose(res["time"], h * np.arange(n + 1), rtol=1e-12, atol=1e-15)
    scale = np.max(np.abs(ref), axis=0) + 1e-300
    assert np.all(np.abs(got - ref) <= AGREEMENT * scale)


def test_fmi3_model_description_matches_fmi2(fmus: dict[str, dict[int, Path]]) -> None:
    """fmpy validation finds no problem; every FMI 2 variable is there with the same value
    reference, causality, unit, min/max/nominal and start; choices are Enumerations with the
    FMI 2 items; outputs declare no dependencies; ``time`` is the independent variable."""
    from fmpy.validation import validate_fmu

    for name in NAMES:
        f2, f3 = fmus[name][2], fmus[name][3]
        assert validate_fmu(str(f3)) == []
        r2, r3 = _md(f2), _md(f3)
        assert r3.get("fmiVersion") == "3.0"
        cs = r3.find("CoSimulation")
        assert cs is not None and cs.get("canHandleVariableCommunicationStepSize") == "true"
        mv = r3.find("ModelVariables")
        assert mv is not None
        v3 = {el.get("name"): el for el in mv}
        assert v3["time"].get("causality") == "independent"
        for sv in r2.iter("ScalarVariable"):
            el, typed = v3[sv.get("name")], next(iter(sv))
            assert el.get("valueReference") == sv.get("valueReference")
            assert el.get("causality") == sv.get("causality")
            kind = {"Real": "Float64", "Integer": "Int32"}.get(typed.tag, typed.tag)
            assert el.tag == kind, sv.get("name")
            for key in ("unit", "min", "max", "nominal", "declaredType"):
                assert el.get(key) == typed.get(key), (sv.get("name"), key)
            if typed.get("start") is not None and kind != "Float64":
                assert el.get("start") == typed.get("start")
            elif typed.get("start") is not None:
                assert float(el.get("start")) == float(typed.get("start"))
        items2 = {st.get("name"): [(i.get("name"), i.get("value")) for i in st.iter("Item")]
                  for st in r2.iter("SimpleType")}
        items3 = {et.get("name"): [(i.get("name"), i.get("value")) for i in et.iter("Item")]
                  for et in r3.iter("EnumerationType")}
        assert items3 == items2 and items3
        outputs = r3.find("ModelStructure").findall("Output")
        assert len(outputs) == sum(sv.get("causality") == "output"
                                   for sv in r2.iter("ScalarVariable"))
        assert all(o.get("dependencies") == "" for o in outputs)


def test_fmi3_fmu_is_slim(fmus: dict[str, dict[int, Path]]) -> None:
    """Only the model and solver code: no CLI, plots, build side or FMI 2 slave (pythonfmu)."""
    files = zipfile.ZipFile(fmus["helicopter_tail"][3]).namelist()
    private = [f for f in files if "/gear_dyn_fmu_" in f]
    assert any(f.endswith("/fmu/slave3.py") for f in private)
    for part in ("/cli/", "/plots/", "/fmu/slave.py", "/fmu/build", "/fmu/staging.py",
                 "/fmu/check.py",
                 "/fmu/cosim.py", "/scenes/"):
        assert not any(part in f for f in private), part
    assert not any("matplotlib" in f or f.startswith("resources/pythonfmu/") for f in files)
    assert any(f.startswith("resources/pythonfmu3/") for f in files)
    assert not any(f.startswith("sources/") for f in files)


def test_fmi3_bad_parameter_is_refused_and_instance_survives(
        fmus: dict[str, dict[int, Path]]) -> None:
    """A bad value: fmi3Set* fails (fmi3Fatal, pythonfmu3's status of a raised exception; the
    instance stays valid), the host gets one message (status Error) naming the parameter, its
    value and the valid range, the old value stays; a pair that cannot mesh fails at
    exitInitializationMode; afterwards the same instance runs and gives a fresh instance's
    outputs bit for bit."""
    from fmpy.fmi1 import FMICallException

    f3 = fmus["helicopter_tail"][3]
    names, h, _ = _spec_outputs(f3)
    fresh = _rows(f3, names, None, h, 6)
    with Fmu3Session(f3) as s:
        s.instantiate()
        vr = s.vars["gear.teeth_pinion"].valueReference
        with pytest.raises(FMICallException) as info:
            s.fmu.setInt32([vr], [0])
        assert info.value.status == 4  # the slave's message, then pythonfmu3's technical one
        assert s.messages[0][0] == 3 and len(s.messages) <= 2, s.messages
        assert re.search(r"gear\.teeth_pinion = '0'.*valid range 5 <= x <= 10000",
                         s.messages[0][1])
        assert s.fmu.getInt32([vr]) == [23]
        with pytest.raises(InputError, match=r"solver\.method = 99: valid range 1 <= x <= 9"):
            s.set({"solver.method": 99})
        with pytest.raises(InputError, match=r"gear\.pressure_angle.*valid range"):
            s.set({"gear.pressure_angle": 2.0})
        s.fmu.enterInitializationMode()
        s.set({"gear.addendum_coef": 0.5})  # valid alone, but the pair no longer meshes
        with pytest.raises(FMICallException) as info:
            s.fmu.exitInitializationMode()
        assert info.value.status == 4
        assert any("contact_ratio" in m[1] for m in s.messages[-2:] if m[0] == 3), s.messages
        s.set({"gear.addendum_coef": 1.0})
        s.fmu.exitInitializationMode()
        rows = [s.get(names)]
        for k in range(6):
            s.step(k * h, h)
            rows.append(s.get(names))
    np.testing.assert_array_equal(np.array(rows), fresh)


def test_fmi3_refuses_a_start_time_it_cannot_honour(fmus: dict[str, dict[int, Path]]) -> None:
    """pythonfmu3 does not pass the start time on: a first doStep from t != 0 is refused with
    a message saying so (not silently run from 0)."""
    f3 = fmus["helicopter_tail"][3]
    _, h, _ = _spec_outputs(f3)
    from gear_dyn.errors import SolverError

    with Fmu3Session(f3) as s:
        s.instantiate()
        s.initialize(0.5)
        with pytest.raises(SolverError, match="starts at 0 s"):
            s.step(0.5, h)


def test_fmu_check_cli_on_fmi3(fmus: dict[str, dict[int, Path]],
                               capsys: pytest.CaptureFixture[str]) -> None:
    """`gear-dyn fmu check` recognises the FMI 3 FMU: every line runs and passes (the C host
    line is skipped: a pythonfmu FMU runs in Python hosts only)."""
    from gear_dyn.cli import main

    code = main(["fmu", "check", str(fmus["helicopter_tail"][3]), "--steps", "16"])
    out = capsys.readouterr().out
    assert code == 0, out
    assert "FMI 3.0: no problems" in out
    for name in ("fmpy run", "stop-time independence", "C host"):
        assert name in out
    assert "FAIL" not in out and "verdict: PASS" in out


def test_fmi3_fmu_state_restores_the_run_bit_for_bit(fmus: dict[str, dict[int, Path]]) -> None:
    """Get the state after 20 steps (backlash scene, with a speed change before step 10), run
    20 more; set the state (and its serialised copy, deserialised) and run again: the same
    outputs bit for bit."""
    f3 = fmus["helicopter_tail_backlash"][3]
    names, h, _ = _spec_outputs(f3)

    def run(s: Fmu3Session, k0: int, n: int) -> np.ndarray:
        rows = []
        for k in range(k0, k0 + n):
            s.step(k * h, h)
            rows.append(s.get(names))
        return np.array(rows)

    with Fmu3Session(f3) as s:
        s.instantiate()
        s.initialize()
        run(s, 0, 10)
        s.set({"operating.speed": 1.05 * float(s.vars["operating.speed"].start)})
        run(s, 10, 10)
        state = s.fmu.getFMUState()
        blob = s.fmu.serializeFMUState(state)
        first = run(s, 20, 20)
        s.fmu.setFMUState(state)
        again = run(s, 20, 20)
        restored = s.fmu.deserializeFMUState(blob)
        s.fmu.setFMUState(restored)
        from_bytes = run(s, 20, 20)
        s.fmu.freeFMUState(state)
        s.fmu.freeFMUState(restored)
    np.testing.assert_array_equal(again, first)
    np.testing.assert_array_equal(from_bytes, first)


def test_cosim_runs_fmi3_as_fmi2(fmus: dict[str, dict[int, Path]]) -> None:
    """`gear-dyn cosim` (``compare``) runs the FMI 3 FMU as the FMI 2 one: the same reference,
    the same DTE differences (the two FMUs give the same outputs) and PASS; the FMI 2 session
    itself refuses an FMI 3 FMU with a message naming the way to either."""
    from gear_dyn.fmu.cosim import FmuSession, compare

    f_m = 23 * 3319 / 60  # helicopter_tail: z1 n1, Hz
    reports = {fmi: compare(fmus["helicopter_tail"][fmi], stop_time=2 / f_m) for fmi in (2, 3)}
    assert all(r.passed for r in reports.values())
    for a, b in zip(reports[2].steps, reports[3].steps, strict=True):
        assert b.max_diff["dte"] == pytest.approx(a.max_diff["dte"], rel=1e-6, abs=1e-20)
    with pytest.raises(InputError, match="an FMI 3.0 FMU, not FMI 2.0 .open_session"):
        FmuSession(fmus["helicopter_tail"][3])
