"""The native FMU (FMI 2.0 and 3.0) through fmpy against gear_dyn's own solver, for every
single-DOF packaged scene; its range-error message; agreement with the pythonfmu FMU.

Bounds come from the FMU's own stated error (its modelDescription): 1e-9 of the static
deflection W/k_m where every piece is exact and closed form, 1e-6 otherwise (issue 23). The
references: the exact propagator (``exact``, ``exact_contact``: exact to rounding) or DOP853 at
rtol 1e-11, far below the bounds.

Communication steps: 10 and 21 reference samples at 160 samples per mesh period, i.e. 16 steps
per period (divides the period) and 160/21 = 7.62 (does not), so the FMU's instants are
reference instants.
"""

from __future__ import annotations

import math
import re
import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from native_harness import Slave, stated_error

from gear_dyn.fmu.export_c import OUTPUTS
from gear_dyn.scene import build_plan, load_scene
from gear_dyn.scene.packaged import resolve_scene
from gear_dyn.solvers.settings import SolverSettings
from gear_dyn.solvers.simulate_bare import simulate_bare

pytestmark = [pytest.mark.fmu,
              pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc) on PATH")]
fmpy = pytest.importorskip("fmpy")

#: the single-DOF packaged scenes and their reference methods
SCENES = {"helicopter_tail": "exact", "helicopter_tail_backlash": "exact_contact",
          "backlash_constant_stiffness": "exact_contact",
          "helicopter_tail_relief": "DOP853"}
SAMPLES = 160
PERIODS = 24
STEPS = {"divides": 10, "does_not_divide": 21}  # reference samples per communication step


@pytest.fixture(scope="session")
def native_fmus(tmp_path_factory: pytest.TempPathFactory) -> dict[tuple[str, int], Path]:
    """Every single-DOF packaged scene built as a native FMU, FMI 2 and 3 (built once)."""
    from gear_dyn.fmu.export_fmu import build_native_fmu

    d = tmp_path_factory.mktemp("native_fmus")
    return {(name, fmi): build_native_fmu(name, d / f"{name}_{fmi}.fmu", fmi=fmi).path
            for name in SCENES for fmi in (2, 3)}


@pytest.fixture(scope="session")
def references() -> dict[str, Any]:
    """The solver's run of each scene at SAMPLES per mesh period over PERIODS periods."""
    out = {}
    for name, method in SCENES.items():
        model = build_plan(load_scene(resolve_scene(name))).model
        ref = simulate_bare(model, PERIODS / model.mesh_frequency,
                            SolverSettings(method=method, rtol=1e-11, samples_per_period=SAMPLES,
                                           estimate_error=False))
        out[name] = (model, ref)
    return out


@pytest.mark.parametrize("announce_stop", [True, False], ids=["stop_time", "no_stop_time"])
@pytest.mark.parametrize("step", sorted(STEPS))
@pytest.mark.parametrize("fmi", [2, 3])
@pytest.mark.parametrize("scene", sorted(SCENES))
def test_native_fmu_matches_solver(native_fmus, references, scene: str, fmi: int, step: str,
                                   announce_stop: bool) -> None:
    model, ref = references[scene]
    every = STEPS[step]
    idx = np.arange(0, ref.t.size, every)
    h = every / (SAMPLES * model.mesh_frequency)
    n = idx.size - 1
    run = Slave(native_fmus[scene, fmi], fmi)
    run.start(n * h if announce_stop else None)
    x = np.array([run.get("dte"), *run.steps(h, n)])
    run.close()
    bound = stated_error(native_fmus[scene, fmi])
    scale = model.static_load / model.mean_stiffness
    assert np.allclose(ref.t[idx], np.arange(n + 1) * h, rtol=1e-12, atol=0)
    err = float(np.max(np.abs(x - ref.y[0][idx]))) / scale
    assert bound in (1e-9, 1e-6)
    assert err < bound, f"{scene} FMI {fmi} {step}: {err:.3g} W/k_m (stated {bound:g})"


