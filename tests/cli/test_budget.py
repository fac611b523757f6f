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
