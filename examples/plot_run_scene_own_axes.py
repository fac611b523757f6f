"""
Run a packaged scene into your own axes
=======================================

Load the packaged helicopter tail scene by name, run it, and draw its time history and spectrum
on axes of your own figure: every gear_dyn plot function takes ``ax=None`` (a new figure) or
your axes, and returns the Figure.

Usage: ``python examples/plot_run_scene_own_axes.py [OUT_DIR]``; writes ``own_axes.png``.
"""

from __future__ import annotations

import sys
from pathlib import Path

from matplotlib.figure import Figure

import gear_dyn as gd
from gear_dyn.io import save_figure
from gear_dyn.plots.run import plot_spectrum, plot_time_history


def main(out: Path, fast: bool = False) -> dict[str, float]:
    # a packaged scene by name (works from any folder); fewer mesh periods when fast
    scene = gd.load_scene("helicopter_tail")
    result = gd.run_scene(scene, periods=40 if fast else None)
    summary = gd.summarize(result)  # dynamic factor, DTE figures, stated error, ...
    print(f"dynamic factor {summary['dynamic_factor']:.4f} "
          f"({summary['dynamic_factor_definition']})")

    # your own figure: time history in the top row (DTE, force), spectrum below
    fig = Figure(figsize=(11, 8))
    grid = fig.subplots(3, 2, height_ratios=[1, 1, 1.2])
    plot_time_history(result, periods=5, ax=grid[:2, :])      # 4 axes: DTE, zoom, force, zoom
    spec_ax = fig.add_subplot(3, 1, 3)
    for a in grid[2]:
        a.remove()
    plot_spectrum(result, ax=spec_ax, scale="log")               # one axes: the spectrum
    fig.suptitle("helicopter_tail: your figure, your title and layout", fontsize=10)
    fig.tight_layout()  # the plot functions leave a caller's figure layout alone
    out.mkdir(parents=True, exist_ok=True)
    save_figure(fig, out / "own_axes.png", dpi=100)
    return {"dynamic_factor": summary["dynamic_factor"],
            "peak_force_ratio": summary["peak_force_ratio"],
            "mesh_frequency_hz": summary["mesh_frequency_hz"]}


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else "own_axes_out"))
