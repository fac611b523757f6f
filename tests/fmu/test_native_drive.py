"""The drivetrain interface of the native FMU (``--ports torque``): a torque input on each
shaft, angles and speeds out.

- Driven by a constant motor torque T1 on the pinion and loaded by a speed-proportional torque
  T2 = -c_L w2 on the gear (a simple master loop over fmpy, the load held over each step), the
  pair settles where the mean mesh force is T1 / r_b1 (with friction T1 / (r_b1 - phi1_mean))
  and the mean speed ratio z2 / z1.
- In libcosim and in Ecos (FMI 2 and 3), every packaged scene: the gear FMU between two shaft
  FMUs written in C (tests/fmu/shaft_fmu/shaft.c), a motor and a dynamometer load; over whole
  table periods (an eccentric pair's hunting period) the speed ratio z2 / z1 to the mesh's
  compliance and the torque through the mesh to the angular momentum balance. The
  speed-driven variant (``--ports shaft-speed``) between a speed source and the load's shaft.
- At constant torques the FMU's DTE and speeds follow the same equations (gd_drive.c, written
  again here from the exported tables) integrated by solve_ivp DOP853.
"""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pytest
from native_harness import Slave

from gear_dyn.fmu.export import RK_ERROR
from gear_dyn.scene import build_pair, load_scene
from gear_dyn.scene.packaged import resolve_scene

pytestmark = [pytest.mark.fmu,
              pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc) on PATH")]
fmpy = pytest.importorskip("fmpy")

#: single-DOF tables with the rectangular ISO stiffness (force jumps), the torsional helical ones
BUILDS = [("helicopter_tail", 2), ("eccentric_helical_ideal", 3)]
PER_PERIOD = 32  # communication steps per mesh period


#: every packaged scene (each builds natively); the eccentric pair's build takes 5-15 s (its
#: Fourier series over the hunting period) and its chain the longest span (:func:`_window`)
SCENES = [pytest.param(p.stem, marks=pytest.mark.slow) if p.stem == "eccentric_helical"
          else p.stem for p in sorted(resolve_scene("helicopter_tail").parent.glob("*.toml"))]


@pytest.fixture(scope="module")
def fmus(tmp_path_factory: pytest.TempPathFactory):
    """``get(scene, fmi=2, ports="torque")``: the native FMU, built once per module."""
    from gear_dyn.fmu.export_fmu import build_native_fmu

    d = tmp_path_factory.mktemp("drive")
    cache: dict[tuple[str, int, str], object] = {}

    def get(scene: str, fmi: int = 2, ports: str = "torque"):
        key = (scene, fmi, ports)
        if key not in cache:
            cache[key] = build_native_fmu(scene, d / f"{scene}_{fmi}_{ports}.fmu", fmi=fmi,
                                          ports=ports)
        return cache[key]

    return get


@pytest.fixture(scope="module")
def drives(fmus) -> dict[str, object]:
    """The drivetrain FMUs of :data:`BUILDS`, by scene."""
    return {s: fmus(s, fmi) for s, fmi in BUILDS}


@pytest.mark.parametrize(("scene", "fmi"), BUILDS)
def test_steady_state_under_a_speed_proportional_load(drives, scene: str, fmi: int) -> None:
    """Motor torque T1 (the build torque) on the pinion from 0.9 of the build speed, load
    T2 = -c_L w2 with c_L such that the build speed is the equilibrium: after 10 time constants
    of the load, over the last 40 mesh periods, the angle increments are in the ratio z2/z1
    (to the DTE's share: |d dte| / (r_b1 d th2)) and the mean mesh force is T1/r_b1
    (T1/(r_b1 - phi1_mean) with friction, phi1_mean the mean friction arm) to the sampling
    error of a rectangle rule over whole periods (the force's total variation per period over
    the samples per period, Koksma's bound) plus the pinion's momentum change."""
    built = drives[scene]
    pair = build_pair(load_scene(resolve_scene(scene)))
    z1, z2 = pair.z1, pair.z2
    run = Slave(built.path, fmi)
    w0, t1 = run.get("pinion.speed_start"), run.get("pinion.torque")
    i1, i2 = run.get("inertia.pinion"), run.get("inertia.gear")
    run.set("pinion.speed_start", 0.9 * w0)
    run.start(None)
    rb1, ratio = run.get("base_radius.pinion"), run.get("ratio")
    assert ratio == pytest.approx(z2 / z1, rel=1e-12)
    assert run.get("base_radius.gear") == pytest.approx(ratio * rb1, rel=1e-12)
    c_load = t1 * ratio ** 2 / w0  # N m s: -c_L w2 balances T1 z2/z1 at w2 = w0 z1/z2
    tau = (i2 + i1 * ratio ** 2) / c_load  # s, the load's time constant
    f_m = w0 * z1 / (2 * math.pi)
    h = 1 / (PER_PERIOD * f_m)
    n = PER_PERIOD * (int(10 * tau * f_m) + 40)
    names = ["pinion.angle", "gear.angle", "pinion.speed", "mesh_force", "dte"]
    rows = np.empty((n, len(names)))
    for k in range(n):
        run.set("gear.torque", -c_load * run.get("gear.speed"))
        run.fmu.doStep(k * h, (k + 1) * h - k * h)
        rows[k] = [run.get(o) for o in names]
    run.close()
    a1, a2, w1, force, dte = rows[-40 * PER_PERIOD - 1:].T
    d1, d2 = a1[-1] - a1[0], a2[-1] - a2[0]
    assert abs(d1 / d2 - z2 / z1) <= abs(dte[-1] - dte[0]) / (rb1 * abs(d2)) + 1e-12 * z2 / z1
    assert abs(d1 / d2 - z2 / z1) < 1e-4 * z2 / z1
    variation = np.sum(np.abs(np.diff(force))) / 40  # per mesh period
    window = 40 / f_m
    bound = variation / PER_PERIOD + i1 * abs(w1[-1] - w1[0]) / (rb1 * window)
    mean = float(np.mean(force[1:]))  # whole periods, one sample each step
    # with friction the pinion's torque balance holds the friction torque too: W = T1/(r_b1 -
    # phi1_mean), phi1_mean the mean friction arm (the torsional model's W)
    arm = built.model.mean_arms[0] if getattr(built.model, "friction", False) else 0.0
    assert abs(mean - t1 / (rb1 - arm)) <= bound, (mean, t1 / (rb1 - arm), bound)
    assert bound < 0.3 * t1 / rb1  # the check means something


