"""
Mesh stiffness by every method
==============================

The mesh stiffness of one pair by each method, side by side over one mesh cycle: the ISO 6336-1
rectangular wave (``iso6336``), the potential-energy method with the Sainsot fillet foundation
(``potential_energy``) and Weber's sliced cantilever with Hertz contact (``weber``), on the
helicopter tail pair of Jiang et al. (2018).

Usage: ``python examples/plot_stiffness_methods.py [OUT_DIR]``; writes
``stiffness_methods.png`` and prints each method's mean stiffness.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

import gear_dyn as gd
from gear_dyn.io import save_figure
from gear_dyn.stiffness.select import build_stiffness

METHODS = ("iso6336", "potential_energy", "weber")


def main(out: Path, fast: bool = False) -> dict[str, float]:
    # the helicopter tail pair of Jiang et al. (2018) (SI units in the Python API: m, rad, Pa)
    pair = gd.GearPair(z1=23, z2=64, module=6e-3, pressure_angle=math.radians(22.5),
                       face_width=50e-3, youngs_modulus1=207e9, youngs_modulus2=207e9)
    opts = {"samples_per_cycle": 40} if fast else {}
    phase = np.linspace(0.0, 1.0, 801)        # mesh phase in cycles, 0 = a pair enters
    fig = Figure(figsize=(8, 4.5))
    ax = fig.subplots()
    means = {}
    for method in METHODS:
        k = build_stiffness(pair, method, **(opts if method != "iso6336" else {}))
        means[method] = k.mean
        ax.plot(phase, k(phase) / 1e9, label=f"{method}: mean {k.mean / 1e9:.3f} N/nm")
        print(f"{method:17s} mean {k.mean:.4g} N/m")
    ax.set_xlabel("mesh phase (cycles; 0 = a tooth pair enters contact)")
    ax.set_ylabel("mesh stiffness k (10^9 N/m)")
    ax.set_title(f"contact ratio {pair.contact_ratio:.3f}: one and two pairs in contact")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    out.mkdir(parents=True, exist_ok=True)
    save_figure(fig, out / "stiffness_methods.png", dpi=100)
    return means


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else "stiffness_methods_out"))
