"""The quick start's figures, from running ``gear-dyn demo`` when the pages are built.

The quick start quotes what the demo prints (the dynamic factor, the ISO 6336-1 K_v, ...). So
that no page quotes a number the code no longer gives, this extension runs the demo through the
command's own entry point (:func:`gear_dyn.cli.app.main`) into a fresh folder when the build
starts, and hands its figures to the pages:

- ``docs/_generated/demo_output.txt``: what the command printed (folder names relative, as a
  user who ran ``gear-dyn demo`` in their own folder sees them; the run time as measured here),
  shown with ``literalinclude``;
- ``docs/_generated/demo_time_history.png``: the time history the demo wrote;
- MyST substitutions ``{{ demo_NAME }}`` for the figures quoted in the text (:data:`QUOTED`),
  formatted as the demo prints them.
"""

from __future__ import annotations

import contextlib
import io
import json
import shutil
import tempfile
from pathlib import Path
from typing import Any

# substitution name -> (key path in summary.json, format)
QUOTED: dict[str, tuple[tuple[str, ...], str]] = {
    "demo_mesh_frequency": (("mesh_frequency_hz",), "{:.1f} Hz"),
    "demo_output_speed": (("output_speed_rpm",), "{:.1f} rpm"),
    "demo_contact_ratio": (("contact_ratio",), "{:.4f}"),
    "demo_dynamic_factor": (("dynamic_factor",), "{:.4f}"),
    "demo_peak_force_ratio": (("peak_force_ratio",), "{:.4f}"),
    "demo_stiffness_jump": (("stiffness_jump_factor",), "{:.4f}"),
    "demo_kv": (("iso_6336_kv", "k_v"), "{:.4f}"),
    "demo_kv_n": (("iso_6336_kv", "resonance_ratio_n"), "{:.3f}"),
    "demo_kv_range": (("iso_6336_kv", "speed_range"), "{}"),
    "demo_rms_dte": (("rms_dte_m",), "{:.4g}"),
    "demo_solver": (("solver", "method"), "{}"),
    "demo_floquet": (("floquet", "max_multiplier_modulus"), "{:.3f}"),
}


def run_demo(docs_dir: Path) -> dict[str, str]:
    """Run ``gear-dyn demo``, write its output and figure under ``docs/_generated/`` and return
    the substitutions of :data:`QUOTED`."""
    from gear_dyn.cli.app import main

    gen = docs_dir / "_generated"
    gen.mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "gear_dyn_demo"
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf):
            code = main(["demo", "--quiet", "--out", str(out)])
        if code != 0:
            raise RuntimeError(f"gear-dyn demo exited with {code}:\n{buf.getvalue()}")
        printed = buf.getvalue().replace(str(out.resolve()), "gear_dyn_demo")
        (gen / "demo_output.txt").write_text(printed)
        shutil.copyfile(out / "time_history.png", gen / "demo_time_history.png")
        summary = json.loads((out / "summary.json").read_text())
    subs = {}
    for name, (keys, fmt) in QUOTED.items():
        value: Any = summary
        for key in keys:
            value = value[key]
        subs[name] = fmt.format(value)
    return subs


def _on_config_inited(app: Any, config: Any) -> None:
    subs = run_demo(Path(app.srcdir))
    config.myst_substitutions = {**config.myst_substitutions, **subs}


def setup(app: Any) -> dict[str, Any]:
    app.connect("config-inited", _on_config_inited)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
