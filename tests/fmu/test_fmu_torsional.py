"""The torsional eccentric FMU (the eccentric helical scene, Liu et al. 2017): validated,
co-simulated through fmpy against solve_ivp, and its integrator state restored exactly."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from gear_dyn.fmu.build import build_fmu
from gear_dyn.fmu.cosim import FmuSession, compare

pytestmark = pytest.mark.fmu

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"
F_M = 18 * 1500 / 60  # eccentric_helical: z1 n1 / 60 = 450 Hz
OUTPUTS = ("dte", "mesh_force", "w2", "friction_torque_pinion", "contact_length")


@pytest.fixture(scope="module")
def ecc_fmu(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The packaged scene with its solver pinned to DOP853 (the scene says auto, which a run
    integrates by Gauss-Legendre step maps; an FMU keeps one ODE solver across steps)."""
    folder = tmp_path_factory.mktemp("ecc")
    text = (SCENES / "eccentric_helical.toml").read_text()
    pinned = re.sub(r'(?m)^method = "auto".*$', 'method = "DOP853"', text)
    assert pinned != text
    (folder / "ecc.toml").write_text(pinned)
    return build_fmu(folder / "ecc.toml", folder / "ecc.fmu").path


def test_torsional_fmu_valid_with_eccentricity_and_friction(ecc_fmu: Path) -> None:
    from fmpy import read_model_description
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(ecc_fmu)) == []
    md = read_model_description(str(ecc_fmu))
    v = {x.name: x for x in md.modelVariables}
    assert float(v["eccentricity.pinion"].start) == pytest.approx(0.2e-3, rel=1e-12)
    assert v["eccentricity.pinion"].unit == "m"
    assert float(v["friction.coefficient"].start) == 0.05
    assert v["friction_torque_pinion"].causality == "output"
    assert v["friction_torque_pinion"].unit == "N.m"
    assert v["w2"].unit == "rad/s"
    assert float(md.defaultExperiment.stepSize) == pytest.approx(1 / (64 * F_M), rel=1e-12)


def test_cosim_of_the_eccentric_pair_matches_solve_ivp(ecc_fmu: Path) -> None:
    """FMU (DOP853 at the scene's rtol = 1e-7, its solver kept across communication points)
    against the reference, solve_ivp DOP853 at rtol 1e-12, at two communication steps: the
    verdict passes, the reference's error below the FMU's. The bound of the force is 100 times
    the FMU's rtol of its RMS (the mesh force is a small deflection times a large stiffness, so
    it carries ~10x the states' relative error). The FMU keeps one solver
    across communication points, so the communication step only decides where it is read:
    the coarse points, a subset of the fine ones, show the same differences. (The FMU's
    switching windows and solver bounds do not depend on the announced stop time, unlike
    solve_ivp's: the two take slightly different steps near the stop time.)"""
    report = compare(ecc_fmu, stop_time=8 / F_M, outputs=OUTPUTS,
                     steps=[1 / (16 * F_M), 1 / (4 * F_M)])
    assert (report.reference_method, report.rtol) == ("DOP853", 1e-12)
    assert report.bounds is not None and report.bounds.conclusive and report.passed
    for step in report.steps:
        for name in OUTPUTS:
            assert step.max_diff[name] <= 100 * 1e-7 * report.scales[name], (step, name)
    coarse, fine = report.steps
    for name in OUTPUTS:
        # coarse points are a subset of the fine ones: same differences there
        assert coarse.max_diff[name] <= fine.max_diff[name] * (1 + 1e-9) + 1e-300


def test_torsional_state_restore_and_input(ecc_fmu: Path) -> None:
    """FMU state get/set rewinds the DOP853 integrator exactly; a torque input change is
    taken from the next step on (and rewound with the state)."""
    h = 1 / (16 * F_M)
    names = ["state.q1_dot", "state.q2_dot", "mesh_force"]
    with FmuSession(ecc_fmu) as s:
        s.instantiate()
        s.initialize(0.0, 40 * h)
        for k in range(10):
            s.step(k * h, h)
        state = s.fmu.getFMUstate()

        def more(torque: float | None) -> np.ndarray:
            if torque is not None:
                s.set({"operating.torque": torque})
            out = []
            for k in range(10, 20):
                s.step(k * h, h)
                out.append(s.get(names))
            return np.array(out)

        first = more(None)
        s.fmu.setFMUstate(state)
        np.testing.assert_array_equal(more(None), first)
        s.fmu.setFMUstate(state)
        loaded = more(120.0)
        assert not np.allclose(loaded[:, 2], first[:, 2])
        s.fmu.setFMUstate(state)  # the state holds the torque of its time (63.662 N m)
        np.testing.assert_array_equal(more(None), first)


def test_packaged_eccentric_fmu_passes_its_own_check(tmp_path: Path) -> None:
    """The eccentric scene as shipped (method auto: LSODA inside the FMU), built and checked as
    a user would: validation, fmpy and stop-time independence pass; the C host line is skipped
    (a pythonfmu FMU runs in Python hosts only) and says so."""
    from gear_dyn.fmu.check import check_fmu, verdict

    built = build_fmu("eccentric_helical", tmp_path / "ecc_auto.fmu")
    lines = {ln.name: ln for ln in check_fmu(built.path)}  # 64 steps, as the command
    host = lines["C host"]
    assert host.ok is None and "Python hosts only" in host.detail, host.detail
    assert verdict(list(lines.values())), [ln.detail for ln in lines.values()]
    assert all(ln.ok for name, ln in lines.items() if name != "C host"), lines
