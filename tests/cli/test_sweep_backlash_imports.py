"""``gear-dyn sweep`` of the backlash scene imports no scipy: shooting takes the exact one-period
map and sensitivity, and the orbit samples and settling transients the exact contact propagator
(closed form between located contact changes), so scipy.integrate (~0.25 s), scipy.optimize and
scipy.linalg are never loaded."""

from __future__ import annotations

import csv
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("workers", ["1", "2"])
def test_backlash_sweep_imports_no_integrator(tmp_path: Path, workers: str) -> None:
    """Serial in the calling process, or on a pool of two processes (``--workers 2``)."""
    out = tmp_path / "out"
    code = (
        "import sys\n"
        "from gear_dyn.cli.app import main\n"
        f"rc = main(['sweep', {str(ROOT / 'examples/scenes/helicopter_tail_backlash.toml')!r}, "
        f"'--speeds', '4600 rpm:6400 rpm:10', '--workers', {workers!r}, "
        "'--quiet', "
        f"'--out', {str(out)!r}])\n"
        "print('RESULT', rc, sorted(m for m in sys.modules if m.split('.')[:2] in "
        "(['scipy', 'integrate'], ['scipy', 'optimize'], ['scipy', 'linalg'])))\n"
    )
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    last = [ln for ln in res.stdout.splitlines() if ln.startswith("RESULT")]
    # (pint.compat imports the bare scipy package to see whether it is there; ~10 ms)
    assert last == ["RESULT 0 []"], res.stdout + res.stderr
    with (out / "sweep.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    # both directions solved, with the jump: the teeth separate on the upper branch
    assert len(rows) == 20
    assert max(float(r["separation_share"]) for r in rows) > 0.3
