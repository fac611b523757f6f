"""Every API example in examples/ runs with fast settings and gives figures that could fail.

The docs build runs the same scripts in full (the sphinx-gallery pages of docs/gallery/);
test_every_example_is_tested keeps this file and the folder in step.
"""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path
from types import ModuleType

import pytest

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _load(name: str) -> ModuleType:
    """The example ``examples/plot_NAME.py`` (the gallery's file names) as a module."""
    spec = importlib.util.spec_from_file_location(f"example_{name}", EXAMPLES / f"plot_{name}.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    return mod


def test_run_scene_own_axes(tmp_path: Path) -> None:
    out = _load("run_scene_own_axes").main(tmp_path, fast=True)
    # exact propagator (stated error ~1e-11): the demo's figure, steady after a few periods
    assert out["peak_force_ratio"] == pytest.approx(1.4979, abs=1e-4)
    assert out["mesh_frequency_hz"] == pytest.approx(3319 / 60 * 23, rel=1e-12)
    assert (tmp_path / "own_axes.png").stat().st_size > 10_000


def test_stiffness_methods(tmp_path: Path) -> None:
    import gear_dyn as gd

    means = _load("stiffness_methods").main(tmp_path, fast=True)
    pair = gd.GearPair(z1=23, z2=64, module=6e-3, pressure_angle=math.radians(22.5),
                       face_width=50e-3, youngs_modulus1=207e9, youngs_modulus2=207e9)
    # the ISO wave's mean is c_gamma b by construction (second route: the ISO figures)
    iso = gd.iso6336_stiffness(pair)
    assert means["iso6336"] == pytest.approx(iso.c_mesh * pair.face_width, rel=1e-9)
    assert 0.8 < means["potential_energy"] / means["iso6336"] < 1.3
    assert (tmp_path / "stiffness_methods.png").exists()


def test_eccentric_spectrum(tmp_path: Path) -> None:
    peaks = _load("eccentric_spectrum").main(tmp_path, fast=True)
    # the sidebands are physics: above the run's stated error (the gear-shaft ones far above)
    for name in ("f_m-f1", "f_m+f1"):
        assert peaks[name] > 3 * peaks["noise_floor"]
    for name in ("f_m-f2", "f_m+f2"):
        assert peaks[name] > 10 * peaks["noise_floor"]
    assert (tmp_path / "eccentric_spectrum.png").exists()


def test_speed_sweep_local_and_dask(tmp_path: Path) -> None:
    pytest.importorskip("distributed", reason="the Dask example needs dask[distributed]")
    out = _load("speed_sweep").main(tmp_path, fast=True)
    assert out["identical"] == 1.0
    assert out["natural_frequency_hz"] == pytest.approx(2913.09, abs=0.01)
    assert out["max_dynamic_factor"] > 2  # the 8-point sweep passes near f_m = f_n


def test_fmu_cosim(tmp_path: Path) -> None:
    pytest.importorskip("fmpy", reason="the FMU example needs fmpy")
    pytest.importorskip("pythonfmu", reason="the FMU example needs pythonfmu")
    out = _load("fmu_cosim").main(tmp_path, fast=True)
    # exact propagator on both sides: agreement far below the DTE scale
    assert out["max_diff"] < 1e-6 * out["scale"]
    assert (tmp_path / "helicopter_tail.fmu").exists() and (tmp_path / "cosim.png").exists()


def test_relief_trends(tmp_path: Path) -> None:
    table = _load("relief_trends").main(tmp_path)
    # Wang et al. (2024): a longer relief lengthens the load transition and lowers the entry load
    lengths = list(table["length"].values())
    for short, long in zip(lengths, lengths[1:], strict=False):
        assert long["transition_mm"] > short["transition_mm"]
        assert long["entry_load_share"] < short["entry_load_share"]
    assert (tmp_path / "relief_trends.png").exists()


def test_compare_reliefs(tmp_path: Path) -> None:
    cmp = _load("compare_reliefs").main(tmp_path, fast=True)
    plain, handbook = cmp.designs
    # ranked by the peak force: the handbook relief first, though its K_dyn is the larger (it
    # is divided by the relief's own, lower quasi-static peak)
    assert cmp.ranking == ("handbook relief", "no relief")
    assert handbook["peak_dynamic_factor"] > plain["peak_dynamic_factor"]
    assert handbook["peak_peak_force_ratio_delta_pct"] < 0
    assert "linear_model_invalid_at_peak" in plain["flags"]
    assert (tmp_path / "compare.png").exists() and (tmp_path / "compare.csv").exists()


def test_every_example_is_tested() -> None:
    """Each gallery script has a test here, except plot_relief_rules.py (22 s): its cases are
    checked in tests/test_docs_figures.py (amounts by hand, tangent against contact model)."""
    scripts = sorted(EXAMPLES.glob("*.py"))
    assert all(p.name.startswith("plot_") for p in scripts), "sphinx-gallery runs plot_*.py"
    names = {p.stem.removeprefix("plot_") for p in scripts} - {"relief_rules"}
    untested = {n for n in names if not any(t.startswith(f"test_{n}") for t in globals())}
    assert not untested, f"examples without a test: {sorted(untested)}"


@pytest.mark.slow
def test_tutorial(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The tutorial runs top to bottom (a script of cells, not a main()); its figures are
    checked against closed forms where the step has one."""
    import runpy

    import numpy as np

    monkeypatch.setattr(sys, "argv", ["plot_tutorial.py", str(tmp_path)])
    ns = runpy.run_path(str(EXAMPLES / "plot_tutorial.py"), run_name="__main__")
    assert ns["summary"]["mesh_frequency_hz"] == pytest.approx(4000 / 60 * 23, rel=1e-12)
    # the sweep's peak lies within one grid step (500 rpm) of f_m = f_n
    assert abs(ns["peak"].speed_rpm - ns["resonance_rpm"]) <= 500
    # eps_beta = 1 (helix angle to 1e-3 deg): constant contact-line length, hence constant
    # stiffness and no excitation: F_max / W = 1 up to the rounding of the angle
    cmp = ns["comparison"]
    assert cmp.ranking[0] == "rail_pair_eps1"
    rows = {r["scene"]: r for r in cmp.designs}
    assert rows["rail_pair_eps1"]["peak_peak_force_ratio"] == pytest.approx(1.0, abs=1e-2)
    # constant stiffness without deviations: the static response, K_dyn = 1
    assert np.allclose(ns["study"].baseline["k_dyn"], 1.0, atol=1e-9)
    # drivetrain FMU: the rigid pair under T1 and -c w2 relaxes as w1 = w0 (1 - 0.1 e^{-t/tau})
    t, w1, w0, tau, f_m = ns["t"], ns["w1"], ns["w0"], ns["tau"], ns["f_m"]
    end = t > t[-1] - 1 / f_m                         # the last mesh period: ripple averages out
    rigid = w0 * (1 - 0.1 * np.exp(-t[end] / tau))
    assert np.mean(w1[end]) == pytest.approx(np.mean(rigid), rel=1e-4)
    # mean mesh force: T1 / r_b1 to the rectangle rule's error over whole periods (the force's
    # total variation per period over the 16 samples of a period) and the pinion's inertia
    last, force, load = ns["last"], ns["force"], ns["load"]
    variation = np.sum(np.abs(np.diff(force[last]))) / 20
    assert abs(np.mean(force[last]) - load) <= variation / 16 + 1e-3 * load


def test_helical_contact(tmp_path: Path) -> None:
    table = _load("helical_contact").main(tmp_path, fast=True)
    peak = {name: row["peak_stress_pa"] for name, row in table.items()}
    # misalignment loads one end of the face; crowning and then tip relief relieve it
    assert peak["misaligned"] > peak["aligned, unmodified"]
    assert peak["misaligned, crowned"] < peak["misaligned"]
    assert peak["misaligned, crowned, tip relief"] < peak["misaligned, crowned"]
    assert (tmp_path / "face_load.png").exists() and (tmp_path / "slice_stiffness.png").exists()


def test_tolerance_study(tmp_path: Path) -> None:
    import numpy as np

    import gear_dyn as gd

    out = _load("tolerance_study").main(tmp_path, fast=True)
    # the response without deviations by a second route: the steady sweep of the same scene
    # (both exact for piecewise-constant stiffness, to rounding)
    sweep = gd.sweep_scene(gd.load_scene("helicopter_tail"), out["speeds"], si=True)
    assert np.allclose(out["baseline_k_dyn"], sweep.curves[0].dynamic_factor, rtol=1e-9)
    assert np.all(out["p05"] <= out["median"]) and np.all(out["median"] <= out["p95"])
    assert (tmp_path / "tolerance.png").exists()


def test_response_curve(tmp_path: Path) -> None:
    import gear_dyn as gd
    from gear_dyn.scene import build_model

    found = _load("response_curve").main(tmp_path, fast=True)
    f_n = build_model(gd.load_scene("backlash_constant_stiffness")).natural_frequency
    resonance_rpm = f_n / 23 * 60
    # backlash softens the resonance: the curve bends to lower speeds, both folds below f_n
    assert len(found["fold"]) == 2
    assert max(found["fold"]) < resonance_rpm
    assert min(found["period_doubling"]) > max(found["fold"])
    assert (tmp_path / "response.png").exists()


def test_bifurcation_diagram(tmp_path: Path) -> None:
    periods = _load("bifurcation_diagram").main(tmp_path, fast=True)
    # speeds 7000, 8375, 9750, 11125, 12500 rpm: 9750 and 11125 lie on the period-2 branch
    # that the continuation follows from 9163 to 11766 rpm (gear-dyn response, the response
    # page), in both sweep directions
    for direction in ("up", "down"):
        speeds = periods[direction] if direction == "up" else periods[direction][::-1]
        assert speeds[2] == 2 and speeds[3] == 2, (direction, periods[direction])
    assert (tmp_path / "bifurcation.png").exists()
