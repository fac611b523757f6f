"""Where a whole ``gear-dyn run`` process spends its time, phase by phase (one process, serial).

Run:  python benchmarks/cli_phases.py [SCENE]      (prints ``phase<TAB>seconds`` lines)

The same steps as ``gear-dyn run SCENE --out DIR``, in a fresh interpreter, each timed by wall
clock, but serially. The command itself, with a second core free, runs them on two cores
(gear_dyn/cli/_parallel.py): at its start it forks a forerunner that imports matplotlib (the
quick import of gear_dyn/plots/_warm.py, timed here) while the command imports gear_dyn, reads
the scene, solves and writes the CSV and JSON; the forerunner then builds the time history and
forks once more, so that one process draws its whole-run column and the other its zoom column
and the spectrum. Python's own
start-up is not included (``python -c pass`` in benchmarks/bench_cli.py). Used by
benchmarks/bench_cli.py for the phase table of its report.
"""

from __future__ import annotations

import gc
import sys
import tempfile
import time
from pathlib import Path

T0 = time.perf_counter()
LAPS: list[tuple[str, float]] = []


def lap(name: str) -> None:
    LAPS.append((name, time.perf_counter()))


def main(scene_path: str) -> None:
    gc.disable()  # as cli/run.py does while it runs
    import numpy  # noqa: F401

    lap("import numpy")
    from gear_dyn.cli.output import _write_timeseries
    from gear_dyn.io import save_figure, write_json
    from gear_dyn.scene import load_scene, run_scene

    lap("import gear_dyn (scene, models, solvers, analysis)")
    scene = load_scene(scene_path)
    lap("read the scene")
    result = run_scene(scene)
    lap("solve + error estimate")
    from gear_dyn.analysis.report import summarize

    summary = summarize(result)
    with tempfile.TemporaryDirectory() as tmp:
        _write_timeseries(result, summary, Path(tmp) / "timeseries.csv")
        write_json(Path(tmp) / "summary.json", summary)
        lap("summary, timeseries.csv, summary.json")
        from gear_dyn.plots._warm import import_for_files

        import_for_files()
        from gear_dyn.plots.run import plot_spectrum, plot_time_history

        lap("import matplotlib (Figure, Agg; the forerunner's quick import)")
        fig = plot_time_history(result, blocks=1500)
        save_figure(fig, Path(tmp) / "t.png", dpi=110, pil_kwargs={"compress_level": 1})
        lap("time_history.png (build, draw, PNG)")
        fig = plot_spectrum(result)
        save_figure(fig, Path(tmp) / "s.png", dpi=110, pil_kwargs={"compress_level": 1})
        lap("spectrum.png (build, draw, PNG)")
    prev = T0
    for name, t in LAPS:
        print(f"{name}\t{t - prev:.4f}")
        prev = t
    gc.freeze()  # as cli/app.py does at the end (not timed here: the exit itself)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "examples/scenes/helicopter_tail.toml")
