"""Speed and torque changed mid-run, at a communication point, in the native FMU of both models,
against gear_dyn's solver run piecewise the same way.

At the change the FMU keeps its states and the mesh phase continuous (the tables are in phase)
and takes the new pinion speed and torque from there on. The reference does the same with the
Python models:

- single-DOF: the model copy of :func:`gear_dyn.fmu.inputs.input_changes` (new f_m, W and a
  phase offset that keeps the mesh phase continuous), integrated from the change time with the
  state reached there (exact propagator: exact to rounding);
- torsional: the model rebuilt at the new speed and torque; its time runs as ``th1 / w1``, so the
  second piece starts at ``tau_c = p_c / f_m'`` (the same mesh phase ``p_c``) with the state
  reached (DOP853 at rtol 1e-12).

Bound: the FMU's stated error (1e-9 of the static deflection for the exact single-DOF scene,
1e-6 for the torsional model), relative to the smaller of the two static deflections.
"""

from __future__ import annotations

import dataclasses
import shutil
from pathlib import Path

import numpy as np
import pytest
from native_harness import Slave

from gear_dyn.fmu.inputs import input_changes
from gear_dyn.scene import build_pair, build_plan, load_scene
from gear_dyn.scene.packaged import resolve_scene
from gear_dyn.solvers.integrate import integrate
from gear_dyn.solvers.settings import SolverSettings

pytestmark = [pytest.mark.fmu, pytest.mark.slow,  # builds five native FMUs (about 30 s)
              pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc) on PATH")]
pytest.importorskip("fmpy")

#: scene: (reference method, stated error); steps per mesh period 7.3 (not dividing it)
CASES = {"helicopter_tail": ("exact", 1e-9), "eccentric_helical": ("DOP853", 1e-6),
         "eccentric_helical_ideal": ("DOP853", 1e-6)}
PER_PERIOD = 7.3
N1, N2 = 60, 90  # steps before and after the change
SPEED, TORQUE = 1.3, 0.7  # factors of the build values


def run_fmu(path: Path, fmi: int, h: float, speed: float, torque: float) -> np.ndarray:
    """DTE at 0, h, ..., (N1 + N2) h; the inputs change at N1 h."""
    run = Slave(path, fmi)
    run.start(None)
    dte = [run.get("dte"), *run.steps(h, N1)]
    run.set("operating.speed", speed)
    run.set("operating.torque", torque)
    dte += run.steps(h, N2, k0=N1)
    run.close()
    return np.array(dte)


def reference(name: str, h: float) -> tuple[np.ndarray, float]:
    """DTE of the piecewise solver run at the FMU's instants, and the smaller static
    deflection."""
    scene = load_scene(resolve_scene(name))
    model = build_plan(scene).model
    pair = build_pair(scene)
    op = scene.get("operating")
    speed, torque = SPEED * op["speed"], TORQUE * op["torque"]
    settings = SolverSettings(method=CASES[name][0], rtol=1e-12, estimate_error=False)
    t1 = np.arange(N1 + 1) * h
    y1, _ = integrate(model, t1, settings)
    t_c = float(t1[-1])
    t2 = np.arange(N1, N1 + N2 + 1) * h
    if model.mesh_periodic:  # single-DOF: a model copy with a continuous mesh phase
        after = dataclasses.replace(model, **input_changes(model, pair, speed, torque, t_c))
        y2, _ = integrate(after, t2, settings, y1[:, -1])
        dte = np.concatenate([y1[0], y2[0][1:]])
    else:  # torsional: rebuilt; the same mesh phase at tau_c
        after = dataclasses.replace(model, speed=speed, torque=torque)
        tau_c = model.mesh_frequency * t_c / after.mesh_frequency
        y2, _ = integrate(after, tau_c + (t2 - t_c), settings, y1[:, -1])
        rb1, rb2 = pair.rb1, pair.rb2
        dte = np.concatenate([rb1 * y1[0] - rb2 * y1[1], (rb1 * y2[0] - rb2 * y2[1])[1:]])
    scale = min(model.static_load, after.static_load) / model.mean_stiffness
    return dte, scale


@pytest.fixture(scope="module")
def fmus(tmp_path_factory: pytest.TempPathFactory) -> dict[tuple[str, int], Path]:
    from gear_dyn.fmu.export_fmu import build_native_fmu

    d = tmp_path_factory.mktemp("inputs")
    return {(name, fmi): build_native_fmu(name, d / f"{name}{fmi}.fmu", fmi=fmi,
                                          max_size=None).path
            for name in CASES for fmi in (2, 3) if fmi == 2 or name == "eccentric_helical"}


@pytest.mark.parametrize(("name", "fmi"), [("helicopter_tail", 2), ("eccentric_helical", 2),
                                           ("eccentric_helical", 3),
                                           ("eccentric_helical_ideal", 2)])
def test_inputs_changed_mid_run_match_piecewise_solver(fmus, name: str, fmi: int) -> None:
    scene = load_scene(resolve_scene(name))
    model = build_plan(scene).model
    op = scene.get("operating")
    h = 1.0 / (PER_PERIOD * model.mesh_frequency)
    got = run_fmu(fmus[name, fmi], fmi, h, SPEED * op["speed"], TORQUE * op["torque"])
    ref, scale = reference(name, h)
    err = np.abs(got - ref) / scale
    assert float(np.max(err)) < CASES[name][1], f"{name}: {np.max(err):.3g} W/k_m"
    # the change is felt: after it, the DTE leaves the path it had at the old inputs
    before, _ = reference_unchanged(name, h)
    assert float(np.max(np.abs(got[N1 + 5:] - before[N1 + 5:]))) > 100 * CASES[name][1] * scale


def reference_unchanged(name: str, h: float) -> tuple[np.ndarray, None]:
    """DTE of the solver run without the change (to show the change matters)."""
    scene = load_scene(resolve_scene(name))
    model = build_plan(scene).model
    pair = build_pair(scene)
    settings = SolverSettings(method=CASES[name][0], rtol=1e-9, estimate_error=False)
    y, _ = integrate(model, np.arange(N1 + N2 + 1) * h, settings)
    if model.mesh_periodic:
        return y[0], None
    return pair.rb1 * y[0] - pair.rb2 * y[1], None
