"""
Bifurcation diagram: period doubling and chaos
==============================================

The constant-stiffness backlash oscillator of Kahraman & Singh (1990)
(``backlash_constant_stiffness``) sampled once per mesh period after it has settled, at every
speed of a sweep up and a sweep down: one point per sample means a period-1 orbit, two a
period-2 orbit, a band of points no orbit of up to 16 mesh periods (chaos, or an orbit that has
not settled: ``gear-dyn bifurcation ... --classify`` tells them apart with the largest Lyapunov
exponent). The same from a terminal: ``gear-dyn bifurcation backlash_constant_stiffness
--speeds "7000 rpm:12500 rpm:111" --out bif``.

Usage: ``python examples/plot_bifurcation_diagram.py [OUT_DIR]``; writes ``bifurcation.png``
and prints the speed ranges of each period.
"""

from __future__ import annotations

import itertools
import math
import sys
from pathlib import Path

import gear_dyn as gd
from gear_dyn.io import save_figure
from gear_dyn.plots.bifurcation import plot_bifurcation
from gear_dyn.scene.bifurcation import bifurcation_scene

RPM = 2 * math.pi / 60  # rad/s per rpm


def main(out: Path, fast: bool = False) -> dict[str, list[int]]:
    scene = gd.load_scene("backlash_constant_stiffness")
    speeds = "7000 rpm:12500 rpm:5" if fast else "7000 rpm:12500 rpm:23"
    # 100 mesh periods to settle, then 32 samples, one per mesh period
    options = gd.DiagramOptions(settle=100, samples=32)
    diagram = bifurcation_scene(scene, speeds, options=options)
    print(repr(diagram))
    periods: dict[str, list[int]] = {}
    for c in diagram.curves:                # up and down
        periods[c.direction] = [int(p) for p in c.period]
        parts = []
        for p, run in itertools.groupby(zip(c.period, c.speed / RPM, strict=True),
                                        key=lambda item: int(item[0])):
            rpm = [r for _, r in run]
            name = f"period-{p}" if p else "no orbit <= 16"
            parts.append(f"{name} {rpm[0]:.0f}" + (f"-{rpm[-1]:.0f}" if len(rpm) > 1 else "")
                         + " rpm")
        print(f"{c.direction}: " + "; ".join(parts))
    out.mkdir(parents=True, exist_ok=True)
    save_figure(plot_bifurcation(diagram), out / "bifurcation.png", dpi=100)
    return periods


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else "bifurcation_diagram_out"))
