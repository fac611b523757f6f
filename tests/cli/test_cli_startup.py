"""Start-up of the command: building the parser loads no physics, numerics or plotting."""

from __future__ import annotations

import subprocess
import sys


def test_help_imports_no_heavy_module() -> None:
    code = (
        "import sys\n"
        "from gear_dyn.cli.app import build_parser\n"
        "build_parser().format_help()\n"
        "heavy = ('numpy', 'scipy', 'matplotlib', 'pint')\n"
        "print(sorted({m.split('.')[0] for m in sys.modules} & set(heavy)))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_registry_is_built_once_per_process() -> None:
    from gear_dyn.units import registry

    assert registry() is registry()
    q = registry().Quantity("3319 rpm").to("rad/s").magnitude
    assert abs(q - 3319 * 2 * 3.141592653589793 / 60) < 1e-9


def test_run_of_the_example_scene_loads_no_integrator_or_optimizer() -> None:
    """``gear-dyn run`` of the exact-propagator scene needs neither scipy.integrate nor
    scipy.optimize (together ~0.5 s of imports): they load only where a function uses them."""
    code = (
        "import sys\n"
        "from gear_dyn.scene import load_scene, run_scene\n"
        "from gear_dyn.scene.packaged import scene_path\n"
        "run_scene(load_scene(scene_path('helicopter_tail')))\n"
        "print(sorted(m for m in ('scipy.integrate', 'scipy.optimize') if m in sys.modules))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
