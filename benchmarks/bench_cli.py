"""Whole-process speed of ``gear-dyn run`` against the naive script, side by side.

Run:  python benchmarks/bench_cli.py [--repeats 5] [--scenes helicopter_tail,...] [--out DIR]
      [--record]

What a user feels is the whole command: start-up, scene parsing, the solve, plots and files.
For each scene this measures, in one run and interleaved (naive, gear-dyn, naive, gear-dyn, ...):

1. ``python benchmarks/naive_run.py``: one ``solve_ivp(RK45)`` call, plain Python right-hand
   side, and the same two PNGs (time history, spectrum), at its loosest rtol (of 1e-6..1e-11)
   reaching max error <= 1e-6 of the static deflection against the reference;
2. ``gear-dyn run SCENE --out DIR`` (the scene's own settings), whose error is read back from its
   ``timeseries.csv`` (10 significant digits) and must also be <= 1e-6;

and the ratio naive / gear-dyn pair by pair (median, min, max), against the target: the whole
command at least ``TARGET_RATIO`` (2.5) times faster than the naive script. The reference is
``gear_dyn.analysis.bench.reference_solution`` (the exact propagator, or DOP853 restarted at
every switching instant and contact change at rtol 1e-13 for backlash).

It also times, ``repeats`` fresh processes each:

- ``gear-dyn --help``, ``python -c "import gear_dyn"`` and importing numpy and matplotlib;
- ``gear-dyn run`` of the first scene and a serial ``gear-dyn sweep`` of the backlash scene with
  two BLAS threads against the command's default of one
  (``gear_dyn.cli.app.limit_blas_threads``), pair by pair;
- the phases of both (``benchmarks/cli_phases.py``; ``NAIVE_PHASES=1 benchmarks/naive_run.py``):
  where the time goes;

and what each drawing choice of the run's figures saves (``benchmarks/cli_phases.py
--choices``, on the runs of :data:`CHOICE_RUNS`).

Writes ``cli.md`` into ``--out`` (default ``benchmarks/out/``, git-ignored); ``--record`` writes
it into ``benchmarks/results/`` instead (the recorded figures).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
from _timing import as_installed, run_child, spread  # noqa: E402  (benchmarks/ is on sys.path)

from gear_dyn.analysis.accuracy import relative_errors
from gear_dyn.analysis.bench import reference_solution
from gear_dyn.scene import load_scene
from gear_dyn.scene.build import build_plan
from gear_dyn.solvers import output_grid

ROOT = Path(__file__).resolve().parents[1]
SCENES = ("helicopter_tail", "helicopter_tail_backlash")
TARGET = 1e-6
#: the whole command's target: at least this many times faster than the naive script
TARGET_RATIO = 2.5
#: the drawing choices are timed on these runs: (scene, mesh periods or None for the scene's
#: own); eccentric_helical is the longest packaged run (40 321 samples per line), the last a
#: long run of the first scene as ``gear-dyn run --periods 2000`` makes it
CHOICE_RUNS: tuple[tuple[str, int | None], ...] = (("helicopter_tail", None),
                                                   ("eccentric_helical", None),
                                                   ("helicopter_tail", 2000))
RTOLS = (1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11)
GEAR_DYN = str(Path(sys.executable).with_name("gear-dyn"))
MPL_USUAL = "import numpy, matplotlib.figure, matplotlib.backends.backend_agg"
#: BLAS threads for the comparison with the command's default of one
BLAS_TWO = {var: "2" for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")}
#: the sweep timed with two BLAS threads and with one: scene, speeds (up and down), serial
BLAS_SWEEP_SCENE = "helicopter_tail_backlash"
BLAS_SWEEP_SPEEDS = "2000 rpm:6000 rpm:24"
#: the children's environment (bytecode compiled as after pip install), set by main()
ENV: dict[str, str] = {}


def _environment() -> str:
    """What the timed interpreter has installed that changes the command's start-up: the unit
    parser pint imports Dask at start-up when Dask is installed (the ``dask`` extra)."""
    import importlib.util

    dask = importlib.util.find_spec("dask") is not None
    return (f"Dask {'installed (pint imports it at start-up)' if dask else 'not installed'} "
            "- the README's demo install, `pip install .`, has no Dask")


def timed(cmd: list[str], env: dict[str, str] | None = None) -> float:
    """Wall time of one whole process in s (its output discarded; a failure raises);
    ``env``: variables set on top of :data:`ENV`."""
    return timed_cpu(cmd, env)[0]


def timed_cpu(cmd: list[str], env: dict[str, str] | None = None) -> tuple[float, float]:
    """Wall time and CPU time (user + system, of the process and its children) of one whole
    process in s. On a machine busy with other work the wall time grows with the load; the CPU
    time much less."""
    done = run_child(cmd, env={**ENV, **(env or {})})
    return done.wall, done.cpu


def naive_params(model: Any, t: np.ndarray, rtol: float) -> dict[str, Any]:
    """The numbers the naive script needs (it imports nothing from gear_dyn)."""
    edges, values = model.stiffness.segments()
    return {"mass": model.mass, "damping": model.damping, "static_load": model.static_load,
            "mesh_frequency": model.mesh_frequency, "f_switch": float(edges[1]),
            "k_hi": float(values[0]), "k_lo": float(values[1]), "half_gap": model.backlash,
            "y0": [float(v) for v in model.initial_state()], "t_end": float(t[-1]),
            "n_samples": len(t), "rtol": rtol,
            "atol": [rtol * float(s) for s in model.state_scale]}


def naive_cmd(params: dict[str, Any], work: Path) -> list[str]:
    pfile = work / f"params_{params['rtol']:.0e}.json"
    pfile.write_text(json.dumps(params))
    return [sys.executable, str(ROOT / "benchmarks" / "naive_run.py"), str(pfile),
            str(work / "naive")]


def bench_scene(name: str, repeats: int, work: Path) -> dict[str, Any]:
    """One scene: the naive script at its loosest rtol reaching TARGET against gear-dyn run."""
    path = ROOT / "examples" / "scenes" / f"{name}.toml"
    plan = build_plan(load_scene(path))
    model = plan.model
    t = output_grid(model, plan.t_end, plan.settings)
    ref = reference_solution(model, t)
    chosen: dict[str, Any] | None = None
    for rtol in RTOLS:
        cmd = naive_cmd(naive_params(model, t, rtol), work)
        timed(cmd)
        err = relative_errors(model, t, np.load(work / "naive" / "y.npy"), ref.y)[0]
        if err <= TARGET:
            chosen = {"rtol": rtol, "cmd": cmd, "err": err}
            break
    if chosen is None:
        raise SystemExit(f"{name}: the naive script does not reach {TARGET:g} at rtol 1e-11")
    ours = [GEAR_DYN, "run", str(path), "--out", str(work / "gd")]
    t_naive, t_ours, cpu_naive, cpu_ours = [], [], [], []
    timed(ours)  # warm-up (pint's definition cache, file-system caches)
    for _ in range(repeats):
        for times, cpus, cmd in ((t_naive, cpu_naive, chosen["cmd"]), (t_ours, cpu_ours, ours)):
            wall, cpu = timed_cpu(cmd)
            times.append(wall)
            cpus.append(cpu)
    lines = (work / "gd" / "timeseries.csv").read_text().splitlines()
    body = [ln for ln in lines if not ln.startswith("#")][1:]  # comments, then the header
    data = np.loadtxt(body, delimiter=",")
    err_ours = relative_errors(model, t, data[:, 1:3].T, ref.y)[0]
    ratios = [a / b for a, b in zip(t_naive, t_ours, strict=True)]
    cpu_ratios = [a / b for a, b in zip(cpu_naive, cpu_ours, strict=True)]
    return {"scene": name, "naive_rtol": chosen["rtol"], "naive_err": chosen["err"],
            "ours_err": err_ours, "t_naive": t_naive, "t_ours": t_ours, "ratios": ratios,
            "cpu_naive": cpu_naive, "cpu_ours": cpu_ours, "cpu_ratios": cpu_ratios,
            "ref": ref.kind, "naive_cmd": chosen["cmd"], "path": path}


def phase_times(cmd: list[str], stream: str, env: dict[str, str]) -> dict[str, float]:
    """``phase<TAB>seconds`` lines a process prints (stdout or stderr) as a dict."""
    t0 = time.perf_counter()
    out = subprocess.run(cmd, check=True, capture_output=True, text=True,
                         env={**ENV, **env})
    wall = time.perf_counter() - t0
    lines = (out.stdout if stream == "stdout" else out.stderr).splitlines()
    res = {ln.split("\t")[0]: float(ln.split("\t")[1]) for ln in lines if "\t" in ln}
    res["the rest: interpreter start-up and exit"] = wall - sum(res.values())
    return res


def phases(row: dict[str, Any], repeats: int) -> dict[str, dict[str, list[float]]]:
    """Phase times of the gear-dyn run path (benchmarks/cli_phases.py) and of the naive script
    (NAIVE_PHASES=1), ``repeats`` interleaved fresh processes each."""
    ours_cmd = [sys.executable, str(ROOT / "benchmarks" / "cli_phases.py"), str(row["path"])]
    res: dict[str, dict[str, list[float]]] = {"gear-dyn run": {}, "naive script": {}}
    for _ in range(repeats):
        for key, cmd, stream, env in (("gear-dyn run", ours_cmd, "stdout", {}),
                                      ("naive script", row["naive_cmd"], "stderr",
                                       {"NAIVE_PHASES": "1"})):
            for name, sec in phase_times(cmd, stream, env).items():
                res[key].setdefault(name, []).append(sec)
    return res


def startup(repeats: int) -> dict[str, list[float]]:
    """Whole-process times of ``gear-dyn --help``, ``import gear_dyn`` and of importing numpy
    and matplotlib."""
    cmds = {"gear-dyn --help": [GEAR_DYN, "--help"],
            "python -c 'import gear_dyn'": [sys.executable, "-c", "import gear_dyn"],
            "python -c 'pass'": [sys.executable, "-c", "pass"],
            "import numpy, matplotlib.figure, Agg": [sys.executable, "-c", MPL_USUAL]}
    out: dict[str, list[float]] = {k: [] for k in cmds}
    for cmd in cmds.values():
        timed(cmd)
    for _ in range(repeats):
        for key, cmd in cmds.items():
            out[key].append(timed(cmd))
    return out


def blas(row: dict[str, Any], repeats: int, work: Path) -> dict[str, dict[str, list[float]]]:
    """``gear-dyn run`` of a scene and ``gear-dyn sweep`` of the backlash scene in its own
    process (24 speeds up and down) with two BLAS threads and with the command's default (one),
    interleaved; the ratio two / one pair by pair."""
    sweep = [GEAR_DYN, "sweep", str(ROOT / "examples" / "scenes" / f"{BLAS_SWEEP_SCENE}.toml"),
             "--speeds", BLAS_SWEEP_SPEEDS, "--workers", "1", "--quiet", "--out",
             str(work / "blas_sweep")]
    cmds = {f"gear-dyn run {row['scene']}": [GEAR_DYN, "run", str(row["path"]), "--out",
                                              str(work / "blas")],
            f"gear-dyn sweep {BLAS_SWEEP_SCENE} --speeds '{BLAS_SWEEP_SPEEDS}' --workers 1":
                sweep}
    out = {}
    for name, cmd in cmds.items():
        timed(cmd)
        two, one = [], []
        for _ in range(repeats):
            two.append(timed(cmd, BLAS_TWO))
            one.append(timed(cmd))
        out[name] = {"two": two, "one": one,
                     "ratios": [a / b for a, b in zip(two, one, strict=True)]}
    return out


def choices(scene: Path, periods: int | None) -> dict[str, float]:
    """``benchmarks/cli_phases.py --choices SCENE [--periods N]``: seconds each drawing choice
    saves."""
    extra = [] if periods is None else ["--periods", str(periods)]
    out = subprocess.run([sys.executable, str(ROOT / "benchmarks" / "cli_phases.py"),
                          "--choices", str(scene), *extra], check=True, capture_output=True,
                         text=True, env=ENV)
    return {ln.split("\t")[0]: float(ln.split("\t")[1]) for ln in out.stdout.splitlines()
            if "\t" in ln}


def _choice_rows(scene: str, saved: dict[str, float]) -> list[str]:
    """Rows of the drawing-choices table for one scene."""
    both = saved["ours (both figures)"]
    size = saved["ours (bytes)"]
    texts = {
        "envelope": "whole-run lines from every sample, not their per-pixel envelope",
        "tight_layout": "`tight_layout`, not fixed margins in inches",
        "png_zlib_6": "PNG zlib level 6 (matplotlib's default), not 1",
        "mathtext_first_use": "the first mathtext label of a process (log tick labels "
                              "`10^{-8}`), against the same label in plain text "
                              "(fresh processes)",
    }
    rows = []
    for key, text in texts.items():
        extra = ""
        if key == "png_zlib_6":
            extra = (f"; both files {saved['png_zlib_6 (bytes)'] / 1e3:.0f} kB instead of "
                     f"{size / 1e3:.0f} kB")
        rows.append(f"| {scene} ({saved['samples per line']:.0f} samples per line) | {text} | "
                    f"{saved[key] * 1e3:+.0f} ms "
                    f"({100 * saved[key] / both:+.0f} %){extra} |")
    return rows


def report(rows: list[dict[str, Any]], start: dict[str, list[float]], repeats: int,
           phase: dict[str, dict[str, list[float]]],
           blas_row: dict[str, dict[str, list[float]]],
           saved: dict[str, dict[str, float]], command: str) -> str:
    ratios = [statistics.median(r["ratios"]) for r in rows]
    met = all(x >= TARGET_RATIO for x in ratios)
    lines = [
        "# Whole-command speed: `gear-dyn run` vs the naive script (one side-by-side run)", "",
        f"Produced by `{command}` on {platform.machine()} (Python "
        f"{platform.python_version()}); {repeats} interleaved pairs per scene, figures as median "
        f"(min..max). The machine is shared ({os.cpu_count()} cores, 1-minute load average "
        f"{os.getloadavg()[0]:.1f} at the end): the ratios, measured pair by pair, are the "
        "figures to quote.", "",
        f"Installed packages: {_environment()}.", "",
        "`gear-dyn run` works in its own process only: it reads the scene, solves, writes the "
        "CSV and JSON, then draws and writes the two figures, one after the other.", "",
        "Naive script: `benchmarks/naive_run.py` (one `solve_ivp(RK45)` call, plain Python "
        "right-hand side, pyplot time history + spectrum PNGs) at its loosest rtol reaching "
        f"max error <= {TARGET:g} of the static deflection. `gear-dyn run SCENE --out DIR`: the "
        "scene's own settings (also writes the CSV and summary.json). gear_dyn's bytecode is "
        "compiled before timing, as `pip install` leaves it, and `PYTHONDONTWRITEBYTECODE` is "
        "not passed on (with it set, an editable install compiles every gear_dyn module in "
        "every process).", "",
        "| scene | naive rtol | naive error | gear-dyn error | naive (s) | gear-dyn run (s) "
        "| ratio naive / gear-dyn |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['scene']} | {r['naive_rtol']:.0e} | {r['naive_err']:.1e} | "
            f"{r['ours_err']:.1e} | {spread(r['t_naive'])} | {spread(r['t_ours'])} | "
            f"**{spread(r['ratios'])}x** |")
    lines += ["", "The same pairs in CPU time (user + system of each process; on a machine busy "
              "with other work it grows much less than the wall time):", "",
              "| scene | naive CPU (s) | gear-dyn run CPU (s) | ratio naive / gear-dyn |",
              "|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['scene']} | {spread(r['cpu_naive'])} | {spread(r['cpu_ours'])} | "
                     f"{spread(r['cpu_ratios'])}x |")
    lines += ["", f"Target: the whole command at least {TARGET_RATIO:g}x faster than the naive "
              f"script (median ratio): **{'met' if met else 'NOT met'}** "
              f"({', '.join(f'{x:.2f}x' for x in ratios)}).", ""]
    lines += ["Start-up, whole processes:", "", "| command | wall time (s) |", "|---|---|"]
    for key, vals in start.items():
        lines.append(f"| `{key}` | {spread(vals)} |")
    lines += ["", "BLAS threads (`gear_dyn.cli.app.limit_blas_threads`: one per process unless "
              "the user sets OPENBLAS_NUM_THREADS / OMP_NUM_THREADS / MKL_NUM_THREADS), whole "
              "processes, interleaved pairs:", "",
              "| command | two BLAS threads (s) | one, the default (s) | ratio two / one |",
              "|---|---|---|---|"]
    for name, b in blas_row.items():
        lines.append(f"| `{name}` | {spread(b['two'])} | {spread(b['one'])} | "
                     f"**{spread(b['ratios'])}x** |")
    lines += [""]
    lines += [f"Where the time goes ({rows[0]['scene']}; fresh processes, phases timed inside "
              "them, the rest is the process's wall time minus the phases; "
              "`python benchmarks/cli_phases.py` and "
              "`NAIVE_PHASES=1 python benchmarks/naive_run.py`):", "",
              "| process | phase | wall time (s) |", "|---|---|---|"]
    for who, table in phase.items():
        for name, vals in table.items():
            lines.append(f"| {who} | {name} | {spread(vals)} |")
        total = [sum(v) for v in zip(*table.values(), strict=True)]
        lines.append(f"| {who} | **whole process** | {spread(total)} |")
    lines += ["", "What the drawing choices of the run's figures save (`python "
              "benchmarks/cli_phases.py --choices SCENE [--periods N]`: one process after a "
              "warm-up; building, drawing and writing both figures the plain way minus as the "
              "command does it, each the least of interleaved runs; the share is of the "
              "command's time for both figures, "
              + ", ".join(f"{k} {v['ours (both figures)']:.2f} s" for k, v in saved.items())
              + "; a positive figure is time the choice saves):", "",
              "| scene | done instead | costs |", "|---|---|---|"]
    for scene, vals in saved.items():
        lines += _choice_rows(scene, vals)
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--out", type=Path, default=ROOT / "benchmarks" / "out")
    ap.add_argument("--record", action="store_true",
                    help="write into benchmarks/results/ (the recorded figures)")
    args = ap.parse_args(argv)
    command = "python benchmarks/bench_cli.py " + " ".join(sys.argv[1:] if argv is None
                                                            else argv)
    ENV.update(as_installed(ROOT / "gear_dyn"))
    out_dir = ROOT / "benchmarks" / "results" if args.record else args.out
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.scenes.split(","):
            r = bench_scene(name.strip(), args.repeats, Path(tmp))
            print(f"{r['scene']}: naive / gear-dyn run = {spread(r['ratios'])}x, CPU time "
                  f"{spread(r['cpu_ratios'])}x (errors {r['naive_err']:.1e} / "
                  f"{r['ours_err']:.1e})", flush=True)
            rows.append(r)
        phase = phases(rows[0], args.repeats)
        blas_row = blas(rows[0], args.repeats, Path(tmp))
        for name, b in blas_row.items():
            print(f"BLAS two / one thread, {name}: {spread(b['ratios'])}x", flush=True)
    start = startup(args.repeats)
    for key, vals in start.items():
        print(f"{key}: {spread(vals)} s")
    saved = {}
    for scene, periods in CHOICE_RUNS:
        label = scene if periods is None else f"{scene} --periods {periods}"
        saved[label] = choices(ROOT / "examples" / "scenes" / f"{scene}.toml", periods)
        print(f"drawing choices, {label}: {saved[label]}", flush=True)
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "cli.md").write_text(report(rows, start, args.repeats, phase, blas_row, saved,
                                           command.strip()))
    print(f"wrote {out_dir / 'cli.md'}")
    return 0 if all(math.isfinite(statistics.median(r["ratios"])) for r in rows) else 1


if __name__ == "__main__":
    raise SystemExit(main())
