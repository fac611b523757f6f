"""The single-DOF FMU (the helicopter tail of Jiang et al. 2018): built, validated, co-simulated
through fmpy against solve_ivp, and its lifecycle (bad parameters, reset, terminate,
re-instantiation, two instances, FMU state, inputs)."""

from __future__ import annotations

import math
import subprocess
import sys
import textwrap
import xml.etree.ElementTree as ET
import zipfile
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from gear_dyn.errors import InputError, SolverError
from gear_dyn.fmu.build import build_fmu
from gear_dyn.fmu.cosim import FmuSession
from gear_dyn.fmu.stepper import Stepper
from gear_dyn.scene import build_pair, build_plan, load_scene, parse_scene
from gear_dyn.solvers import SolverSettings, integrate

pytestmark = pytest.mark.fmu

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"
#: the helicopter tail mesh frequency from kinematics alone: z1 n1 / 60 = 23 * 3319 / 60 Hz
F_M = 23 * 3319 / 60
H = 1 / (16 * F_M)  # communication step: 16 per mesh period
OUT = ["dte", "mesh_force", "state.v", "driven_speed"]

VARIANT = """
[scene]
name = "heli_variant"
model = "sdof"
[gear]
teeth_pinion = 23
teeth_gear = 64
module = "6 mm"
pressure_angle = "22.5 deg"
face_width = "50 mm"
youngs_modulus = "2.07e5 MPa"
[operating]
speed = "3319 rpm"
torque = "800 N*m"
[inertia]
pinion = "0.05 kg*m^2"
gear = "0.3 kg*m^2"
[damping]
ratio = 0.1
[solver]
periods = 40
samples_per_period = 16
"""


@pytest.fixture(scope="module")
def heli_fmu(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return build_fmu(SCENES / "helicopter_tail.toml",
                     tmp_path_factory.mktemp("fmu") / "heli.fmu").path


@pytest.fixture(scope="module")
def variant_fmu(tmp_path_factory: pytest.TempPathFactory) -> Path:
    d = tmp_path_factory.mktemp("variant")
    (d / "variant.toml").write_text(VARIANT)
    return build_fmu(d / "variant.toml", d / "variant.fmu").path


def _run(session: FmuSession, n: int, values: dict[str, Any] | None = None,
         outputs: list[str] = OUT) -> np.ndarray:
    """Instantiated session: initialize, n steps of H, the outputs after each step."""
    session.initialize(0.0, None, None, values)
    rows = [session.get(outputs)]
    for k in range(n):
        session.step(k * H, H)
        rows.append(session.get(outputs))
    return np.array(rows)


def _solo(fmu: Path, n: int, values: dict[str, Any] | None = None) -> np.ndarray:
    with FmuSession(fmu) as s:
        s.instantiate()
        y = _run(s, n, values)
        s.terminate()
    return y


# ---------------------------------------------------------------------- modelDescription
def test_model_description_valid_and_complete(heli_fmu: Path) -> None:
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(heli_fmu)) == []
    root = ET.fromstring(zipfile.ZipFile(heli_fmu).read("modelDescription.xml"))
    units = {u.get("name"): u for u in root.iter("Unit")}
    svs = root.find("ModelVariables").findall("ScalarVariable")  # type: ignore[union-attr]
    by_name = {sv.get("name"): sv for sv in svs}
    for sv in svs:
        assert sv.get("description"), sv.get("name")
        if sv.get("causality") in ("parameter", "input"):
            assert sv.get("variability") in ("fixed", "continuous")
            assert next(iter(sv)).get("start") is not None, sv.get("name")
        unit = next(iter(sv)).get("unit")
        if unit is not None:
            assert unit in units
    # units by hand: module in m, speed in rad/s shown in rpm (factor 60 / 2 pi), force in N
    assert by_name["gear.module"].find("Real").get("unit") == "m"  # type: ignore[union-attr]
    # physical bounds of the scene fields: z1 in [5, 10000], damping ratio in [0, 10],
    # nominal = |start|
    teeth = by_name["gear.teeth_pinion"].find("Integer").attrib  # type: ignore[union-attr]
    assert (teeth["min"], teeth["max"]) == ("5", "10000")
    ratio = by_name["damping.ratio"].find("Real").attrib  # type: ignore[union-attr]
    assert (float(ratio["min"]), float(ratio["max"])) == (0.0, 10.0)
    assert float(ratio["nominal"]) == float(ratio["start"])
    for sv in svs:
        t = next(iter(sv)).attrib
        if "min" in t and "start" in t:
            assert float(t["min"]) <= float(t["start"]) <= float(t.get("max", "inf"))
    speed = by_name["operating.speed"].find("Real")
    assert speed.get("unit") == "rad/s"  # type: ignore[union-attr]
    assert float(speed.get("start")) == pytest.approx(3319 * 2 * math.pi / 60, rel=1e-12)  # type: ignore[union-attr, arg-type]
    rpm = units["rad/s"].find("DisplayUnit")
    assert rpm.get("name") == "rpm"  # type: ignore[union-attr]
    assert float(rpm.get("factor")) == pytest.approx(60 / (2 * math.pi), rel=1e-15)  # type: ignore[union-attr, arg-type]
    assert units["N"].find("BaseUnit").attrib == {"kg": "1", "m": "1", "s": "-2"}  # type: ignore[union-attr]
    # model structure: every output is an output unknown and an initial unknown
    outputs = [str(i) for i, sv in enumerate(svs, 1) if sv.get("causality") == "output"]
    ms = root.find("ModelStructure")
    assert [u.get("index") for u in ms.find("Outputs")] == outputs  # type: ignore[union-attr]
    assert [u.get("index") for u in ms.find("InitialUnknowns")] == outputs  # type: ignore[union-attr]
    cs = root.find("CoSimulation").attrib  # type: ignore[union-attr]
    assert cs["canGetAndSetFMUstate"] == cs["canSerializeFMUstate"] == "true"
    assert cs["canBeInstantiatedOnlyOncePerProcess"] == "false"
    # DefaultExperiment from the scene: 200 mesh periods, 64 samples per period, rtol 1e-8
    de = root.find("DefaultExperiment").attrib  # type: ignore[union-attr]
    assert float(de["stopTime"]) == pytest.approx(200 / F_M, rel=1e-12)
    assert float(de["stepSize"]) == pytest.approx(1 / (64 * F_M), rel=1e-12)
    assert float(de["tolerance"]) == 1e-8