def _mesh(nm, drive, par):
    """The drivetrain equations (module docstring of gd_drive.c) from the exported table:
    ``accel(y, t1, t2)``, the derivative of y = [th1, th2, w1, w2] under shaft torques t1, t2."""
    rb1, rb2, z1 = nm.rb1, nm.rb2, nm.z1
    i1, i2, zeta = par["inertia.pinion"], par["inertia.gear"], par["damping.ratio"]
    m_e = i1 * i2 / (i1 * rb2 ** 2 + i2 * rb1 ** 2)
    c = 2 * zeta * math.sqrt(m_e * nm.mean_stiffness)
    phase0 = getattr(nm, "phase0", 0.0)

    def accel(y: np.ndarray, t1: float, t2: float) -> np.ndarray:
        p = np.mod(phase0 + z1 * y[0] / (2 * math.pi), drive.period)
        q = nm.table.evaluate(np.array([p]))[:, 0]
        v = [q[i] if i >= 0 else 0.0 for i in drive.idx]  # e, de/dp, k, phi1, phi2
        u = rb1 * y[0] - rb2 * y[1]
        f = v[2] * (u + drive.sign_e * v[0]) + c * (
            rb1 * y[2] - rb2 * y[3] + drive.sign_e * z1 * y[2] / (2 * math.pi) * v[1])
        n = max(f, 0.0)
        return np.array([y[2], y[3], (t1 - rb1 * f + n * v[3]) / i1,
                         (t2 + rb2 * f + n * v[4]) / i2])

    return accel


def _reference_rhs(nm, drive, par):
    """The drivetrain equations at the constant torques of ``par``."""
    accel = _mesh(nm, drive, par)
    return lambda t, y: accel(y, par["pinion.torque"], par["gear.torque"])


@pytest.mark.parametrize(("scene", "fmi"), [
    *BUILDS, pytest.param("eccentric_helical", 2, marks=pytest.mark.slow)])
def test_drive_matches_solve_ivp_at_constant_torques(fmus, scene: str, fmi: int) -> None:
    """Build torque on the pinion, the balancing -T1 z2/z1 on the gear, 10 mesh periods: the
    FMU's DTE and gear speed against solve_ivp DOP853 (rtol 1e-11, atol 1e-11 of the state
    scales) of the same equations from the FMU's start state. Both control the local error to
    about 1e-10 of the state scales; over the ~10^3 steps the bound is 1e-6 of the static
    deflection (DTE) and of the speed scale. The eccentric pair's table is its contact-line
    form (Fourier series and the contact-line overlap, evaluated in C by the FMU and in Python
    here)."""
    from scipy.integrate import solve_ivp

    built = fmus(scene, fmi)
    nm, drive = built.model, built.drive
    run = Slave(built.path, fmi)
    run.start(None)
    par = {p: run.get(p) for p in drive.values() if p in run.vr}
    out = ["pinion.angle", "gear.angle", "pinion.speed", "gear.speed", "dte"]
    y0 = np.array([run.get(o) for o in out[:4]])
    f_m = par["pinion.speed_start"] * nm.z1 / (2 * math.pi)
    h = 1 / (PER_PERIOD * f_m)
    rows = [[run.get(o) for o in out]]
    for k in range(10 * PER_PERIOD):
        run.fmu.doStep(k * h, (k + 1) * h - k * h)
        rows.append([run.get(o) for o in out])
    run.close()
    got = np.array(rows)
    t = np.arange(10 * PER_PERIOD + 1) * h
    scale = np.asarray(drive.q_scale)
    ref = solve_ivp(_reference_rhs(nm, drive, par), (0.0, t[-1]), y0, method="DOP853",
                    t_eval=t, rtol=1e-11, atol=1e-11 * scale)
    assert ref.success, ref.message
    dte_ref = nm.rb1 * ref.y[0] - nm.rb2 * ref.y[1]
    assert np.max(np.abs(got[:, 4] - dte_ref)) < 1e-6 * nm.x_scale
    assert np.max(np.abs(got[:, 3] - ref.y[3])) < 1e-6 * scale[3]
    assert np.ptp(got[:, 4]) > 1e-3 * nm.x_scale  # the mesh vibrates: a real comparison


