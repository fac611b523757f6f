"""Run an FMU (FMI 2.0 or 3.0) through fmpy and compare it with the same scene integrated by
solve_ivp.

A session (:class:`~gear_dyn.fmu.session.FmuSession` for FMI 2, re-exported here;
:class:`~gear_dyn.fmu.session3.Fmu3Session` for FMI 3; :func:`~gear_dyn.fmu.session3.open_session`
picks one) drives one FMU instance step by step and turns every failed FMI call into a gear_dyn
error carrying the FMU's own log messages (fmpy's ``simulate_fmu`` would end early without
complaint when a step is discarded).
:func:`compare` runs the FMU at several communication steps and the reference once, and reports
the differences, run times and a verdict (:class:`CosimReport`): the DTE difference at every
step must stay within the sum of the FMU's error and the reference's estimated error
(:func:`error_bounds`). Both kinds of FMU built by gear_dyn take the same path; what differs
(:class:`~gear_dyn.fmu.fmu_info.FmuInfo`) is where the scene and variables are read from, whether
a SCENE is set on the FMU, and where the FMU's error comes from.
"""

from __future__ import annotations

import math
import tempfile
import time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.accuracy import error_scale, estimate_error
from gear_dyn.errors import InputError
from gear_dyn.fmu.fmu_info import FmuInfo, read_fmu
from gear_dyn.fmu.inputs import driven_speed
from gear_dyn.fmu.session import FmuSession
from gear_dyn.fmu.session3 import open_session
from gear_dyn.fmu.stepper import stepper_method
from gear_dyn.fmu.variables import EXPERIMENT_KEYS
from gear_dyn.scene import SECTIONS, Scene, build_pair, build_plan, parse_scene
from gear_dyn.solvers import SolverSettings, integrate

FloatArray = NDArray[np.float64]


# ---------------------------------------------------------------------- comparison
@dataclass(frozen=True)
class StepComparison:
    """FMU against the reference at one communication step."""

    step: float
    n_steps: int
    fmu_run_time_s: float
    max_diff: dict[str, float]
    rms_diff: dict[str, float]

    def as_dict(self) -> dict[str, Any]:
        return {"step_s": self.step, "n_steps": self.n_steps,
                "fmu_run_time_s": self.fmu_run_time_s,
                "fmu_time_per_step_s": self.fmu_run_time_s / self.n_steps,
                "max_diff": self.max_diff, "rms_diff": self.rms_diff}


@dataclass(frozen=True)
class ErrorBounds:
    """The errors the verdict allows, in m of DTE, and where each comes from.

    Attributes
    ----------
    fmu, reference : float
        The FMU's error and the reference's estimated error, m.
    fmu_basis, reference_basis : str
        How each was obtained.
    scale : float
        Static deflection W/k_m of the reference scene, m (the unit of the relative errors).
    """

    fmu: float
    reference: float
    fmu_basis: str
    reference_basis: str
    scale: float

    @property
    def total(self) -> float:
        """The allowed DTE difference, m: the sum of both errors."""
        return self.fmu + self.reference

    @property
    def conclusive(self) -> bool:
        """The reference's error is below the FMU's: a PASS confirms the FMU's error."""
        return self.reference < self.fmu

    def as_dict(self) -> dict[str, Any]:
        return {"fmu_m": self.fmu, "fmu_basis": self.fmu_basis,
                "reference_m": self.reference, "reference_basis": self.reference_basis,
                "allowed_dte_diff_m": self.total, "static_deflection_m": self.scale,
                "reference_below_fmu": self.conclusive}


@dataclass(frozen=True)
class CosimReport:
    """Co-simulation of an FMU against solve_ivp, at several communication steps, with its
    verdict: :attr:`~gear_dyn.fmu.cosim.CosimReport.passed` when the DTE difference at every
    step is within
    ``bounds.total``."""

    fmu: str
    scene_name: str
    fmu_method: str
    reference_method: str
    rtol: float
    stop_time: float
    mesh_frequency: float
    outputs: tuple[str, ...]
    scales: dict[str, float]
    reference_run_time_s: float
    fmu_load_time_s: float
    steps: list[StepComparison]
    t: FloatArray = field(repr=False)
    fmu_y: FloatArray = field(repr=False)  # finest step, (n_outputs, n)
    ref_y: FloatArray = field(repr=False)
    backend: str = "python"
    bounds: ErrorBounds | None = None

    @property
    def passed(self) -> bool:
        """The DTE difference at every communication step is within the allowed error."""
        return self.bounds is not None and all(
            s.max_diff["dte"] <= self.bounds.total for s in self.steps)

    def as_dict(self) -> dict[str, Any]:
        return {
            "fmu": self.fmu, "backend": self.backend, "scene": self.scene_name,
            "fmu_method": self.fmu_method,
            "verdict": "PASS" if self.passed else "FAIL",
            "bounds": None if self.bounds is None else self.bounds.as_dict(),
            "reference": f"solve_ivp {self.reference_method}", "rtol": self.rtol,
            "stop_time_s": self.stop_time, "mesh_frequency_hz": self.mesh_frequency,
            "outputs": list(self.outputs), "scales": self.scales,
            "reference_run_time_s": self.reference_run_time_s,
            "fmu_load_time_s": self.fmu_load_time_s,
            "steps": [s.as_dict() for s in self.steps],
        }


