"""The native FMU's C kernel against gear_dyn's own solvers (kernel through ctypes, FMU through
fmpy), under the sanitizers, and its parameter range errors.

Tolerances: the stated error of the native FMU is 1e-9 of the static deflection W/k_m where the
table is exact and the pieces are closed form, 1e-6 otherwise (issue 23); the references run at
rtol 1e-11 (closed-form references are exact to rounding).
"""

from __future__ import annotations

import ctypes
import math
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from native_drivers import driver as native_driver
from native_harness import kernel

from gear_dyn.fmu.export import native_model
from gear_dyn.fmu.export_c import (
    GLUE_SOURCES,
    KERNEL_DIR,
    KERNEL_SOURCES,
    NATIVE_DIR,
    model_data_c,
)
from gear_dyn.models.sdof import sdof_from_pair
from gear_dyn.scene import build_pair, build_plan, load_scene
from gear_dyn.scene.packaged import resolve_scene
from gear_dyn.solvers.settings import SolverSettings
from gear_dyn.solvers.simulate_bare import simulate_bare
from gear_dyn.stiffness.periodic import FourierStiffness

pytestmark = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc) on PATH")

EXACT_BOUND = 1e-9
FITTED_BOUND = 1e-6


def scene_case(name: str, speed_factor: float = 1.0):
    scene = load_scene(resolve_scene(name))
    model = build_plan(scene).model
    pair = build_pair(scene)
    op = scene.get("operating")
    speed = op["speed"] * speed_factor
    model = model.at_mesh_frequency(model.mesh_frequency * speed_factor)
    return model, native_model(model, pair, speed, op["torque"], tolerance=1e-11)


def fourier_case():
    scene = load_scene(resolve_scene("helicopter_tail"))
    pair = build_pair(scene)
    base = build_plan(scene).model
    k = base.stiffness.truncated(12)
    assert isinstance(k, FourierStiffness)
    op = scene.get("operating")
    model = sdof_from_pair(pair, op["speed"], op["torque"], k)
    return model, native_model(model, pair, op["speed"], op["torque"], tolerance=1e-11)


def run_kernel(lib: ctypes.CDLL, times: np.ndarray) -> np.ndarray:
    md = ctypes.addressof(ctypes.c_char.in_dll(lib, "gd_model_data"))
    state = ctypes.create_string_buffer(1024)  # larger than gd_state
    lib.gd_defaults(state, ctypes.c_void_p(md))
    lib.gd_start(state, md, 0.0)
    out = (ctypes.c_double * 6)()
    rows = []
    for t in times:
        assert lib.gd_advance(state, md, float(t)) == 0
        lib.gd_outputs(state, ctypes.c_void_p(md), out)
        rows.append(list(out))
    return np.array(rows).T


