"""Writing a run's files (shared by ``run`` and ``demo``)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from gear_dyn.analysis.report import summarize
from gear_dyn.io import save_figure, staged_output, write_csv, write_json
from gear_dyn.plots.run import plot_spectrum, plot_time_history
from gear_dyn.solvers import Result

#: PNG zlib level 1 instead of matplotlib's 6: the same pixels, larger files written faster
#: (``python benchmarks/cli_phases.py --choices``, benchmarks/results/cli.md)
PNG_OPTIONS = {"compress_level": 1}
#: resolution of the run's figures (pixels per inch)
DPI = 110
#: blocks of the time history's whole-run lines (:func:`gear_dyn.plots.run.plot_time_history`):
#: about 2 per pixel column of its 6.5 in panel at :data:`DPI`
ENVELOPE_BLOCKS = 1500


def write_run_outputs(result: Result, out: Path, spectrum_scale: str = "log") -> dict[str, Any]:
    """Write plots, CSV and summary.json of ``result`` into ``out`` (whole or not at all).

    ``spectrum_scale``: amplitude axis of spectrum.png, ``"log"`` or ``"linear"``.
    Returns the summary (:func:`gear_dyn.analysis.report.summarize`).
    """
    summary = summarize(result)
    with staged_output(out) as tmp:
        _write_timeseries(result, summary, tmp / "timeseries.csv")
        write_json(tmp / "summary.json", summary)
        save_figure(plot_time_history(result, blocks=ENVELOPE_BLOCKS), tmp / "time_history.png",
                    dpi=DPI, pil_kwargs=PNG_OPTIONS)
        save_figure(plot_spectrum(result, scale=spectrum_scale), tmp / "spectrum.png", dpi=DPI,
                    pil_kwargs=PNG_OPTIONS)
    return summary


def _write_timeseries(result: Result, summary: dict[str, Any], path: Path) -> None:
    """timeseries.csv: states and outputs in SI units, a commented head stating them."""
    cols: dict[str, Any] = {"t_s": result.t,
                            **dict(zip(result.state_labels, result.y, strict=True))}
    for name, arr in result.outputs.items():
        cols.setdefault(name, arr)  # an output named as a state is written once, as the state
    name = getattr(result.scene, "name", None) or "run"  # a result without a scene: "run"
    head = [f"# {name}: time series in SI units (t_s in s; dte, delta, "
            "e_ecc in m;", "# mesh_force in N; stiffness in N/m; angles in rad, rates in "
            "rad/s)",
            f"# dte: {summary['dte_definition']}",
            f"# dynamic factor {summary['dynamic_factor']:.6g}: "
            f"{summary['dynamic_factor_definition']}"]
    write_csv(path, cols, comments=head)
