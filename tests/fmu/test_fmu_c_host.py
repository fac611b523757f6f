"""The FMU in a plain C host (gear_dyn/fmu/fmi2_host.c): loaded with dlopen(RTLD_LOCAL) as
fmuCheck and other C masters load it, with no Python in the process and an empty environment.
It must give fmpy's numbers and exit cleanly, run after run."""

from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np
import pytest

from gear_dyn.fmu.build import build_fmu
from gear_dyn.fmu.check import compile_host, fmpy_rows, run_c_host
from gear_dyn.fmu.native import unsupported_reason

pytestmark = pytest.mark.fmu

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"
F_M = 23 * 3319 / 60  # helicopter_tail mesh frequency, Hz
H = 1 / (16 * F_M)
NAMES = ["dte", "mesh_force", "state.x", "state.v"]


@pytest.fixture(scope="module")
def host(tmp_path_factory: pytest.TempPathFactory) -> Path:
    reason = unsupported_reason()
    if reason:
        pytest.skip(f"the FMU cannot run in a C host here: {reason}")
    exe = compile_host(tmp_path_factory.mktemp("host"))
    if exe is None:
        pytest.skip("no C compiler (cc/gcc/clang) on PATH: the C host cannot be compiled")
    return exe


@pytest.fixture(scope="module")
def heli(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    d = tmp_path_factory.mktemp("cfmu")
    fmu = build_fmu(SCENES / "helicopter_tail.toml", d / "heli.fmu")
    assert fmu.c_host_missing is None
    with zipfile.ZipFile(fmu.path) as z:
        z.extractall(d / "unzipped")
    return fmu.path, d / "unzipped"


@pytest.mark.parametrize("stop", [None, 40 * H])
def test_c_host_gives_fmpy_outputs(host: Path, heli: tuple[Path, Path],
                                   stop: float | None) -> None:
    """40 steps in the C host (empty environment: no PYTHONPATH, no LD_PRELOAD) against the
    same run through fmpy: the same Python code runs in both, so they agree to 1e-12
    relative; every FMI call returned OK and the process exited with code 0."""
    fmu, unzipped = heli
    proc, rows = run_c_host(host, unzipped, NAMES, stop, H, 40)
    assert proc.returncode == 0, proc.stderr[-2000:]
    ref = fmpy_rows(fmu, NAMES, stop, H, 40)
    assert rows.shape == ref.shape == (41, 5)
    scale = np.max(np.abs(ref), axis=0)
    assert np.all(np.abs(rows - ref) <= 1e-12 * scale)


@pytest.mark.slow
def test_c_host_exits_cleanly_20_runs(host: Path, heli: tuple[Path, Path]) -> None:
    """20 C-host runs in a row: each exits with code 0 (no crash at interpreter shutdown:
    the boot library's interpreter is never finalized) and prints the same numbers."""
    _, unzipped = heli
    first = None
    for k in range(20):
        proc, rows = run_c_host(host, unzipped, NAMES, None, H, 8)
        assert proc.returncode == 0, (k, proc.returncode, proc.stderr[-2000:])
        if first is None:
            first = rows
        np.testing.assert_array_equal(rows, first)