def test_modelDescription_states_the_ports_and_what_is_fixed(drives) -> None:
    """Inputs pinion.torque and gear.torque, the shafts' angles and speeds out with the mesh
    force and DTE (no output depends on an input), base radii and ratio as calculated
    parameters, inertias as parameters; the description says what is fixed at build."""
    for built in drives.values():
        md = fmpy.read_model_description(str(built.path))
        by = {v.name: v for v in md.modelVariables}
        assert {n for n, v in by.items() if v.causality == "input"} == {"pinion.torque",
                                                                        "gear.torque"}
        assert {n for n, v in by.items() if v.causality == "output"} == {
            "pinion.angle", "pinion.speed", "gear.angle", "gear.speed", "mesh_force", "dte"}
        assert {n for n, v in by.items() if v.causality == "calculatedParameter"} == {
            "base_radius.pinion", "base_radius.gear", "ratio"}
        assert by["inertia.pinion"].causality == "parameter"
        assert all(u.dependencies == [] for u in md.outputs)
        assert "Fixed at build: the gear geometry" in md.description
        assert fmpy.validation.validate_fmu(str(built.path)) == []


@pytest.mark.parametrize(("scene", "fmi"), [
    ("helicopter_tail", 2), ("helicopter_tail", 3),
    pytest.param("eccentric_helical", 2, marks=pytest.mark.slow)])
def test_drive_under_sanitizers(fmus, tmp_path: Path, scene: str, fmi: int) -> None:
    """The drivetrain FMU's shipped sources with a C driver under AddressSanitizer and UBSan
    (tests/fmu/native_drivers.py: forbidden calls and bad states refused, a state restored, 400
    steps that cut the mesh period unevenly): exit 0, no report, finite outputs. The eccentric
    pair: the contact-line form, whose table has no polynomials to read."""
    import subprocess
    import zipfile

    from native_drivers import driver

    cc = shutil.which("cc")
    assert cc is not None
    built = fmus(scene)  # FMI 2 sources; the glue of either version is the same
    with zipfile.ZipFile(built.path) as z:
        z.extractall(tmp_path / "u")
    src = tmp_path / "u" / "sources"
    from gear_dyn.fmu.export_c import NATIVE_DIR

    glue = {2: "gd_fmi2.c", 3: "gd_fmi3.c"}
    files = [str(p) for p in sorted(src.glob("*.c")) if p.name not in glue.values()]
    drv = tmp_path / "drv.c"  # outputs 10 (pinion.speed), 13 (mesh_force)
    f_m = built.model.z1 * built.model.speed / (2 * math.pi)
    drv.write_text(driver(fmi, (10, 13), f"1.0 / {f_m!r} / 7.3"))
    exe = tmp_path / "drv"
    subprocess.run([cc, "-std=c99", "-g", "-Wall", "-Wextra", "-Werror", "-pedantic",
                    "-fsanitize=address,undefined", "-fno-sanitize-recover=all", f"-I{src}",
                    f"-I{NATIVE_DIR}", str(drv), *files, str(NATIVE_DIR / glue[fmi]),
                    "-o", str(exe), "-lm"], check=True, capture_output=True)
    proc = subprocess.run([str(exe)], capture_output=True, text=True, check=False)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "runtime error" not in proc.stderr and "ERROR" not in proc.stderr
    speed, force = map(float, proc.stdout.split())
    assert math.isfinite(speed) and speed > 0 and math.isfinite(force)


SHAFT_DIR = Path(__file__).resolve().parent / "shaft_fmu"
#: the shaft FMU's variables: (name, value reference, causality)
SHAFT_VARS = (("flange.angle", 1, "input"), ("flange.speed", 2, "input"),
              ("flange.torque", 3, "output"), ("end.angle", 4, "output"),
              ("end.speed", 5, "output"), ("shaft.stiffness", 6, "parameter"),
              ("shaft.damping", 7, "parameter"), ("end.inertia", 8, "parameter"),
              ("end.torque", 9, "parameter"), ("end.viscous", 10, "parameter"),
              ("end.angle_start", 11, "parameter"), ("end.speed_start", 12, "parameter"))


@pytest.fixture(scope="module")
def shaft_libs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """The test shaft FMU's binaries (tests/fmu/shaft_fmu/shaft.c), compiled once."""
    from gear_dyn.fmu.toolchain import compile_binaries, fmi_headers

    return compile_binaries([SHAFT_DIR / "shaft.c"], tmp_path_factory.mktemp("shaft_bin"),
                            "gd_test_shaft", 2, include_dirs=[fmi_headers(2)], windows=False)


def _shaft_fmu(out: Path, libs: dict[str, Path], starts: dict[str, float] | None = None) -> Path:
    """The test shaft FMU, FMI 2, with its binaries ``libs``; ``starts``: start values in its
    modelDescription (a host may read the shaft's torque in initialization mode from the start
    values of its inputs, before any connection)."""
    import zipfile

    rows = []
    for name, vr, causality in SHAFT_VARS:
        extra = ('variability="fixed" initial="exact"' if causality == "parameter" else
                 'variability="continuous"')
        start = ("" if causality == "output" else
                 f' start="{float((starts or {}).get(name, 0.0))!r}"')
        rows.append(f'<ScalarVariable name="{name}" valueReference="{vr}" '
                    f'causality="{causality}" {extra}><Real{start}/></ScalarVariable>')
    md = ('<?xml version="1.0" encoding="UTF-8"?>\n<fmiModelDescription fmiVersion="2.0" '
          'modelName="gd_test_shaft" guid="{gear-dyn-test-shaft-1}" '
          'numberOfEventIndicators="0"><CoSimulation modelIdentifier="gd_test_shaft" '
          'canHandleVariableCommunicationStepSize="true"/><ModelVariables>'
          + "".join(rows) + '</ModelVariables><ModelStructure><Outputs>'
          '<Unknown index="3" dependencies="1 2"/><Unknown index="4" dependencies=""/>'
          '<Unknown index="5" dependencies=""/></Outputs></ModelStructure>'
          '</fmiModelDescription>\n')
    with zipfile.ZipFile(out, "w") as z:
        z.writestr("modelDescription.xml", md)
        for folder, lib in libs.items():
            z.write(lib, f"binaries/{folder}/{lib.name}")
    return out