# ---------------------------------------------------------------------- against solve_ivp
def test_cosim_of_the_helicopter_tail_matches_solve_ivp(heli_fmu: Path) -> None:
    """fmpy.simulate_fmu (the standard importer path) against solve_ivp DOP853.

    The FMU runs the scene's method, the exact propagator, so the whole difference is
    solve_ivp's own error: within 100 rtol of the static deflection x_st (DOP853's global error
    over 10 periods is ~10 rtol x_st), it shrinks >= 10x when solve_ivp's rtol goes 1e-8 ->
    1e-10, and against the exact reference it is rounding (1e-10 x_st)."""
    from fmpy import simulate_fmu

    res = simulate_fmu(str(heli_fmu), stop_time=10 / F_M, output_interval=H,
                       output=["dte", "mesh_force"])
    t = np.asarray(res["time"])
    assert t.size == 161  # not cut short
    plan = build_plan(load_scene(SCENES / "helicopter_tail.toml"))
    model = plan.model
    x_st = model.static_load / model.mean_stiffness
    diffs = {}
    for method, rtol in (("DOP853", 1e-8), ("DOP853", 1e-10), ("exact", 1e-8)):
        y, _ = integrate(model, t, SolverSettings(method=method, rtol=rtol))
        out = model.outputs(t, y)
        diffs[(method, rtol)] = np.max(np.abs(res["dte"] - out["dte"]))
        force_diff = np.max(np.abs(res["mesh_force"] - out["mesh_force"]))
        assert force_diff <= 100 * rtol * model.static_load
    assert diffs[("DOP853", 1e-8)] <= 100 * 1e-8 * x_st
    assert diffs[("DOP853", 1e-10)] <= diffs[("DOP853", 1e-8)] / 10
    assert diffs[("exact", 1e-8)] <= 1e-10 * x_st