def _same_model(spec: dict[str, Any], scene: Scene) -> None:
    kind = scene.get("scene")["model"]
    if kind != spec["model"]:
        raise InputError(f"scene {scene.name!r} runs the {kind} model, the FMU the "
                         f"{spec['model']} model")


def scene_values(spec: dict[str, Any], scene: Scene) -> dict[str, Any]:
    """FMU variable values that make the FMU run ``scene`` (parameters and inputs).

    Raises
    ------
    InputError
        The scene has a table or key that the FMU does not expose, or another model.
    """
    _same_model(spec, scene)
    names = {v["name"] for v in spec["variables"] if v["causality"] != "output"}
    values: dict[str, Any] = {}
    for table, entries in scene.tables.items():
        if table == "scene":
            continue
        for key, value in entries.items():
            name = f"{table}.{key}"
            if name in names:
                values[name] = value
            elif (value is not None and value != spec["tables"].get(table, {}).get(key)
                  and (table, key) not in EXPERIMENT_KEYS):
                raise InputError(f"scene {scene.name!r}: {name} = {value!r} is not a parameter "
                                 "of this FMU; build the FMU from this scene")
    return values


#: the reference's solve_ivp method and relative tolerance: tight enough that its own error
#: (estimated against a run at 1e-13) lies below the FMU's on every packaged scene, so that a
#: PASS confirms the FMU's error rather than the reference's (tests/fmu/test_native_cosim.py)
REFERENCE_METHOD = "DOP853"
REFERENCE_RTOL = 1e-12


def reference_settings(settings: SolverSettings) -> SolverSettings:
    """The solve_ivp settings of the reference: the scene's settings with
    ``REFERENCE_METHOD`` at ``REFERENCE_RTOL`` (and the default absolute tolerance),
    whatever the scene's method, so that the reference is always what its label says, a
    solve_ivp run, and its error is below the FMU's."""
    return replace(settings, method=REFERENCE_METHOD, rtol=REFERENCE_RTOL, atol=None)