@pytest.mark.parametrize("fmi", [2, 3])
def test_out_of_range_parameter_message_then_reset(native_fmus, fmi: int) -> None:
    """An out-of-range value: fmi2Error/fmi3Error (fmpy raises), exactly one error message
    naming the parameter, the value and the range with its unit; after reset the instance
    runs."""
    run = Slave(native_fmus["helicopter_tail_backlash", fmi], fmi)
    with pytest.raises(Exception, match=f"fmi{fmi}SetReal failed|fmi3SetFloat64 failed"):
        run.set("backlash.half_gap", 0.5)
    assert run.log == [(3, "backlash.half_gap = 0.5 m is out of range: valid range (0, 0.1] m")]
    with pytest.raises(Exception, match="failed"):
        run.set("damping.ratio", -1.0)
    assert run.log[1] == (3, "damping.ratio = -1 is out of range: valid range [0, 10]")
    run.fmu.reset()
    run.set("damping.ratio", 0.1)
    run.start(None)
    x = [run.get("dte"), *run.steps(1e-5, 20)]
    assert np.all(np.isfinite(x)) and len(run.log) == 2
    run.close()


@pytest.mark.parametrize("fmi", [2, 3])
def test_state_copy_replays_exactly(native_fmus, fmi: int) -> None:
    """Get the FMU state, step, set it back, step again: the same DTE bit for bit; serialize
    and deserialize give the same state."""
    run = Slave(native_fmus["helicopter_tail_relief", fmi], fmi)
    run.start(None)
    h = 1e-5
    run.steps(h, 10)
    get = run.fmu.getFMUstate if fmi == 2 else run.fmu.getFMUState
    put = run.fmu.setFMUstate if fmi == 2 else run.fmu.setFMUState
    state = get()
    if fmi == 2:
        state = run.fmu.deSerializeFMUstate(run.fmu.serializeFMUstate(state))
    else:
        state = run.fmu.deserializeFMUState(run.fmu.serializeFMUState(state))
    first = [run.fmu.doStep(10 * h + k * h, h) or run.get("dte") for k in range(5)]
    put(state)
    again = [run.fmu.doStep(10 * h + k * h, h) or run.get("dte") for k in range(5)]
    assert first == again
    run.close()


def test_native_and_pythonfmu_agree(native_fmus, tmp_path_factory) -> None:
    """The pythonfmu FMU (exact propagation) and the native FMU of the same scene, both through
    fmpy.simulate_fmu at the scene's own step: within the larger of their stated errors (the
    native one; the pythonfmu FMU's exact method is exact to rounding)."""
    from gear_dyn.fmu.build import build_fmu

    py = build_fmu("helicopter_tail", tmp_path_factory.mktemp("py") / "tail_py.fmu").path
    nat = native_fmus["helicopter_tail", 2]
    model = build_plan(load_scene(resolve_scene("helicopter_tail"))).model
    h = 1 / (16 * model.mesh_frequency)
    names = [o[0] for o in OUTPUTS if o[0] in ("dte", "mesh_force")]
    a = fmpy.simulate_fmu(str(py), stop_time=160 * h, output_interval=h, output=names)
    b = fmpy.simulate_fmu(str(nat), stop_time=160 * h, output_interval=h, output=names)
    assert a["time"].size == b["time"].size == 161
    scale = model.static_load / model.mean_stiffness
    err = float(np.max(np.abs(a["dte"] - b["dte"]))) / scale
    assert err < stated_error(nat), f"{err:.3g} W/k_m"
    # the force jumps with k at a switching instant: there the native FMU reports the new
    # piece (right limit), the pythonfmu FMU the one before; compare the others
    phase = np.mod(model.mesh_frequency * a["time"] + model.phase0, 1.0)
    switch = np.asarray(model.stiffness.switching_phases)
    gap = np.abs(phase[:, None] - switch[None, :])
    away = np.min(np.minimum(gap, 1 - gap), axis=1) > 1e-9
    assert 0 < np.sum(~away) < away.size // 4
    f_err = float(np.max(np.abs(a["mesh_force"] - b["mesh_force"])[away])) / model.static_load
    # |dF| <= k_max |dx| + c |dv|: a few times the DTE bound
    assert math.isfinite(f_err) and f_err < 10 * stated_error(nat), f"{f_err:.3g} W"


