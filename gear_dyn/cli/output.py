"""Writing a run's files (shared by ``run`` and ``demo``)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from gear_dyn.io import save_figure, staged_output, write_json
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
    Returns the summary (:meth:`Result.to_dict <gear_dyn.solvers.result.Result.to_dict>`).
    """
    summary = result.to_dict()
    with staged_output(out) as tmp:
        result.to_csv(tmp / "timeseries.csv")
        write_json(tmp / "summary.json", summary)
        save_figure(plot_time_history(result, blocks=ENVELOPE_BLOCKS), tmp / "time_history.png",
                    dpi=DPI, pil_kwargs=PNG_OPTIONS)
        save_figure(plot_spectrum(result, scale=spectrum_scale), tmp / "spectrum.png", dpi=DPI,
                    pil_kwargs=PNG_OPTIONS)
    return summary