#: the chain's connections: (from instance, variable) -> (to instance, variable)
CHAIN = ((("gear", "pinion.angle"), ("motor", "flange.angle")),
         (("gear", "pinion.speed"), ("motor", "flange.speed")),
         (("gear", "gear.angle"), ("load", "flange.angle")),
         (("gear", "gear.speed"), ("load", "flange.speed")),
         (("motor", "flange.torque"), ("gear", "pinion.torque")),
         (("load", "flange.torque"), ("gear", "gear.torque")))
#: the speed-driven variant's chain: the pinion at a set speed, the gear on the load's shaft
SPEED_CHAIN = CHAIN[2:4] + CHAIN[5:]
CHAIN_OUT = ["pinion.angle", "gear.angle", "pinion.speed", "mesh_force", "dte", "gear.speed",
             "pinion.torque", "gear.torque"]
#: communication steps per mesh cycle of a chain over an eccentric pair's hunting period (630
#: mesh cycles): its shafts' modes (near 70 Hz) and the sampling of the friction torques' mean
#: need no more; a quarter of the steps of the others
LONG_PER_PERIOD = 8
#: the shafts' first modes (rad/s) and their damping ratio against a fixed end
SHAFT_MODE, SHAFT_DAMPING = 2 * math.pi * 50, 0.5


def _chain(built) -> tuple[dict[str, dict[str, float]], float, dict[str, float]]:
    """The shaft FMUs' start values by instance, the communication step (a whole number of
    nanoseconds, for libcosim) and the constants the checks need.

    A motor inertia J_m = I1 with the constant torque T_m (the build torque) on a shaft into
    the pinion; the gear on a second shaft into a load inertia J_L = I2 with the torque
    T_e - c_L w_L of a dynamometer, whose steep characteristic (c_L such that the drivetrain's
    rigid mode has the time constant of the shaft modes' decay) passes through the build point
    (T_e - c_L w2_0 balances T_m z2/z1). The shafts: stiffness I1 w_s^2 and I2 w_s^2,
    w_s = 2 pi 50 Hz (h w_s << 1), damping ratio 0.5 of the pinion and of the gear against a
    fixed end. Started at the build point, the shafts twisted by their steady torques: the
    transient decays in about 1/(zeta w_s); the chain runs :func:`_settle` (ten of these)
    before it is checked. The speed-driven variant has no motor: its pinion turns at the
    build speed (:data:`SPEED_CHAIN`)."""
    nm, spec = built.model, built.drive.values()
    t_m, w0, ratio = nm.torque, spec["pinion.speed_start"], nm.rb2 / nm.rb1
    i1, i2 = spec["inertia.pinion"], spec["inertia.gear"]
    f_m = w0 * nm.z1 / (2 * math.pi)
    per = PER_PERIOD if built.drive.period == 1 else LONG_PER_PERIOD
    step = round(1e9 / (per * f_m)) * 1e-9
    k_s, d_s = i1 * SHAFT_MODE ** 2, 2 * SHAFT_DAMPING * i1 * SHAFT_MODE
    run = Slave(built.path, built.fmi)
    run.start(None)
    a2_0, w2_0 = run.get("gear.angle"), run.get("gear.speed")
    run.close()
    c_load = (2 * i1 * ratio ** 2 + 2 * i2) * SHAFT_DAMPING * SHAFT_MODE
    # the flanges start where the gear FMU starts: a host need not pass its start outputs on
    values = {"motor": {"flange.angle": 0.0, "flange.speed": w0,
                        "shaft.stiffness": k_s, "shaft.damping": d_s, "end.inertia": i1,
                        "end.torque": t_m, "end.viscous": 0.0, "end.angle_start": t_m / k_s,
                        "end.speed_start": w0},
              "load": {"flange.angle": a2_0, "flange.speed": w2_0,
                       "shaft.stiffness": k_s * i2 / i1, "shaft.damping": d_s * i2 / i1,
                       "end.inertia": i2, "end.torque": c_load * w0 / ratio - t_m * ratio,
                       "end.viscous": c_load,
                       "end.angle_start": a2_0 - t_m * ratio / (k_s * i2 / i1),
                       "end.speed_start": w0 / ratio}}
    if built.drive.speed_in:
        del values["motor"]
    scale = built.drive.q_scale
    return values, step, {"per": per, "h": step, "t_m": t_m, "w0": w0, "ratio": ratio,
                          "f_m": f_m, "i1": i1, "i2": i2, "rb1": nm.rb1, "rb2": nm.rb2,
                          "z1": nm.z1, "period": built.drive.period,
                          "dte_error": nm.stated_error * nm.static_deflection,
                          # the speeds' stated error, rad/s
                          "w1_error": RK_ERROR * scale[2], "w2_error": RK_ERROR * scale[3]}