def compare(fmu: str | Path, scene: Scene | None = None, steps: Sequence[float] | None = None,
            stop_time: float | None = None, outputs: Sequence[str] = ("dte", "mesh_force"),
            fmu_values: dict[str, Any] | None = None) -> CosimReport:
    """Run ``fmu`` at each communication step and ``scene`` with solve_ivp; compare and judge.

    Parameters
    ----------
    fmu : str or Path
        FMU built by gear_dyn, native or pythonfmu, FMI 2.0 or 3.0.
    scene : Scene or None
        Scene of the reference; None runs the scene stored in the FMU. A pythonfmu FMU gets its
        values set (every scene key is a parameter); a native FMU runs as built (its geometry
        and tables are fixed), so the verdict says whether it implements ``scene``.
    steps : sequence of float or None
        Communication steps in s, each an integer multiple of the smallest; None uses the
        DefaultExperiment step times 8, 4, 2 and 1.
    stop_time : float or None
        End of the run in s (None: the DefaultExperiment stop time).
    outputs : sequence of str
        FMU outputs compared (model output names); ``dte`` is always compared (the verdict).
    fmu_values : dict or None
        Extra FMU values (e.g. ``{"solver.method": "DOP853"}``, ``{"damping.ratio": 0.1}``);
        those that are scene keys also change the reference.

    Raises
    ------
    InputError
        Bad steps, stop time, outputs or scene.
    SolverError
        The FMU or the reference failed.
    """
    info = read_fmu(fmu)
    outputs = tuple(outputs) if "dte" in outputs else ("dte", *outputs)
    base, ref_scene, values = _scenes(fmu, info, scene, fmu_values)
    plan = build_plan(ref_scene)
    stop, h0, ratios = _steps(info, steps, stop_time, outputs)
    grid = np.arange(int(math.floor(stop / h0 + 1e-9)) + 1, dtype=np.float64) * float(h0)
    settings = reference_settings(plan.settings)
    ref, ref_time, y_ref, stats = _reference(plan.model, ref_scene, grid, settings, outputs)
    scales = {o: float(max(np.sqrt(np.mean(ref[i] ** 2)), 1e-300))
              for i, o in enumerate(outputs)}
    start = time.perf_counter()
    with open_session(fmu, instance_name="cosim_load") as session:
        session.instantiate()  # first load imports the FMU's Python code: not a step cost
    load_time = time.perf_counter() - start
    results, finest = _fmu_runs(fmu, grid, h0, ratios, ref, values, outputs)
    if info.backend == "native":
        fmu_method = "native kernel"
        fmu_settings = None
    else:
        fmu_method = str(values.get("solver.method", base.get("solver")["method"]))
        resolved = stepper_method(plan.model) if fmu_method == "auto" else fmu_method
        if fmu_method == "auto":
            fmu_method = f"auto -> {resolved}"
        fmu_settings = replace(plan.settings, method=resolved)
    bounds = error_bounds(info, plan.model, grid, y_ref, settings, stats, fmu_settings)
    return CosimReport(
        fmu=str(fmu), scene_name=base.name, fmu_method=fmu_method,
        reference_method=settings.method, rtol=settings.rtol, stop_time=float(grid[-1]),
        mesh_frequency=plan.model.mesh_frequency, outputs=tuple(outputs), scales=scales,
        reference_run_time_s=ref_time, fmu_load_time_s=load_time,
        steps=sorted(results, key=lambda s: -s.step),
        t=grid, fmu_y=finest, ref_y=ref, backend=info.backend, bounds=bounds,
    )


def error_bounds(info: FmuInfo, model: Any, grid: FloatArray, y_ref: FloatArray,
                 settings: SolverSettings, stats: dict[str, Any],
                 fmu_settings: SolverSettings | None) -> ErrorBounds:
    """The FMU's error and the reference's estimated error of the DTE, in m.

    The reference's: gear_dyn's error estimate of its run
    (:func:`gear_dyn.analysis.accuracy.estimate_error`). The FMU's: a native FMU's stated
    error (its modelDescription, relative to the static deflection W/k_m); a pythonfmu FMU
    states none and runs gear_dyn's solver with ``fmu_settings``, so its error is the same
    estimate for a run at those settings (the reference's own when the settings are equal).
    """
    scale = error_scale(model)
    est = estimate_error(model, grid, y_ref, settings, stats)
    ref_basis = f"solve_ivp {settings.method} at rtol {settings.rtol:g}: {est['basis']}"
    if info.stated_error is not None:
        fmu_rel = info.stated_error
        fmu_basis = "stated in the FMU's modelDescription"
    elif fmu_settings is None or fmu_settings == settings:
        fmu_rel, fmu_basis = float(est["max_rel"]), f"as the reference: {est['basis']}"
    else:
        y, st = integrate(model, grid, fmu_settings)
        fest = estimate_error(model, grid, y, fmu_settings, st)
        fmu_rel = float(fest["max_rel"])
        fmu_basis = (f"gear_dyn's solver as the FMU runs it ({fmu_settings.method}, rtol "
                     f"{fmu_settings.rtol:g}): {fest['basis']}")
    return ErrorBounds(fmu=fmu_rel * scale, reference=float(est["max_rel"]) * scale,
                       fmu_basis=f"{fmu_rel:.2g} W/k_m, {fmu_basis}",
                       reference_basis=f"{float(est['max_rel']):.2g} W/k_m, {ref_basis}",
                       scale=scale)


def _scenes(fmu: str | Path, info: FmuInfo, scene: Scene | None,
            fmu_values: dict[str, Any] | None) -> tuple[Scene, Scene, dict[str, Any]]:
    """(scene run, reference scene with the FMU values applied, values set on the FMU).

    A pythonfmu FMU gets ``scene``'s values set; a native FMU runs as built."""
    spec = info.spec
    base = scene if scene is not None else parse_scene(
        {k: dict(v) for k, v in spec["tables"].items()}, source=f"{Path(fmu).name} (stored)",
        si=True)
    _same_model(spec, base)
    values = scene_values(spec, base) if scene is not None and info.backend == "python" else {}
    values.update(fmu_values or {})
    for name in fmu_values or {}:
        if name not in info.settable:
            raise InputError(f"--set {name}: not a parameter or input of this FMU; available: "
                             f"{', '.join(sorted(info.settable))}")
    tables = {k: {kk: vv for kk, vv in v.items() if vv is not None}
              for k, v in base.tables.items()}
    for name, value in (fmu_values or {}).items():
        table, _, key = name.partition(".")
        section = SECTIONS.get(table)
        if section is not None and any(f.name == key for f in section.fields):
            tables.setdefault(table, {})[key] = value
    return base, parse_scene(tables, source=base.source, si=True), values