def test_fmu_with_dop853_takes_solve_ivp_steps(heli_fmu: Path) -> None:
    """With solver.method = DOP853 the FMU keeps one solver alive across communication points
    and so takes exactly solve_ivp's steps: the difference is rounding (1e-12 x_st), far below
    the 1e-8 a restarted solver would leave."""
    with FmuSession(heli_fmu) as s:
        s.instantiate()
        y = _run(s, 48, {"solver.method": "DOP853"})
    plan = build_plan(load_scene(SCENES / "helicopter_tail.toml"))
    model = plan.model
    t = np.arange(49) * H
    yr, _ = integrate(model, t, SolverSettings(method="DOP853", rtol=1e-8))
    x_st = model.static_load / model.mean_stiffness
    assert np.max(np.abs(y[:, 0] - yr[0])) <= 1e-12 * x_st


def test_fmu_runs_without_gear_dyn_pint_matplotlib(heli_fmu: Path) -> None:
    """In a fresh interpreter where importing gear_dyn, pint or matplotlib fails, the FMU still
    runs (it carries its own gear_dyn copy and pythonfmu) and gives the same numbers."""
    expected = _solo(heli_fmu, 8)[:, 0]
    code = textwrap.dedent(f"""
        import sys
        class Block:
            def find_spec(self, name, path=None, target=None):
                top = name.split(".")[0]
                if top in ("gear_dyn", "pint", "matplotlib"):
                    raise ImportError("blocked " + name)
        sys.meta_path.insert(0, Block())
        from fmpy import simulate_fmu
        r = simulate_fmu({str(heli_fmu)!r}, stop_time={8 * H!r}, output_interval={H!r},
                         output=["dte"])
        import pythonfmu
        print(pythonfmu.__file__)
        print(" ".join(repr(float(v)) for v in r["dte"]))
    """)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=240)
    assert proc.returncode == 0, proc.stderr
    where, numbers = proc.stdout.strip().splitlines()[-2:]
    assert "resources" in where  # the FMU's own pythonfmu copy
    np.testing.assert_allclose([float(v) for v in numbers.split()], expected, rtol=0,
                               atol=1e-20)


# ---------------------------------------------------------------------- lifecycle
def test_bad_parameters_are_refused_and_instance_survives(heli_fmu: Path,
                                                         variant_fmu: Path) -> None:
    """Zero teeth and a negative inertia are refused (error logged, call fails) and keep the
    old value; a pair that cannot mesh is refused at exitInitializationMode; afterwards the
    same instance still runs and gives the normal result."""
    normal = _solo(heli_fmu, 6)
    with FmuSession(heli_fmu) as s:
        s.instantiate()
        s.enter_init()
        with pytest.raises(InputError, match=r"gear\.teeth_pinion = '0'.*5 <= x <= 10000"):
            s.set({"gear.teeth_pinion": 0})
        assert any(st == 3 and "teeth_pinion" in m for st, m in s.messages)  # logged as error
        assert s.fmu.getInteger([s.vr("gear.teeth_pinion")]) == [23]  # old value kept
        s.set({"gear.addendum_coef": 0.5})  # valid alone, but the pair no longer meshes
        with pytest.raises(InputError, match="contact_ratio = 0.837"):
            s.exit_init()
        s.set({"gear.addendum_coef": 1.0})
        s.exit_init()
        rows = [s.get(OUT)]
        for k in range(6):
            s.step(k * H, H)
            rows.append(s.get(OUT))
    np.testing.assert_array_equal(np.array(rows), normal)
    with FmuSession(variant_fmu) as s:
        s.instantiate()
        bad_inertia = r"inertia\.pinion = '-0\.05 kg\*m\*\*2'.*valid range 0 < x"
        with pytest.raises(InputError, match=bad_inertia):
            s.set({"inertia.pinion": -0.05})
        with pytest.raises(InputError, match="damping.ratio"):
            s.set({"damping.ratio": math.nan})


