"""Where a ``gear-dyn run`` process spends its time, and what its drawing choices save.

Run:  python benchmarks/cli_phases.py [SCENE]            (prints ``phase<TAB>seconds`` lines)
      python benchmarks/cli_phases.py --choices [SCENE] [--periods N]
                                                         (prints ``choice<TAB>seconds`` lines)

Phases: the steps of ``gear-dyn run SCENE --out DIR`` (gear_dyn/cli/run.py, cli/output.py), in
a fresh interpreter, each timed by wall clock. Python's own start-up and exit are not included
(benchmarks/bench_cli.py reports them as the rest of the process's wall time).

Choices (``--choices``): what each choice of the run's figures saves, in one process after a
warm-up (matplotlib imported, fonts loaded): the time to build, draw and write both figures
(time_history.png and spectrum.png) done the plain way minus done as the command does it, each
the least of ``REPEATS`` interleaved runs (the run least disturbed by other work on a shared
machine, as the ``timeit`` documentation advises):

- ``envelope``: whole-run lines drawn from every sample instead of their per-pixel envelope
  (:func:`gear_dyn.plots._decimate.envelope`, :data:`gear_dyn.cli.output.ENVELOPE_BLOCKS`);
- ``tight_layout``: ``tight_layout`` instead of the fixed margins
  (:func:`gear_dyn.plots._axes.fixed_layout`);
- ``png_zlib_6``: matplotlib's default PNG compression instead of level 1
  (:data:`gear_dyn.cli.output.PNG_OPTIONS`), also the sizes of both files;

and, in fresh processes, ``mathtext_first_use``: what the first mathtext label of a process
costs (the log axes' tick labels ``10^{-8}`` are drawn by it), against the same label in plain
text. Used by benchmarks/bench_cli.py.
"""

from __future__ import annotations

import gc
import io
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

T0 = time.perf_counter()
LAPS: list[tuple[str, float]] = []
REPEATS = 11
DEFAULT_SCENE = "examples/scenes/helicopter_tail.toml"


def lap(name: str) -> None:
    LAPS.append((name, time.perf_counter()))


def phases(scene_path: str) -> None:
    """Time the steps of ``gear-dyn run`` (gear_dyn/cli/output.py) and print them."""
    import numpy  # noqa: F401

    lap("import numpy")
    from gear_dyn.analysis.report import summarize
    from gear_dyn.io import write_json
    from gear_dyn.scene import load_scene, run_scene

    lap("import gear_dyn (scene, models, solvers, analysis)")
    scene = load_scene(scene_path)
    lap("read the scene")
    result = run_scene(scene)
    lap("solve + error estimate")
    from gear_dyn.cli.output import DPI, ENVELOPE_BLOCKS, PNG_OPTIONS
    from gear_dyn.io import save_figure
    from gear_dyn.plots.run import plot_spectrum, plot_time_history

    lap("import matplotlib (Figure, Agg) and the run figures")
    summary = summarize(result)
    with tempfile.TemporaryDirectory() as tmp:
        result.to_csv(Path(tmp) / "timeseries.csv")
        write_json(Path(tmp) / "summary.json", summary)
        lap("summary, timeseries.csv, summary.json")
        save_figure(plot_time_history(result, blocks=ENVELOPE_BLOCKS), Path(tmp) / "t.png",
                    dpi=DPI, pil_kwargs=PNG_OPTIONS)
        lap("time_history.png (build, draw, PNG)")
        save_figure(plot_spectrum(result), Path(tmp) / "s.png", dpi=DPI, pil_kwargs=PNG_OPTIONS)
        lap("spectrum.png (build, draw, PNG)")
    prev = T0
    for name, t in LAPS:
        print(f"{name}\t{t - prev:.4f}")
        prev = t


def _both_figures(result: Any, blocks: int | None, layout: str, png: dict[str, Any]
                  ) -> tuple[float, int]:
    """Build, draw and write (to memory) both run figures: (seconds, bytes)."""
    from matplotlib.figure import Figure

    from gear_dyn.cli.output import DPI
    from gear_dyn.plots.run import plot_spectrum, plot_time_history, time_history_size

    gc.collect()  # the previous call's figures are not collected inside this one's timing
    t0 = time.perf_counter()
    if layout == "fixed":
        figs = [plot_time_history(result, blocks=blocks), plot_spectrum(result)]
    else:  # the caller's axes: the plot functions call tight_layout
        th = Figure(figsize=time_history_size(result))
        sp = Figure(figsize=(10, 7 if result.extra.get("eccentric") else 4.5))
        sp_axes = sp.subplots(2 if result.extra.get("eccentric") else 1, 1, squeeze=False)
        figs = [plot_time_history(result, blocks=blocks,
                                  ax=th.subplots(*_grid(result), sharex="col")),
                plot_spectrum(result, ax=sp_axes[:, 0] if sp_axes.size > 1 else sp_axes[0, 0])]
    size = 0
    for fig in figs:
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=DPI, pil_kwargs=png)
        size += buf.tell()
    return time.perf_counter() - t0, size