def _window(c: dict[str, float]) -> int:
    """Mesh cycles the checks average over: whole table periods, at least 40. Over the table
    period the mesh repeats: one mesh cycle, or with eccentricity the hunting period z1 z2 /
    gcd(z1, z2) mesh cycles, z2 / gcd turns of the pinion and z1 / gcd of the gear (the
    kinematic error e(p) repeats only when both gears have made whole turns)."""
    p = int(c["period"])
    return p * math.ceil(40 / p)


def _settle(c: dict[str, float]) -> int:
    """Mesh cycles before the window: ten decay times 1/(zeta w_s) of the shafts' transient."""
    return math.ceil(10 / (SHAFT_DAMPING * SHAFT_MODE) * c["f_m"])


def _table_at(built, a1: np.ndarray) -> np.ndarray:
    """The FMU's table at pinion angles ``a1``: s e(p), the part of r_b1 th1 - r_b2 th2 that
    the kinematics set (eccentricity, or the single-DOF tables' transmission error; the sign s
    of gd_drive.c's F = k (u + s e) + ...), and the friction arms phi1, phi2 (m; zero without
    friction): array (3, n)."""
    nm, drive = built.model, built.drive
    p = np.mod(getattr(nm, "phase0", 0.0) + nm.z1 * a1 / (2 * math.pi), drive.period)
    q = nm.table.evaluate(p)
    e, _, _, phi1, phi2 = (q[i] if i >= 0 else np.zeros_like(p) for i in drive.idx)
    return np.array([drive.sign_e * e, phi1, phi2])


def _check_ratio(built, a1: np.ndarray, a2: np.ndarray, dte: np.ndarray, w2: np.ndarray,
                 c: dict[str, float]) -> None:
    """The speed ratio over the window (:func:`_window`): the angle increments taken between
    equal table phases (the window's start interpolated in the samples where the pinion had
    turned the window's cycles less) are in the ratio z2/z1 to the mesh's compliance:
    r_b1 d th1 - r_b2 d th2 = d dte, and with the kinematic error s e(p) equal at both ends
    d dte is the change of the mesh deflection x = dte + s e, at most its range over the
    window. Plus the FMU's stated DTE error at both ends and the linear interpolation's error
    (h^2 / 8 max |th2''|). Over a part of the hunting period an eccentric pair's kinematic
    error does not cancel: there the check would miss by its range (asserted larger than the
    allowance tenfold)."""
    cycles, h = _window(c), c["h"]
    assert np.all(np.diff(a1) > 0)
    start = a1[-1] - cycles * 2 * math.pi / c["z1"]
    j = int(np.searchsorted(a1, start))
    assert j >= 1
    frac = (start - a1[j - 1]) / (a1[j] - a1[j - 1])
    a2_start = a2[j - 1] + frac * (a2[j] - a2[j - 1])
    d2 = a2[-1] - a2_start
    error = (a1[-1] - start) / d2 / c["ratio"] - 1
    kin = _table_at(built, a1[j - 1:])[0]
    x = dte[j - 1:] + kin
    interpolation = h * float(np.max(np.abs(np.diff(w2[j - 1:])))) / 8
    allowed = (np.ptp(x) + 2 * c["dte_error"] + c["rb2"] * interpolation) / (c["rb2"] * abs(d2))
    assert abs(error) <= allowed, (error, allowed)
    assert allowed < 0.1 / cycles  # a tenth of a tooth slipped over the window would show
    e_range = np.ptp(kin) / (c["rb2"] * abs(d2))
    assert e_range > 10 * allowed or c["period"] == 1, (e_range, allowed)


def _variation(v: np.ndarray) -> float:
    """Total variation of the samples ``v``."""
    return float(np.sum(np.abs(np.diff(v))))


def _check_chain(built, rows: np.ndarray, c: dict[str, float]) -> None:
    """The steady state over the window (:func:`_window`).

    - The speed ratio z2/z1 (:func:`_check_ratio`).
    - The pinion at the build speed (to 1 %, the load's characteristic holds it there).
    - The torque passes through the mesh: the shafts' torques T1, T2 (the gear FMU's inputs,
      held over each step) and the friction torques max(F, 0) phi1, phi2 change the pinion's
      and the gear's momentum, I1 dw1 = int(T1 - r_b1 F + max(F, 0) phi1) and I2 dw2 =
      int(T2 + r_b2 F + max(F, 0) phi2); without F: r_b2 (mean T1 + mean friction torque 1 -
      I1 dw1 / T) + r_b1 (... 2) = 0. The held inputs' integral is the sum of the held values,
      and a host shows after a step either the value held over it or the next one: one of the
      two readings balances to the friction torques' sampling (their variation over the
      samples, Koksma's bound) and the speeds' stated error. The bound is asserted below a
      fifth of the friction torques' share, or without friction a millionth of the torque
      passed on (the check means something)."""
    a1, a2, w1, force, dte, w2, tau1, tau2 = rows.T
    _check_ratio(built, a1, a2, dte, w2, c)
    h, per = c["h"], int(c["per"])
    cycles = _window(c)
    n = cycles * per
    assert abs(np.mean(w1[-n:]) / c["w0"] - 1) < 1e-2
    rb1, rb2, span = c["rb1"], c["rb2"], n * h
    phi = _table_at(built, a1[-n:])[1:]
    fric = np.maximum(force[-n:], 0.0) * phi  # (2, n), N m

    momentum = (rb2 * c["i1"] * (w1[-1] - w1[-n - 1])
                + rb1 * c["i2"] * (w2[-1] - w2[-n - 1])) / span
    friction = rb2 * np.mean(fric[0]) + rb1 * np.mean(fric[1])
    # the held inputs: the samples after the window's steps, or those one step earlier
    held = [(tau1[-n:], tau2[-n:]), (tau1[-n - 1:-1], tau2[-n - 1:-1])]
    residual = min(abs(rb2 * np.mean(t1) + rb1 * np.mean(t2) + friction - momentum)
                   for t1, t2 in held)
    bound = ((rb2 * _variation(fric[0]) + rb1 * _variation(fric[1])) / n
             + 2 * (rb2 * c["i1"] * c["w1_error"] + rb1 * c["i2"] * c["w2_error"]) / span)
    assert residual <= bound, (residual, bound)
    assert bound < max(0.2 * abs(friction), 1e-6 * rb2 * c["t_m"])