def test_calls_out_of_order_are_refused(heli_fmu: Path) -> None:
    """doStep before initialization, from the wrong time, or after terminate, and setting a
    fixed parameter after initialization are refused with a message."""
    with FmuSession(heli_fmu) as s:
        s.instantiate()
        with pytest.raises(SolverError, match="initialize the FMU first"):
            s.step(0.0, H)
        s.initialize()
        with pytest.raises(InputError, match="fixed parameter"):
            s.set({"damping.ratio": 0.1})
        s.step(0.0, H)
        with pytest.raises(SolverError, match="the FMU is at"):
            s.step(5 * H, H)
        s.step(H, H)  # still consistent after the refusals
        s.terminate()
        with pytest.raises(SolverError, match="doStep in state terminated"):
            s.step(2 * H, H)


def test_reset_terminate_reinstantiate_repeat_the_run(heli_fmu: Path) -> None:
    """Reset gives a fresh instance (same run again); terminate, free and a new instance in the
    same process also repeat the run exactly."""
    first = _solo(heli_fmu, 10, {"operating.torque": 1000.0})
    with FmuSession(heli_fmu) as s:
        s.instantiate()
        a = _run(s, 10, {"operating.torque": 1000.0})
        s.reset()
        b = _run(s, 10, {"operating.torque": 1000.0})
        s.terminate()
    np.testing.assert_array_equal(a, first)
    np.testing.assert_array_equal(b, first)
    for _ in range(3):  # re-instantiation, again and again
        np.testing.assert_array_equal(_solo(heli_fmu, 10, {"operating.torque": 1000.0}), first)


def test_two_instances_and_two_fmus_do_not_interfere(heli_fmu: Path,
                                                     variant_fmu: Path) -> None:
    """One FMU twice (different loads) and two FMUs, stepped in turn in one process: each
    gives exactly its own solo run; each FMU runs its own gear_dyn copy."""
    solo_a = _solo(heli_fmu, 12)
    solo_b = _solo(heli_fmu, 12, {"operating.torque": 500.0, "damping.ratio": 0.12})
    solo_c = _solo(variant_fmu, 12)
    sessions = [FmuSession(heli_fmu, "a"), FmuSession(heli_fmu, "b"),
                FmuSession(variant_fmu, "c")]
    values: list[dict[str, Any]] = [{}, {"operating.torque": 500.0, "damping.ratio": 0.12}, {}]
    rows: list[list[list[float]]] = [[], [], []]
    for s, v, r in zip(sessions, values, rows, strict=True):
        s.instantiate()
        s.initialize(0.0, None, None, v)
        r.append(s.get(OUT))
    for k in range(12):
        for s, r in zip(sessions, rows, strict=True):
            s.step(k * H, H)
            r.append(s.get(OUT))
    for s in sessions:
        s.close()
    np.testing.assert_array_equal(np.array(rows[0]), solo_a)
    np.testing.assert_array_equal(np.array(rows[1]), solo_b)
    np.testing.assert_array_equal(np.array(rows[2]), solo_c)
    assert not np.allclose(solo_a, solo_c)
    copies = {m.split(".")[0] for m in sys.modules if m.startswith("gear_dyn_fmu_")}
    assert len(copies) >= 2


@pytest.mark.parametrize("method", ["auto", "DOP853"])
def test_fmu_state_restores_the_integrator(heli_fmu: Path, method: str) -> None:
    """get/set FMU state (and its serialised bytes) rewind the run exactly - for DOP853 this
    needs the solver's own state (step size, stages), not only x and v."""
    with FmuSession(heli_fmu) as s:
        s.instantiate()
        _run(s, 20, {"solver.method": method})
        state = s.fmu.getFMUstate()
        blob = s.fmu.serializeFMUstate(state)

        def more() -> np.ndarray:
            out = []
            for k in range(20, 45):
                s.step(k * H, H)
                out.append(s.get(OUT))
            return np.array(out)

        first = more()
        s.fmu.setFMUstate(state)
        np.testing.assert_array_equal(more(), first)
        s.fmu.setFMUstate(s.fmu.deSerializeFMUstate(blob))
        np.testing.assert_array_equal(more(), first)
        s.fmu.freeFMUstate(state)