def _grid(result: Any) -> tuple[int, int]:
    return (3 if "e_ecc" in result.outputs else 2), 2


def _paired(plain: Callable[[], tuple[float, int]], ours: Callable[[], tuple[float, int]]
            ) -> tuple[float, float, int, int]:
    """The least time of ``plain`` and of ``ours`` over REPEATS interleaved runs; the bytes of
    each."""
    t_plain, t_ours = [], []
    size_plain = size_ours = 0
    for _ in range(REPEATS):
        tp, size_plain = plain()
        to, size_ours = ours()
        t_plain.append(tp)
        t_ours.append(to)
    return min(t_plain), min(t_ours), size_plain, size_ours


def _mathtext_first_use() -> float:
    """The first label drawn by mathtext minus the same label in plain text (after importing
    matplotlib and drawing one plain text), each the least of REPEATS fresh processes."""
    code = ("import time\nfrom matplotlib.figure import Figure\n"
            "from matplotlib.backends.backend_agg import FigureCanvasAgg\n"
            "f = Figure(); FigureCanvasAgg(f); f.text(0.1, 0.1, 'warm'); f.canvas.draw()\n"
            "t0 = time.perf_counter(); f.text(0.5, 0.5, LABEL); f.canvas.draw()\n"
            "print(time.perf_counter() - t0)\n")
    times: dict[str, list[float]] = {r"$\mathdefault{10^{-8}}$": [], "10⁻⁸": []}
    for _ in range(REPEATS):
        for label, seen in times.items():
            seen.append(float(subprocess.run([sys.executable, "-c",
                                              code.replace("LABEL", repr(label))],
                                             check=True, capture_output=True, text=True).stdout))
    mathtext, plain = times.values()
    return min(mathtext) - min(plain)


def choices(scene_path: str, periods: int | None = None) -> None:
    """Time what each drawing choice of ``gear-dyn run`` saves and print it (``periods``: mesh
    periods of the run, as ``gear-dyn run --periods``; None: the scene's own)."""
    from gear_dyn.cli.output import ENVELOPE_BLOCKS, PNG_OPTIONS
    from gear_dyn.scene import load_scene, run_scene

    result = run_scene(load_scene(scene_path), **({} if periods is None else
                                                   {"periods": periods}))
    print(f"samples per line\t{result.t.size}")

    def ours() -> tuple[float, int]:
        return _both_figures(result, ENVELOPE_BLOCKS, "fixed", PNG_OPTIONS)

    ours()  # warm-up: imports, fonts, caches
    variants = {
        "envelope": lambda: _both_figures(result, None, "fixed", PNG_OPTIONS),
        "tight_layout": lambda: _both_figures(result, ENVELOPE_BLOCKS, "tight", PNG_OPTIONS),
        "png_zlib_6": lambda: _both_figures(result, ENVELOPE_BLOCKS, "fixed", {}),
    }
    best = []
    for name, plain in variants.items():
        t_plain, t_ours, size_plain, base_size = _paired(plain, ours)
        best.append(t_ours)
        print(f"{name}\t{t_plain - t_ours:.4f}")
        if name == "png_zlib_6":
            print(f"{name} (bytes)\t{size_plain}")
    print(f"ours (both figures)\t{min(best):.4f}")
    print(f"ours (bytes)\t{base_size}")
    print(f"mathtext_first_use\t{_mathtext_first_use():.4f}")


def main(argv: list[str]) -> None:
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene", nargs="?", default=DEFAULT_SCENE)
    ap.add_argument("--choices", action="store_true", help="time the drawing choices")
    ap.add_argument("--periods", type=int, default=None,
                    help="mesh periods of the run (--choices only; default: the scene's)")
    args = ap.parse_args(argv)
    if args.choices:
        choices(args.scene, args.periods)
    else:
        phases(args.scene)


if __name__ == "__main__":
    main(sys.argv[1:])