CASES = {
    # (model builder, reference method, bound)
    "rectangular": (lambda: scene_case("helicopter_tail"), "exact", EXACT_BOUND),
    "backlash_separating": (lambda: scene_case("helicopter_tail_backlash", 2.2),
                            "exact_contact", EXACT_BOUND),
    "relief": (lambda: scene_case("helicopter_tail_relief"), "DOP853", FITTED_BOUND),
    # backlash with a transmission error: Runge-Kutta pieces whose contact search reads e(t)
    # (the mesh phase must move with the step's time origin)
    "backlash_te": (lambda: scene_case("backlash_constant_stiffness"), "exact_contact",
                    FITTED_BOUND),
    "fourier": (fourier_case, "DOP853", FITTED_BOUND),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_kernel_matches_solver(tmp_path: Path, case: str) -> None:
    build, method, bound = CASES[case]
    model, nm = build()
    n_periods = 30
    ref = simulate_bare(model, n_periods / model.mesh_frequency,
                        SolverSettings(method=method, rtol=1e-11, samples_per_period=16,
                                       estimate_error=False))
    out = run_kernel(kernel(tmp_path, nm), ref.t)
    scale = nm.static_deflection
    err = float(np.max(np.abs(out[0] - ref.y[0]))) / scale
    assert err < bound, f"{case}: max |x - x_ref| = {err:.3g} W/k_m (bound {bound:g})"
    if case == "backlash_separating":  # the case must really leave contact
        assert float(np.min(ref.y[0])) < nm.half_gap
    if not nm.table.exact:
        assert max(nm.table.max_error.values()) < bound


def test_kernel_under_sanitizers(tmp_path: Path) -> None:
    """Kernel and FMI 2 and 3 glue under AddressSanitizer and UBSan: every model kind, a C driver
    that instantiates, steps (dividing and non-dividing steps), copies the state, resets, and
    gets Error for every forbidden call and bad state (tests/fmu/native_drivers.py)."""
    driver = tmp_path / "driver.c"  # outputs 6 and 9, 7 steps per mesh period of 1272.28 Hz
    driver.write_text(native_driver(2, (6, 9), "1.0 / 1272.28 / 7.0"))
    cc = shutil.which("cc")
    assert cc is not None
    driver3 = tmp_path / "driver3.c"
    driver3.write_text(native_driver(3, (6, 9), "1.0 / 1272.28 / 7.0"))
    for case in sorted(CASES):
        model, nm = CASES[case][0]()
        (tmp_path / "model_data.c").write_text(model_data_c(nm, case))
        for drv, fmi in ((driver, 2), (driver3, 3)):
            exe = tmp_path / f"drv_{case}_{fmi}"
            cmd = [cc, "-std=c99", "-g", "-Wall", "-Wextra", "-Werror", "-pedantic",
                   "-fsanitize=address,undefined", "-fno-sanitize-recover=all",
                   f"-I{KERNEL_DIR}", f"-I{NATIVE_DIR}", str(drv),
                   *(str(KERNEL_DIR / k) for k in KERNEL_SOURCES),
                   *(str(NATIVE_DIR / g) for g in GLUE_SOURCES[fmi]),
                   str(tmp_path / "model_data.c"), "-o", str(exe), "-lm"]
            subprocess.run(cmd, check=True, capture_output=True)
            proc = subprocess.run([str(exe)], capture_output=True, text=True, check=False)
            assert proc.returncode == 0, f"{case} FMI {fmi}: {proc.stdout}{proc.stderr}"
            assert "runtime error" not in proc.stderr and "ERROR" not in proc.stderr




fmpy = pytest.importorskip("fmpy")


@pytest.fixture(scope="module")
def tail_fmu(tmp_path_factory: pytest.TempPathFactory):
    from gear_dyn.fmu.export_fmu import build_native_fmu

    out = tmp_path_factory.mktemp("native") / "tail.fmu"
    return build_native_fmu("helicopter_tail", out)


@pytest.mark.parametrize("per_period", [16.0, 7.3])
def test_fmu_in_fmpy_matches_solver(tail_fmu, per_period: float) -> None:
    """Steps that do (16 per period) and do not (7.3) divide the mesh period."""
    from gear_dyn.fmu.export_c import OUTPUTS

    scene = load_scene(resolve_scene("helicopter_tail"))
    model = build_plan(scene).model
    f_m = model.mesh_frequency
    step = 1.0 / (f_m * per_period)
    stop = 200 * step
    res = fmpy.simulate_fmu(str(tail_fmu.path), stop_time=stop, output_interval=step,
                            output=[o[0] for o in OUTPUTS])
    ref = simulate_bare(model, stop, SolverSettings(method="exact", rtol=1e-11,
                                                    samples_per_period=16,
                                                    estimate_error=False))
    x_ref = np.interp(res["time"], ref.t, ref.y[0]) if per_period != 16.0 else None
    if x_ref is None:
        n = min(res["time"].size, ref.t.size)
        assert np.allclose(res["time"][:n], ref.t[:n], rtol=0, atol=1e-15)
        err = np.max(np.abs(res["dte"][:n] - ref.y[0][:n]))
    else:  # non-dividing steps: compare with the exact solution at the FMU's own instants
        ref2 = _exact_at(model, res["time"])
        err = np.max(np.abs(res["dte"] - ref2))
    scale = model.static_load / model.mean_stiffness
    assert err / scale < EXACT_BOUND
    assert math.isfinite(float(res["mesh_force"][-1]))


def _exact_at(model, times: np.ndarray) -> np.ndarray:
    """x at arbitrary instants by the exact propagator (one run per instant block)."""
    from scipy.linalg import expm

    y = model.initial_state()
    out = [y[0]]
    for ta, tb in zip(times[:-1], times[1:], strict=True):
        for a, b, amat, g in model.linear_segments(float(ta), float(tb)):
            big = np.zeros((3, 3))
            big[:2, :2] = amat
            big[:2, 2] = g
            y = (expm(big * (b - a)) @ np.append(y, 1.0))[:2]
        out.append(y[0])
    return np.array(out)


def test_fmu_parameter_out_of_range_then_reset(tail_fmu) -> None:
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    md = read_model_description(str(tail_fmu.path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    unzip = extract(str(tail_fmu.path))
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzip,
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="a")
    fmu.instantiate(loggingOn=True)
    with pytest.raises(Exception, match="fmi2SetReal failed"):
        fmu.setReal([vr["damping.ratio"]], [12.0])
    fmu.reset()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    fmu.doStep(0.0, 1e-4)
    assert math.isfinite(fmu.getReal([vr["dte"]])[0])
    fmu.terminate()
    fmu.freeInstance()
