"""
Response curve by continuation: folds and a period doubling
===========================================================

The constant-stiffness backlash oscillator of Kahraman & Singh (1990)
(``backlash_constant_stiffness``: the helicopter tail pair with a constant mesh stiffness, a
10 um backlash half gap, excited only by a 10 um transmission error at the mesh frequency).
Pseudo-arclength continuation follows its period-1 orbit through the primary resonance, where
the curve bends towards lower speeds: two folds bound the range where a stable orbit of large
and one of small amplitude coexist (the unstable one between them dashed), and the orbit
period-doubles above it. The same from a terminal: ``gear-dyn response
backlash_constant_stiffness --speeds "5000 rpm:8500 rpm" --doublings 0 --out resp``.

Usage: ``python examples/plot_response_curve.py [OUT_DIR]``; writes ``response.png`` and
prints the folds and period doublings with their speeds.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import gear_dyn as gd
from gear_dyn.io import save_figure
from gear_dyn.plots.continuation import plot_branch
from gear_dyn.scene.sweep import SceneModels

RPM = 2 * math.pi / 60  # rad/s per rpm


def main(out: Path, fast: bool = False) -> dict[str, list[float]]:
    scene = gd.load_scene("backlash_constant_stiffness")
    family = SceneModels.of(scene)             # speed (rad/s) -> the scene's model
    start, stop = (6500, 7300) if fast else (5000, 8500)      # rpm
    branch = gd.continue_orbits(family, start * RPM, stop * RPM, doublings=0)
    print(repr(branch))
    found: dict[str, list[float]] = {"fold": [], "period_doubling": []}
    for b in branch.walk():
        for x in b.bifurcations:
            if x.kind in found:
                found[x.kind].append(x.parameter / RPM)
                print(f"{x.kind} at {x.parameter / RPM:.2f} rpm ({x.before} -> {x.after})")
    out.mkdir(parents=True, exist_ok=True)
    save_figure(plot_branch(branch), out / "response.png", dpi=100)
    return found


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else "response_curve_out"))
