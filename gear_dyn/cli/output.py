"""Writing a run's files (shared by ``run`` and ``demo``)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from gear_dyn.analysis.report import summarize
from gear_dyn.cli._parallel import task_in_child
from gear_dyn.io import save_figure, staged_output, write_csv, write_json
from gear_dyn.solvers import Result

#: zlib level 1: the same pixels, ~20 % larger files, the encoder ~2x faster (~40 ms a run)
_PNG = {"compress_level": 1}


def result_name(result: Result) -> str:
    """The scene's name, or ``run`` for a result without a scene."""
    return str(getattr(result.scene, "name", None) or "run")


def write_run_outputs(result: Result, out: Path, spectrum_scale: str = "log") -> dict[str, Any]:
    """Write plots, CSV and summary.json of ``result`` into ``out`` (whole or not at all).

    ``spectrum_scale``: amplitude axis of spectrum.png, ``"log"`` or ``"linear"``.
    """

    from gear_dyn.plots.run import plot_spectrum, plot_time_history

    summary = summarize(result)
    with staged_output(out) as tmp:

        def time_history() -> None:
            fig = plot_time_history(result, blocks=1500)  # ~2 per pixel column at dpi 110
            save_figure(fig, tmp / "time_history.png", dpi=110, pil_kwargs=_PNG)

        # the larger figure in a forked child when a core is free, the rest here meanwhile
        with task_in_child(time_history):
            fig = plot_spectrum(result, scale=spectrum_scale)
            save_figure(fig, tmp / "spectrum.png", dpi=110, pil_kwargs=_PNG)
            _write_timeseries(result, summary, tmp / "timeseries.csv")
            write_json(tmp / "summary.json", summary)
    return summary


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