def _shafts(tmp: Path, libs: dict[str, Path],
            values: dict[str, dict[str, float]]) -> dict[str, Path]:
    """The shaft FMUs of ``values`` (the motor's and the load's, or the load's alone), each
    with the start values of its chain."""
    return {name: _shaft_fmu(tmp / f"{name}.fmu", libs, values[name]) for name in values}


def _libcosim_rows(built, shafts: dict[str, Path], values: dict[str, dict[str, float]],
                   step: float, n: int, names: list[str], chain=CHAIN,
                   gear_inputs: dict[str, float] | None = None) -> np.ndarray:
    """The chain (:data:`CHAIN`, or ``chain``) in libcosim (FMI 2, fixed step ``step``, a whole
    number of nanoseconds): ``names`` of the gear FMU after each of ``n`` steps;
    ``gear_inputs``: values of the gear FMU's unconnected inputs."""
    cosim = pytest.importorskip("libcosimpy.CosimExecution")
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    log_output_level(CosimLogLevel.ERROR)
    ex = cosim.CosimExecution.from_step_size(step_size=round(step * 1e9))
    index = {name: ex.add_local_slave(CosimLocalSlave(fmu_path=str(path), instance_name=name))
             for name, path in (("gear", built.path), *shafts.items())}
    assert min(index.values()) >= 0
    vr = {"gear": {v.name: v.valueReference for v in fmpy.read_model_description(
        str(built.path)).modelVariables}, "shaft": {n: r for n, r, _ in SHAFT_VARS}}
    for name, settings in values.items():
        for var, value in settings.items():
            ex.real_initial_value(index[name], vr["shaft"][var], float(value))
    for var, value in (gear_inputs or {}).items():
        ex.real_initial_value(index["gear"], vr["gear"][var], float(value))
    for (a, out), (b, inp) in chain:
        assert ex.connect_real_variables(  # the C API's 0: connected
            index[a], vr["gear" if a == "gear" else "shaft"][out],
            index[b], vr["gear" if b == "gear" else "shaft"][inp]) == 0
    obs = CosimObserver.create_last_value()
    ex.add_observer(observer=obs)
    refs = [vr["gear"][n] for n in names]
    rows = []
    for _ in range(n):
        assert ex.step(1)
        rows.append(obs.last_real_values(index["gear"], refs))
    ex.stop()
    return np.array(rows)


@pytest.mark.parametrize("scene", SCENES)
def test_drive_between_two_shafts_in_libcosim(fmus, shaft_libs, tmp_path: Path,
                                              scene: str) -> None:
    """libcosim (FMI 2, fixed step, the shafts' torques into the gear FMU, its angles and speeds
    back; :data:`CHAIN`), every packaged scene: from the build point (:func:`_chain`) through
    the shafts' transient (:func:`_settle`), then the steady-state checks of
    :func:`_check_chain` over whole table periods (:func:`_window`; the eccentric pair's
    hunting period, 630 mesh cycles, is the longest span: its kinematic error repeats only
    there)."""
    built = fmus(scene)
    values, step, consts = _chain(built)
    shafts = _shafts(tmp_path, shaft_libs, values)
    n = (_settle(consts) + _window(consts)) * int(consts["per"])
    _check_chain(built, _libcosim_rows(built, shafts, values, step, n, CHAIN_OUT), consts)


