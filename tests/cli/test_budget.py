"""A work budget that stops a run names the flag that raises it, and the flag does raise it.

The budget of a solve_ivp run is its right-hand-side evaluations (SolverSettings.max_nfev,
``--max-nfev``). A DOP853 run of the helicopter tail pair over 200 mesh periods needs far more
than 1000 evaluations: with ``--max-nfev 1000`` it stops (exit 3) with one line that names
``--max-nfev``; the default budget runs it. ``gear-dyn contact --dynamics`` has the flag too.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from gear_dyn.cli.app import main
from gear_dyn.errors import InputError
from gear_dyn.solvers import MAX_NFEV, SolverSettings

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"


def test_a_run_over_budget_names_the_flag(tmp_path: Path,
                                          capsys: pytest.CaptureFixture[str]) -> None:
    args = ["run", "helicopter_tail", "--method", "DOP853", "--periods", "40"]
    rc = main([*args, "--max-nfev", "1000", "--out", str(tmp_path / "a")])
    err = capsys.readouterr().err
    assert rc == 3 and "--max-nfev" in err and "limit 1000" in err
    assert not (tmp_path / "a").exists()
    assert main([*args, "--out", str(tmp_path / "b")]) == 0


def test_contact_dynamics_has_the_budget_flag(tmp_path: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    scene = SCENES / "helicopter_tail_relief.toml"
    rc = main(["contact", str(scene), "--out", str(tmp_path / "c"), "--dynamics",
               "--max-nfev", "1000", "--quiet"])
    err = capsys.readouterr().err
    assert rc == 3 and "--max-nfev" in err, err


def test_the_budget_is_checked() -> None:
    assert SolverSettings().max_nfev == MAX_NFEV
    with pytest.raises(InputError, match="max_nfev"):
        SolverSettings(max_nfev=10)


def test_bench_has_the_budget_flag(tmp_path: Path) -> None:
    """``gear-dyn bench --max-nfev``: an RK45 case over the budget is recorded as failed with
    the solver's message, which names the flag (the exact reference needs no evaluations)."""
    rc = main(["bench", "helicopter_tail", "--methods", "RK45", "--rtols", "1e-4",
               "--periods", "20", "--repeats", "1", "--max-nfev", "1000", "--quiet",
               "--out", str(tmp_path / "b")])
    assert rc == 0
    table = (tmp_path / "b" / "bench.csv").read_text()
    assert "limit 1000" in table and "--max-nfev" in table


def test_compare_passes_the_budget_flag_on(capsys: pytest.CaptureFixture[str],
                                           tmp_path: Path) -> None:
    """``gear-dyn compare --max-nfev`` reaches the sweeps' solver settings (an out-of-range
    budget is refused there, naming the flag)."""
    rc = main(["compare", "helicopter_tail", "helicopter_tail_relief", "--speeds",
               "2000 rpm:3000 rpm:3", "--max-nfev", "10", "--quiet", "--out",
               str(tmp_path / "c")])
    err = capsys.readouterr().err
    assert rc == 2 and "--max-nfev" in err and "10" in err, err


def test_the_output_sample_cap_names_the_flag(capsys: pytest.CaptureFixture[str],
                                             tmp_path: Path) -> None:
    """100000 mesh periods x 64 samples is over the 4e6-sample cap: the message names the
    key and the flag that lower the demand; nothing is written."""
    rc = main(["run", "helicopter_tail", "--periods", "100000", "--out", str(tmp_path / "r")])
    err = capsys.readouterr().err
    assert rc == 2 and "--periods" in err and "solver.samples_per_period" in err, err
    assert not (tmp_path / "r").exists()


def test_the_natural_period_cap_names_the_flags(capsys: pytest.CaptureFixture[str],
                                               tmp_path: Path) -> None:
    """At 100 rpm the helicopter tail's f_n (2.9 kHz) is 76 mesh frequencies: an RK45 run of
    1000 mesh periods spans 76000 natural periods, over the 50000 an ODE run may take; it is
    refused before integrating, naming the flags."""
    rc = main(["run", "helicopter_tail", "--method", "RK45", "--speed", "100 rpm",
               "--periods", "1000", "--out", str(tmp_path / "r")])
    err = capsys.readouterr().err
    assert rc == 2 and "natural periods" in err, err
    assert "--periods" in err and "--speed" in err and "--method" in err


def test_the_continuation_point_budget_names_the_flag() -> None:
    """A branch stopped by ``max_points`` says so and names ``--max-points``."""
    from gear_dyn.analysis.continuation import ContinuationSettings, continue_orbits
    from gear_dyn.analysis.sweep import RPM
    from gear_dyn.scene import load_scene
    from gear_dyn.scene.sweep import SceneModels

    fam = SceneModels.of(load_scene("helicopter_tail_backlash"))
    branch = continue_orbits(fam, 3000 * RPM, 9500 * RPM,
                             settings=ContinuationSettings(max_points=2), doublings=0)
    assert len(branch.points) == 2
    assert branch.stop_reason.startswith("max_points (2) reached")
    assert "--max-points" in branch.stop_reason


def test_the_slice_contact_iteration_cap_names_the_option() -> None:
    """A crowned, misaligned helical pair needs more than two active-set iterations: with
    ``max_iterations=2`` the slice contact stops, naming the option; the default settles."""
    import math

    import numpy as np

    from gear_dyn.errors import SolverError
    from gear_dyn.geometry import GearPair
    from gear_dyn.modification.lead import FlankModification, LeadModification, Misalignment
    from gear_dyn.modification.slice_contact import SliceOptions, slice_contact

    rail = GearPair(23, 79, 6e-3, math.radians(20), 70e-3, math.radians(20), x1=0.3, x2=-0.1)
    mod = FlankModification(lead_pinion=LeadModification(crowning=30e-6),
                            misalignment=Misalignment(f_ma=20e-6))

    def k_pair(s: np.ndarray) -> np.ndarray:  # a constant single-pair stiffness (N/m)
        return np.full_like(np.asarray(s, dtype=float), 5e8)

    with pytest.raises(SolverError, match=r"max_iterations"):
        slice_contact(rail, 400.0, mod, k_pair, SliceOptions(slices=10, positions=4,
                                                             max_iterations=2))
    r = slice_contact(rail, 400.0, mod, k_pair, SliceOptions(slices=10, positions=4))
    assert np.all(r.load >= 0.0)
