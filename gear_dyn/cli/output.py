"""Writing a run's files (shared by ``run`` and ``demo``)."""

from __future__ import annotations

import functools
import math
import mmap
from pathlib import Path
from typing import Any

import numpy as np

from gear_dyn.analysis.report import summarize
from gear_dyn.cli._parallel import Forerunner, can_fork, child_tasks
from gear_dyn.io import save_figure, staged_output, write_csv, write_json
from gear_dyn.solvers import Result

#: zlib level 1: the same pixels, ~20 % larger files, the encoder ~2x faster (~40 ms a run)
_PNG = {"compress_level": 1}
_DPI = 110


def result_name(result: Result) -> str:
    """The scene's name, or ``run`` for a result without a scene."""
    return str(getattr(result.scene, "name", None) or "run")


def write_run_outputs(result: Result, out: Path, spectrum_scale: str = "log",
                      plotter: Forerunner | None = None) -> dict[str, Any]:
    """Write plots, CSV and summary.json of ``result`` into ``out`` (whole or not at all).

    ``spectrum_scale``: amplitude axis of spectrum.png, ``"log"`` or ``"linear"``.
    ``plotter``: a forerunner that imported the plotting stack while the result was computed
    (gear_dyn/cli/_parallel.py): it draws the figures; else this process does.
    """
    summary = summarize(result)
    with staged_output(out) as tmp:
        _write_timeseries(result, summary, tmp / "timeseries.csv")
        write_json(tmp / "summary.json", summary)
        job = functools.partial(draw_run_figures, result, tmp, spectrum_scale)
        if plotter is not None:
            plotter.run(job)
        else:
            job()
    return summary


def draw_run_figures(result: Result, tmp: Path, spectrum_scale: str) -> None:
    """time_history.png and spectrum.png of ``result`` in ``tmp``.

    With a core to spare, a forked child draws the zoom column of the time history (into
    memory shared with this process) and then the spectrum, while this process draws the
    whole-run column and lays the child's column over it (gear_dyn/plots/_compose.py). The
    figure is built once, before the fork, and shared by both.
    """
    from gear_dyn.plots._compose import canvas_shape, column_of, lay_over, render_part, write_png
    from gear_dyn.plots.run import plot_spectrum, plot_time_history

    fig = plot_time_history(result, blocks=1500)  # ~2 per pixel column at dpi 110

    def spectrum() -> None:
        save_figure(plot_spectrum(result, scale=spectrum_scale), tmp / "spectrum.png",
                    dpi=_DPI, pil_kwargs=_PNG)

    if not can_fork() or len({column_of(a) for a in fig.axes}) < 2:
        save_figure(fig, tmp / "time_history.png", dpi=_DPI, pil_kwargs=_PNG)
        spectrum()
        return
    shape = canvas_shape(tuple(fig.get_size_inches()), _DPI)
    zoom = np.frombuffer(mmap.mmap(-1, math.prod(shape)), dtype=np.uint8).reshape(shape)

    def zoom_column() -> None:
        zoom[...] = render_part(fig, _DPI, lambda a: column_of(a) > 0, base=False)

    with child_tasks(zoom_column, spectrum) as work:
        whole = render_part(fig, _DPI, lambda a: column_of(a) == 0, base=True)
        work.wait(0)
        write_png(lay_over(whole, zoom), tmp / "time_history.png", dpi=_DPI, **_PNG)


def _write_timeseries(result: Result, summary: dict[str, Any], path: Path) -> None:
    """timeseries.csv: states and outputs in SI units, a commented head stating them."""
    cols: dict[str, Any] = {"t_s": result.t}
    for i, name in enumerate(result.state_labels):
        cols[name] = result.y[i]
    for name, arr in result.outputs.items():
        if name not in cols:
            cols[name] = arr
    head = [f"# {result_name(result)}: time series in SI units (t_s in s; dte, delta, "
            "e_ecc in m;", "# mesh_force in N; stiffness in N/m; angles in rad, rates in "
            "rad/s)",
            f"# dte: {summary['dte_definition']}",
            f"# dynamic factor {summary['dynamic_factor']:.6g}: "
            f"{summary['dynamic_factor_definition']}"]
    write_csv(path, cols, comments=head)