def test_chain_in_libcosim_matches_solve_ivp(drives, shaft_libs, tmp_path: Path) -> None:
    """The same chain as one ODE (the drivetrain equations, :func:`_mesh`, plus both shafts and
    end inertias) integrated by solve_ivp DOP853 (rtol 1e-10) against libcosim over 10 mesh
    periods at the step h and at h/2. The co-simulation's coupling error (inputs held over a
    step) is of first order in the step: the difference of the two runs estimates the finer
    one's, and the finer run must agree with solve_ivp within twice that estimate (DTE and
    gear speed) plus the ODE's own error, and closer than the coarse run. (libcosim reads the
    gear FMU's outputs in initialization mode: they are those of its start state.)"""
    from scipy.integrate import solve_ivp

    built = drives["helicopter_tail"]
    nm = built.model
    values, step, consts = _chain(built)
    shafts = _shafts(tmp_path, shaft_libs, values)
    step = 2e-9 * round(step * 1e9 / 2)  # h/2 a whole number of nanoseconds too
    names = ["dte", "gear.speed"]
    n = 10 * PER_PERIOD
    coarse = _libcosim_rows(built, shafts, values, step, n, names)
    fine = _libcosim_rows(built, shafts, values, step / 2, 2 * n, names)[1::2]
    run = Slave(built.path, built.fmi)
    run.start(None)
    par = {p: run.get(p) for p in built.drive.values() if p in run.vr}
    y0 = [run.get(o) for o in ("pinion.angle", "gear.angle", "pinion.speed", "gear.speed")]
    run.close()
    accel = _mesh(nm, built.drive, par)
    mo, lo = values["motor"], values["load"]

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        tau1 = mo["shaft.stiffness"] * (y[4] - y[0]) + mo["shaft.damping"] * (y[5] - y[2])
        tau2 = lo["shaft.stiffness"] * (y[6] - y[1]) + lo["shaft.damping"] * (y[7] - y[3])
        return np.array([*accel(y[:4], tau1, tau2), y[5],
                         (mo["end.torque"] - mo["end.viscous"] * y[5] - tau1) / mo["end.inertia"],
                         y[7],
                         (lo["end.torque"] - lo["end.viscous"] * y[7] - tau2) / lo["end.inertia"]])

    start = [*y0, mo["end.angle_start"], mo["end.speed_start"], lo["end.angle_start"],
             lo["end.speed_start"]]
    t = np.arange(1, n + 1) * step
    scale = np.asarray(built.drive.q_scale)
    atol = np.concatenate([scale, scale[[0, 2, 1, 3]]]) * 1e-10
    ref = solve_ivp(rhs, (0.0, t[-1]), start, method="DOP853", t_eval=t, rtol=1e-10,
                    atol=atol)
    assert ref.success, ref.message
    want = np.array([nm.rb1 * ref.y[0] - nm.rb2 * ref.y[1], ref.y[3]]).T
    for j, name in enumerate(names):
        estimate = float(np.max(np.abs(coarse[:, j] - fine[:, j])))
        err_fine = float(np.max(np.abs(fine[:, j] - want[:, j])))
        err_coarse = float(np.max(np.abs(coarse[:, j] - want[:, j])))
        floor = 1e-6 * (nm.x_scale if name == "dte" else scale[3])
        assert err_fine <= 2 * estimate + floor, (name, err_fine, estimate)
        assert err_fine < err_coarse, name


def _ecos_rows(built, shafts: dict[str, Path], values: dict[str, dict[str, float]],
               step: float, n: int, names: list[str], chain=CHAIN,
               gear_inputs: dict[str, float] | None = None) -> np.ndarray:
    """The chain in Ecos (ecospy): as :func:`_libcosim_rows`, the gear FMU of either FMI
    version (the shafts FMI 2)."""
    try:
        from ecospy import EcosSimulation, EcosSimulationStructure
    except (ImportError, OSError) as exc:
        pytest.skip(f"ecospy not usable ({exc}; pip install ecospy, and libtbb12)")
    rows = []
    with EcosSimulationStructure() as ss:
        for name, path in (("gear", built.path), *shafts.items()):
            ss.add_model(name, str(Path(path).resolve()))
        for (a, out), (b, inp) in chain:
            ss.make_real_connection(f"{a}::{out}", f"{b}::{inp}")
        start = {f"{name}::{var}": float(value) for name, settings in values.items()
                 for var, value in settings.items()}
        start.update({f"gear::{var}": float(v) for var, v in (gear_inputs or {}).items()})
        ss.add_parameter_set("start", start)
        with EcosSimulation(structure=ss, step_size=step) as sim:
            sim.init(parameter_set="start")
            for _ in range(n):
                sim.step(1)
                rows.append([sim.get_real(f"gear::{v}") for v in names])
            sim.terminate()
    return np.array(rows)


@pytest.mark.parametrize("scene", SCENES)
@pytest.mark.parametrize("fmi", [2, 3])
def test_drive_between_two_shafts_in_ecos(fmus, shaft_libs, tmp_path: Path, fmi: int,
                                          scene: str) -> None:
    """The same chain in Ecos (ecospy), every packaged scene, the gear FMU as FMI 2 and as
    FMI 3 (the shafts FMI 2): the steady-state checks of :func:`_check_chain`."""
    built = fmus(scene, fmi)
    values, step, consts = _chain(built)
    shafts = _shafts(tmp_path, shaft_libs, values)
    n = (_settle(consts) + _window(consts)) * int(consts["per"])
    _check_chain(built, _ecos_rows(built, shafts, values, step, n, CHAIN_OUT), consts)


#: the speed-driven variant's outputs: its pinion.torque is the torque the pinion shaft delivers
SPEED_CHAIN_OUT = ["pinion.angle", "gear.angle", "pinion.torque", "mesh_force", "dte",
                   "gear.speed", "gear.torque"]


@pytest.mark.parametrize(("host", "scene", "fmi"), [("libcosim", "helicopter_tail", 2),
                                                     ("ecos", "eccentric_helical_ideal", 3)])
