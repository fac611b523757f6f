"""A process pool asked for by a script without a ``__main__`` guard fails with a clear error.

The pool's processes start with ``spawn`` and import the calling script again; without the
guard each of them runs the script's top level, asks for a pool itself and stops (Python's
multiprocessing refuses to start a process while a process is still importing its main
module). The pool then breaks: the caller gets a SolverError that names the guard, not a bare
BrokenProcessPool. (With the guard the pool runs: tests/analysis/test_sweep_parallel.py.)
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BODY = """
    import numpy as np
    from gear_dyn.analysis.motion import DiagramOptions, bifurcation_diagram
    from gear_dyn.errors import SolverError
    from gear_dyn.scene import load_scene
    from gear_dyn.scene.sweep import SceneModels

    def main():
        factory = SceneModels.of(load_scene("helicopter_tail_backlash"))
        speeds = np.array([6000.0, 6100.0]) * 2 * np.pi / 60
        try:
            d = bifurcation_diagram(factory, speeds, direction="up", workers=2, block=1,
                                    options=DiagramOptions(settle=20, samples=32))
        except SolverError as exc:
            print("SolverError:", exc)
            raise SystemExit(3)
        print("ran on", d.executor)
"""


def test_a_pool_from_a_script_without_main_guard_fails_clearly(tmp_path: Path) -> None:
    script = tmp_path / "diagram_script.py"
    script.write_text(textwrap.dedent(BODY) + "\nmain()\n")  # no guard
    env = dict(os.environ, PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="1")
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                         env=env, cwd=tmp_path, timeout=300)
    assert out.returncode == 3, (out.stdout, out.stderr)
    assert "BrokenProcessPool" not in out.stdout
    assert "SolverError: workers = 2:" in out.stdout
    assert "if __name__ == \"__main__\":" in out.stdout
