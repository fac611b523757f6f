"""``gear-dyn run`` of the backlash scene states the orbit's stability without scipy.integrate:
shooting takes the exact one-period map and sensitivity (closed-form pieces and saltation
matrices), so no integrator is imported (~0.25 s of the whole command)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_backlash_run_imports_no_integrator(tmp_path: Path) -> None:
    out = tmp_path / "out"
    code = (
        "import sys\n"
        "from gear_dyn.cli.app import main\n"
        f"rc = main(['run', {str(ROOT / 'examples/scenes/helicopter_tail_backlash.toml')!r}, "
        f"'--out', {str(out)!r}])\n"
        "print('RESULT', rc, 'scipy.integrate' in sys.modules)\n"
    )
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    last = [ln for ln in res.stdout.splitlines() if ln.startswith("RESULT")]
    assert last == ["RESULT 0 False"], res.stdout + res.stderr
    orbit = json.loads((out / "summary.json").read_text())["orbit"]
    assert orbit["period1"] and orbit["stable"]  # the orbit check ran and found the orbit
