"""
Build an FMU and co-simulate it
===============================

Build an FMI 2.0 co-simulation FMU of a scene, run it through fmpy at two communication steps,
and compare its output with the direct solution of the same scene.

Usage: ``python examples/plot_fmu_cosim.py [OUT_DIR]``; writes ``helicopter_tail.fmu`` and
``cosim.png`` (FMU output against solve_ivp, and the difference).
"""

from __future__ import annotations

import sys
from pathlib import Path

from matplotlib.figure import Figure

import gear_dyn as gd
from gear_dyn.fmu.build import build_fmu
from gear_dyn.fmu.cosim import compare
from gear_dyn.io import save_figure


def main(out: Path, fast: bool = False) -> dict[str, float]:
    out.mkdir(parents=True, exist_ok=True)
    scene = gd.load_scene("helicopter_tail")
    fmu = out / "helicopter_tail.fmu"
    build_fmu(scene, fmu)                               # FMI 2.0 co-simulation FMU
    f_m = 3319 / 60 * 23                                # mesh frequency in Hz
    # fmpy steps the FMU at two communication steps; the reference is solve_ivp on the scene
    report = compare(fmu, scene, steps=[1 / (16 * f_m), 1 / (8 * f_m)],
                     stop_time=(4 if fast else 40) / f_m, outputs=("dte",))
    for s in report.steps:
        print(f"step {s.step * 1e6:.2f} us: max |FMU - reference| DTE {s.max_diff['dte']:.3g} m "
              f"(DTE scale {report.scales['dte']:.3g} m)")
    fig = Figure(figsize=(8, 5))
    ax0, ax1 = fig.subplots(2, 1, sharex=True)
    ax0.plot(report.t * 1e3, report.ref_y[0] * 1e6, label="solve_ivp reference")
    ax0.plot(report.t * 1e3, report.fmu_y[0] * 1e6, "--", label="FMU via fmpy")
    ax0.set_ylabel("DTE (µm)")
    ax0.legend(fontsize=8)
    diff = report.fmu_y[0] - report.ref_y[0]            # m
    # the difference in the unit that reads without an offset factor (pm, nm or µm)
    unit, scale = next(((u, f) for u, f in (("µm", 1e6), ("nm", 1e9)) if abs(diff).max() * f >= 1),
                       ("pm", 1e12))
    ax1.plot(report.t * 1e3, diff * scale)
    ax1.set_ylabel(f"FMU - reference ({unit})")
    ax1.set_xlabel("time (ms)")
    save_figure(fig, out / "cosim.png", dpi=100)
    return {"max_diff": max(s.max_diff["dte"] for s in report.steps),
            "scale": report.scales["dte"]}


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else "fmu_cosim_out"))