def test_torque_input_change_mid_run(heli_fmu: Path) -> None:
    """A new torque input at t = 20 H acts from there on, exactly as the stepper with the
    changed model (W = T1 / r_b1) continued from the same state."""
    scene = load_scene(SCENES / "helicopter_tail.toml")
    plan = build_plan(scene)
    pair = build_pair(scene)
    with FmuSession(heli_fmu) as s:
        s.instantiate()
        y = _run(s, 20, outputs=["state.x", "state.v"])
        s.set({"operating.torque": 2000.0})
        for k in range(20, 40):
            s.step(k * H, H)
        final = s.get(["state.x", "state.v", "mesh_force"])
    st = Stepper(plan.model, plan.settings)
    for k in range(20):
        st.advance(k * H + H)  # the communication points as the FMU computes them
    np.testing.assert_array_equal(st.y, y[-1])
    st.replace_model(replace(plan.model, static_load=2000.0 / pair.rb1))
    for k in range(20, 40):
        st.advance(k * H + H)
    np.testing.assert_allclose(final[:2], st.y, rtol=1e-13)
    force = st.model.outputs(np.array([st.t]), st.y[:, None])["mesh_force"][0]
    assert final[2] == pytest.approx(force, rel=1e-12)


def test_stored_scene_reproduces_the_scene_file(heli_fmu: Path) -> None:
    """The SI tables stored in the FMU parse to the same model as the scene file (no pint)."""
    from gear_dyn.fmu.build import read_spec

    spec = read_spec(heli_fmu)
    stored = build_plan(parse_scene(spec["tables"], si=True)).model
    original = build_plan(load_scene(SCENES / "helicopter_tail.toml")).model
    assert stored.mesh_frequency == original.mesh_frequency
    assert stored.mass == original.mass
    assert stored.mean_stiffness == original.mean_stiffness


def test_serialized_state_moves_to_a_fresh_instance(heli_fmu: Path) -> None:
    """A state serialised by one instance (DOP853, mid-run, changed damping) and restored into
    a freshly instantiated one - which rebuilds the model from the state's parameters -
    continues exactly as the first instance does."""
    values = {"solver.method": "DOP853", "damping.ratio": 0.09}
    with FmuSession(heli_fmu, "first") as a:
        a.instantiate()
        _run(a, 15, values)
        blob = a.fmu.serializeFMUstate(a.fmu.getFMUstate())
        expected = []
        for k in range(15, 30):
            a.step(k * H, H)
            expected.append(a.get(OUT))
    with FmuSession(heli_fmu, "second") as b:
        b.instantiate()
        b.fmu.setFMUstate(b.fmu.deSerializeFMUstate(blob))
        got = []
        for k in range(15, 30):
            b.step(k * H, H)
            got.append(b.get(OUT))
    np.testing.assert_array_equal(np.array(got), np.array(expected))


def test_outputs_declare_no_direct_feedthrough(heli_fmu: Path) -> None:
    """ModelStructure declares every output with dependencies="" (no algebraic loop through
    the FMU), and that is true: a new torque or speed input changes no output before the
    next doStep, and does change them after it."""
    root = ET.fromstring(zipfile.ZipFile(heli_fmu).read("modelDescription.xml"))
    unknowns = root.find("ModelStructure").find("Outputs")  # type: ignore[union-attr]
    assert all(u.get("dependencies") == "" for u in unknowns)  # type: ignore[union-attr]
    with FmuSession(heli_fmu) as s:
        s.instantiate()
        _run(s, 4)
        before = s.get(OUT)
        s.set({"operating.torque": 3000.0, "operating.speed": 300.0})
        assert s.get(OUT) == before
        s.step(4 * H, H)
        assert s.get(OUT) != before


def test_missing_package_named_at_instantiate(heli_fmu: Path) -> None:
    """A host Python without scipy: instantiation fails, and the reason naming scipy reaches
    stderr with logging off (pythonfmu would show it only with debug logging on)."""
    code = textwrap.dedent(f"""
        import sys
        class Block:
            def find_spec(self, name, path=None, target=None):
                if name.split(".")[0] == "scipy":
                    raise ModuleNotFoundError("No module named 'scipy'", name="scipy")
        sys.meta_path.insert(0, Block())
        from fmpy import simulate_fmu
        try:
            simulate_fmu({str(heli_fmu)!r}, stop_time=1e-4, output_interval=1e-5)
        except Exception as exc:
            print("refused:", exc)
    """)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=240)
    assert "refused: Failed to instantiate" in proc.stdout, proc.stdout + proc.stderr
    assert "Python package 'scipy' is missing" in proc.stderr, proc.stderr