def test_relief_fmu_says_its_tables_are_fixed_at_the_build_torque(native_fmus) -> None:
    """The relief scene's tables come from the loaded contact at the build torque: the FMU's
    description and its torque variable say so; the other scenes' do not."""
    for (scene, _fmi), path in native_fmus.items():
        md = fmpy.read_model_description(str(path))
        torque = next(v for v in md.modelVariables if v.name == "operating.torque")
        fixed = "fixed at the build torque" in (torque.description or "")
        assert fixed == (scene == "helicopter_tail_relief"), scene
        assert ("changes the load W = T1/r_b1 only" in (md.description or "")) == fixed


def test_cli_builds_every_packaged_kind_natively(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """`fmu build` of a single-DOF scene: the native FMU (FMI 3 here: x86_64-linux binary and
    buildDescription.xml); of both torsional scenes too, the eccentric one although its table
    (3780 pieces over 630 mesh cycles) makes it larger than the benchmark's 500 kB size target:
    the build line states its size."""
    import zipfile

    from gear_dyn.cli.app import main

    out = tmp_path / "tail3.fmu"
    assert main(["fmu", "build", "helicopter_tail", "--fmi", "3", "--out", str(out),
                 "--no-validate", "--quiet"]) == 0
    names = zipfile.ZipFile(out).namelist()
    assert "binaries/x86_64-linux/gd_helicopter_tail.so" in names
    assert "sources/buildDescription.xml" in names and "sources/gd_fmi3.c" in names
    assert "native FMU" in capsys.readouterr().out
    for scene in ("eccentric_helical_ideal", "eccentric_helical"):
        fmu = tmp_path / f"{scene}.fmu"
        assert main(["fmu", "build", scene, "--out", str(fmu), "--no-validate", "--quiet"]) == 0
        line = capsys.readouterr().out.strip()
        size = re.search(r"; (\d+) kB\)$", line)
        assert line.startswith(f"{scene}: native FMU") and size, line
        assert int(size.group(1)) == fmu.stat().st_size // 1000
        names = zipfile.ZipFile(fmu).namelist()
        assert f"binaries/linux64/gd_{scene}.so" in names
        assert not any(n.startswith("resources/pythonfmu/") for n in names)


def test_native_and_pythonfmu_torsional_agree(tmp_path: Path) -> None:
    """The torsional model of eccentric_helical_ideal as a native FMU and as a pythonfmu FMU
    (DOP853, setupExperiment tolerance 1e-10), both through fmpy.simulate_fmu at 16 steps per
    mesh period over 10 periods: the DTE within the sum of their errors, the native FMU's
    stated one (1e-6 W/k_m) and gear_dyn's estimate for the run the pythonfmu FMU makes
    (DOP853 keeps one solver alive across the communication points: solve_ivp's own run)."""
    from gear_dyn.analysis.accuracy import error_scale, estimate_error
    from gear_dyn.fmu.build import build_fmu
    from gear_dyn.fmu.export_fmu import build_native_fmu
    from gear_dyn.solvers import integrate

    name = "eccentric_helical_ideal"
    py = build_fmu(name, tmp_path / "ideal_py.fmu").path
    nat = build_native_fmu(name, tmp_path / "ideal.fmu").path
    model = build_plan(load_scene(resolve_scene(name))).model
    h = 1 / (16 * model.mesh_frequency)
    names = ["dte", "mesh_force"]
    a = fmpy.simulate_fmu(str(py), stop_time=160 * h, output_interval=h, output=names,
                          relative_tolerance=1e-10)
    b = fmpy.simulate_fmu(str(nat), stop_time=160 * h, output_interval=h, output=names)
    assert a["time"].size == b["time"].size == 161
    t = np.asarray(a["time"])
    settings = SolverSettings(method="DOP853", rtol=1e-10)
    y, stats = integrate(model, t, settings)
    py_error = estimate_error(model, t, y, settings, stats)["max_rel"]
    stated = stated_error(nat)
    assert stated == 1e-6 and py_error < 1e-3 * stated
    x_s = error_scale(model)
    err = float(np.max(np.abs(a["dte"] - b["dte"]))) / x_s
    assert err < stated + py_error, f"{err:.3g} W/k_m"
    # |dF| <= k_max |d delta| + c |d delta'|: a few times the DTE bound, relative to W
    f_err = float(np.max(np.abs(a["mesh_force"] - b["mesh_force"]))) / model.static_load
    assert f_err < 10 * (stated + py_error), f"{f_err:.3g} W"