def _steps(info: FmuInfo, steps: Sequence[float] | None, stop_time: float | None,
           outputs: Sequence[str]) -> tuple[float, float, list[float]]:
    """Checked (stop time, smallest step, step ratios); the outputs must be FMU outputs."""
    ex = info.spec["experiment"]
    stop = float(stop_time if stop_time is not None else ex["stop_time"])
    if not (math.isfinite(stop) and stop > 0):
        raise InputError(f"--stop = {stop!r} s: valid range > 0 s")
    hs = sorted(float(h) for h in (steps or [ex["step_size"] * k for k in (8, 4, 2, 1)]))
    if not hs or hs[0] <= 0 or not all(math.isfinite(h) for h in hs):
        raise InputError(f"communication steps {hs}: each must be a positive number of seconds")
    h0 = hs[0]
    ratios = [h / h0 for h in hs]
    if any(abs(r - round(r)) > 1e-6 for r in ratios):
        raise InputError(f"communication steps {hs}: each must be an integer multiple of the "
                         f"smallest ({h0:.6g} s)")
    for o in outputs:
        if o not in info.outputs:
            raise InputError(f"output {o!r} is not an FMU output; available: "
                             f"{', '.join(sorted(info.outputs))}")
    return stop, h0, ratios


def _reference(model: Any, ref_scene: Scene, grid: FloatArray, settings: SolverSettings,
               outputs: Sequence[str]
               ) -> tuple[FloatArray, float, FloatArray, dict[str, Any]]:
    """The solve_ivp reference of the outputs on ``grid``, its run time, states and
    statistics."""
    start = time.perf_counter()
    y_ref, stats = integrate(model, grid, settings)
    ref_time = time.perf_counter() - start
    ref_out = model.outputs(grid, y_ref)
    if "driven_speed" in outputs:
        ref_out = {**ref_out, "driven_speed": driven_speed(
            build_pair(ref_scene), ref_scene.get("operating")["speed"], y_ref[1])}
    return (np.array([np.asarray(ref_out[o], dtype=float) for o in outputs]), ref_time, y_ref,
            stats)


def _fmu_runs(fmu: str | Path, grid: FloatArray, h0: float, ratios: list[float],
              ref: FloatArray, values: dict[str, Any], outputs: Sequence[str]
              ) -> tuple[list[StepComparison], FloatArray]:
    """One FMU run per communication step, each compared with the reference."""
    results: list[StepComparison] = []
    finest: FloatArray | None = None
    for r in ratios:
        stride = int(round(r))
        with open_session(fmu, instance_name=f"cosim_{len(results)}") as session:
            # announce the reference's end time: both then cut at the same switching instants
            t, y, run_time = session.run(h0 * stride, grid[-1] + 0.5 * h0, list(outputs),
                                         values, stop_time=float(grid[-1]))
        rsub = ref[:, ::stride][:, : t.size]
        diff = y[:, : rsub.shape[1]] - rsub
        results.append(StepComparison(
            step=h0 * stride, n_steps=t.size - 1, fmu_run_time_s=run_time,
            max_diff={o: float(np.max(np.abs(diff[i]))) for i, o in enumerate(outputs)},
            rms_diff={o: float(np.sqrt(np.mean(diff[i] ** 2))) for i, o in enumerate(outputs)},
        ))
        if stride == 1:
            finest = y
    if finest is None:
        raise InputError("communication steps: the smallest step must be among them")
    return results, finest


def extracted(fmu: str | Path) -> tempfile.TemporaryDirectory[str]:
    """A temporary folder holding the extracted FMU (for repeated sessions)."""
    from fmpy import extract

    tmp = tempfile.TemporaryDirectory(prefix="gear_dyn_fmu_run_")
    extract(str(fmu), tmp.name)
    return tmp


__all__ = ["CosimReport", "ErrorBounds", "FmuSession", "StepComparison", "compare",
           "error_bounds", "extracted", "reference_settings", "scene_values"]