def test_fmu_is_slim(heli_fmu: Path) -> None:
    """The FMU carries only the code it runs: no CLI, plots, FMU build/co-simulation side or
    studies, and no module of its gear_dyn copy imports matplotlib."""
    names = zipfile.ZipFile(heli_fmu).namelist()
    copy = [n for n in names if n.startswith("resources/gear_dyn_fmu_") and n.endswith(".py")]
    assert copy
    for part in ("/cli/", "/plots/", "/fmu/build.py", "/fmu/staging.py", "/fmu/cosim.py",
                 "/analysis/sweep/", "/analysis/chart.py", "/scenes/"):
        assert not any(part in n for n in names), part
    with zipfile.ZipFile(heli_fmu) as z:
        for n in copy:
            text = z.read(n).decode("utf-8")
            assert "import matplotlib" not in text and "from matplotlib" not in text, n


def test_choices_are_enumerations(heli_fmu: Path) -> None:
    """solver.method and stiffness.method are FMI Enumerations (item k = choice k of the scene
    field); setting item k runs choice k (same result as setting it by name), and an item
    outside 1..n is refused with a message naming the range and the choices."""
    from fmpy import read_model_description

    md = read_model_description(str(heli_fmu))
    v = {x.name: x for x in md.modelVariables}
    for name in ("solver.method", "stiffness.method"):
        assert v[name].type == "Enumeration", name
    items = [i.name for i in v["solver.method"].declaredType.items]
    assert items == ["auto", "exact", "RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA",
                     "periodic"]
    by_name = _solo(heli_fmu, 6, {"solver.method": "DOP853"})
    np.testing.assert_array_equal(_solo(heli_fmu, 6, {"solver.method": 5}), by_name)
    assert not np.array_equal(_solo(heli_fmu, 6, {"solver.method": "LSODA"}), by_name)
    with FmuSession(heli_fmu) as s:
        s.instantiate()
        with pytest.raises(InputError, match=r"solver\.method = 99: valid range 1 <= x <= 9"):
            s.set({"solver.method": 99})


def test_bad_parameter_is_refused_with_one_message(heli_fmu: Path) -> None:
    """A bad parameter value: the set call fails (fmi2Fatal: pythonfmu's status of a raised
    exception; the instance stays valid), the host logger gets the slave's one message naming
    the parameter, its value and the valid range (then pythonfmu's technical one), and after
    fmi2Reset the instance gives the normal run."""
    from fmpy.fmi1 import FMICallException

    normal = _solo(heli_fmu, 6)
    with FmuSession(heli_fmu) as s:
        s.instantiate()
        s.enter_init()
        before = len(s.messages)
        with pytest.raises(FMICallException) as info:
            s.fmu.setReal([s.vr("damping.ratio")], [-1.0])
        assert info.value.status == 4
        new = s.messages[before:]  # the slave's, then pythonfmu's technical one
        assert len(new) == 2 and new[1][1].startswith("Fatal py exception encountered"), new
        status, text = new[0]
        assert status == 3
        assert "damping.ratio" in text and "-1" in text and "0 <= x <= 10" in text, text
        s.reset()
        np.testing.assert_array_equal(_run(s, 6), normal)


#: the methods scipy.integrate.solve_ivp documents
SOLVE_IVP = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")


@pytest.mark.parametrize("method", ["auto", "exact", "periodic", "exact_contact", "gauss",
                                    *SOLVE_IVP])
def test_cosim_reference_is_a_solve_ivp_run(method: str) -> None:
    """The reference of ``gear-dyn cosim`` is labelled "solve_ivp <method>" and is one: whatever
    the scene's method (``auto``, the closed forms, any solve_ivp method) and tolerance, it is
    solve_ivp DOP853 at rtol 1e-12, tight enough that its own error lies below the FMU's
    (tests/fmu/test_native_cosim.py)."""
    from gear_dyn.fmu.cosim import reference_settings

    ref = reference_settings(SolverSettings(method=method, rtol=1e-9, samples_per_period=40))
    assert (ref.method, ref.rtol, ref.atol) == ("DOP853", 1e-12, None)
    assert ref.method in SOLVE_IVP and ref.samples_per_period == 40