def test_speed_driven_variant_in_a_chain(fmus, shaft_libs, tmp_path: Path, host: str,
                                         scene: str, fmi: int) -> None:
    """``--ports shaft-speed`` in a chain (:data:`SPEED_CHAIN`: the pinion at the build speed,
    an input left unconnected; the gear on the load's shaft of :func:`_chain`), in libcosim and
    in Ecos: the speed ratio of :func:`_check_ratio`, and the torque passes through the mesh.
    The torque the pinion shaft delivers, T_p = r_b1 F - max(F, 0) phi1, and the gear's
    momentum, I2 dw2 = int(T2 + r_b2 F + max(F, 0) phi2), give mean T_p + mean max(F, 0) phi1
    + (r_b1 / r_b2) (mean T2 + mean max(F, 0) phi2 - I2 dw2 / T) = 0: T_p and the friction
    torques sampled after each step to their variation over the samples (Koksma's bound), T2
    held over the steps (one of the two readings of :func:`_check_chain`), dw2 to its stated
    error. The mesh force's jumps make T_p's bound the largest: asserted below 30 % of the
    build torque (the check means something)."""
    built = fmus(scene, fmi, "shaft-speed")
    values, step, c = _chain(built)
    shafts = _shafts(tmp_path, shaft_libs, values)
    n = (_settle(c) + _window(c)) * int(c["per"])
    rows = (_libcosim_rows if host == "libcosim" else _ecos_rows)(
        built, shafts, values, step, n, SPEED_CHAIN_OUT, chain=SPEED_CHAIN,
        gear_inputs={"pinion.speed": c["w0"]})
    a1, a2, t_p, force, dte, w2, tau2 = rows.T
    assert np.max(np.abs(np.diff(a1) / step / c["w0"] - 1)) < 1e-9  # the pinion at its input
    _check_ratio(built, a1, a2, dte, w2, c)
    m = _window(c) * int(c["per"])
    rb1, rb2, span = c["rb1"], c["rb2"], m * step
    fric = np.maximum(force[-m:], 0.0) * _table_at(built, a1[-m:])[1:]
    momentum = rb1 / rb2 * c["i2"] * (w2[-1] - w2[-m - 1]) / span
    rest = np.mean(t_p[-m:]) + np.mean(fric[0]) + rb1 / rb2 * np.mean(fric[1]) - momentum
    residual = min(abs(rest + rb1 / rb2 * np.mean(t2)) for t2 in (tau2[-m:], tau2[-m - 1:-1]))
    bound = ((_variation(t_p[-m - 1:]) + _variation(fric[0]) + rb1 / rb2 * _variation(fric[1]))
             / m + 2 * rb1 / rb2 * c["i2"] * c["w2_error"] / span)
    assert residual <= bound, (residual, bound)
    assert bound < 0.3 * c["t_m"]


@pytest.mark.parametrize(("scene", "fmi"), BUILDS)
def test_speed_driven_variant(tmp_path: Path, scene: str, fmi: int) -> None:
    """``--ports shaft-speed``: the pinion turns at its speed input, the gear is loaded by
    T2 = -c_L w2 (held over each step). The gear's angle increment is the pinion's times z1/z2
    (to 1e-4); the mean torque the pinion shaft delivers is c_L w2 (r_b1 - phi1_mean) /
    (r_b2 + phi2_mean) (the gear's and the pinion's torque balances; phi = 0 without friction)
    to the sampling bound of the steady-state test; changing the speed input without a step
    moves exactly the outputs declared to depend on it, pinion.torque and mesh_force (the mesh
    damping sees the pinion speed)."""
    from gear_dyn.fmu.export_fmu import build_native_fmu

    built = build_native_fmu(scene, tmp_path / "s.fmu", fmi=fmi, ports="shaft-speed")
    nm = built.model
    md = fmpy.read_model_description(str(built.path))
    declared = {u.variable.name: [d.name for d in u.dependencies] for u in md.outputs}
    fed = {n for n, d in declared.items() if d}
    assert fed == {"pinion.torque", "mesh_force"}
    assert all(declared[n] == ["pinion.speed"] for n in fed)
    run = Slave(built.path, fmi)
    run.start(None)
    w0, t_start, rb1, ratio = (run.get(n) for n in ("pinion.speed", "gear.torque",
                                                    "base_radius.pinion", "ratio"))
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    before = {o: run.get(o) for o in outputs}
    run.set("pinion.speed", 1.01 * w0)
    assert {o for o in outputs if run.get(o) != before[o]} == fed
    run.set("pinion.speed", w0)
    c_load = -t_start * ratio / w0
    f_m = w0 * nm.z1 / (2 * math.pi)
    h = 1 / (PER_PERIOD * f_m)
    n = 80 * PER_PERIOD
    names = ["pinion.angle", "gear.angle", "pinion.torque"]
    rows = np.empty((n, 3))
    for k in range(n):
        run.set("gear.torque", -c_load * run.get("gear.speed"))
        run.fmu.doStep(k * h, (k + 1) * h - k * h)
        rows[k] = [run.get(o) for o in names]
    run.close()
    a1, a2, torque = rows[-40 * PER_PERIOD - 1:].T
    assert abs((a1[-1] - a1[0]) / (a2[-1] - a2[0]) / ratio - 1) < 1e-4
    w2 = (a2[-1] - a2[0]) / (40 / f_m)
    arms = nm.mean_arms if getattr(nm, "friction", False) else (0.0, 0.0)
    expected = c_load * w2 * (rb1 - arms[0]) / (nm.rb2 + arms[1])
    variation = np.sum(np.abs(np.diff(torque))) / 40
    bound = variation / PER_PERIOD + 1e-3 * expected  # 1e-3: the load's decay over the window
    assert abs(float(np.mean(torque[1:])) - expected) <= bound, (np.mean(torque), expected)
