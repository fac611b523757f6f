"""Speed sweeps: fixed cost, per-speed cost against the steady-state kernel, what workers buy.

Run:  python benchmarks/bench_sweep.py [--repeats 5] [--out DIR] [--record] [--no-dask] [--methods]
      [--jumps]

Scene `helicopter_tail.toml` (linear, piecewise-constant stiffness) and
`helicopter_tail_backlash.toml` (shooting with continuation up and down). Every repeat runs all
cases interleaved; each line gives the median of the repeats and (min..max); ratios are formed
inside one repeat and then summarised the same way.

1. Fixed cost, whole processes: ``gear-dyn sweep SCENE --speeds ...:2`` minus the start-up
   every scene command pays (a process importing the CLI and loading the scene); with and
   without ``--chart both``; the command's per-speed cost from 2 and 2000 speeds; and the whole
   backlash example sweep of docs/sweep.md (71 speeds up and down).
2. Per-speed cost in-process, 2000 speeds, one process: ``sweep_scene`` (the whole sweep:
   models, orbit, metrics, spectra, curves) against the steady-state kernel alone, a loop of
   ``periodic_steady_state(model)`` (monodromy matrix and fixed point) over the same speeds.
3. What workers buy: ``sweep_scene`` serial (the default) against ``workers=2`` (a process pool
   of 2, started by each call: its start-up is part of the figure) and, unless ``--no-dask``,
   a Dask ``LocalCluster`` of 2 processes (started once, outside the figures). Cases: one speed
   (the fixed cost of a pool), the linear example sweep of docs/sweep.md (300 speeds), 20000
   linear speeds, and the backlash example sweep (71 speeds up and down), also with
   ``method = "DOP853"`` pinned (orbits sampled by DOP853 instead of the exact contact
   propagator: more work per speed). Each parallel result is checked to equal the serial one.

BLAS runs single-threaded (``OPENBLAS_NUM_THREADS=1``, as ``gear-dyn sweep`` sets it): with its
default threads, on a loaded machine, scipy's ``expm`` of a 3x3 matrix took 10-30 ms.

Writes ``sweep.md`` into ``--out`` (default ``benchmarks/out/``, git-ignored); ``--record``
writes into ``benchmarks/results/``. ``--methods`` runs instead the slow comparison of the
steady method with transient integration (``sweep_methods.md``, minutes). ``--jumps`` runs
instead the cost of finding the jumps from the orbits (``sweep_jumps.md``): the backlash example
sweep (71 speeds up and down) and one on a grid twice as fine, whole (``sweep_scene``, the jumps
included) against the jump check alone (``find_jumps`` on its curves), with the pairs continued.
"""

from __future__ import annotations

import os

# as `gear-dyn sweep` does (before numpy loads): BLAS single-threaded. With its default threads,
# on a loaded machine scipy's expm of a 3x3 matrix (the kernel's) took 10-30 ms instead of 0.1
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
from _timing import as_installed, run_child, spread, timed, tree_env  # noqa: E402  (benchmarks/ is on sys.path)

from gear_dyn.analysis.stability import periodic_steady_state
from gear_dyn.analysis.study import simulate
from gear_dyn.analysis.sweep import RPM
from gear_dyn.scene import build_model, load_scene
from gear_dyn.scene.sweep import SceneModels, model_at_speed, sweep_scene
from gear_dyn.solvers import SolverSettings, integrate

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "gear_dyn" / "scenes" / "helicopter_tail.toml"
BACKLASH = ROOT / "gear_dyn" / "scenes" / "helicopter_tail_backlash.toml"
GEAR_DYN = str(Path(sys.executable).with_name("gear-dyn"))
STARTUP = ("import sys; from gear_dyn.cli.app import build_parser; "
           "from gear_dyn.scene import load_scene; load_scene(sys.argv[1])")
CHUNK = 10  # mesh periods per transient chunk between convergence checks

#: the children's environment (bytecode compiled as after pip install), set by main()
ENV: dict[str, str] = {}


def wall(cmd: list[str]) -> float:
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, capture_output=True, env=ENV or None)
    return time.perf_counter() - t0


def _timed(fn, repeats: int):  # type: ignore[no-untyped-def]
    times, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), times, out


def transient(scene, speeds, mode: str, method: str = "auto"):  # type: ignore[no-untyped-def]
    """(dynamic factor, RMS DTE, mesh periods integrated) per speed by transient integration.

    mode ``run``: the scene's 200 periods, the last 100 measured (as ``gear-dyn run``).
    mode ``adaptive``: chunks of CHUNK periods until the state at the start of the last period
    and one period later differ by less than 1e-9 of the state scale (the remaining transient
    is then ~1e-9 / (1 - rho) <= 1e-8 for rho <= 0.9), then the last period is measured.
    """
    spp = 64
    # DOP853 runs at rtol 1e-10 so its period-to-period noise stays below the 1e-9 criterion
    # (its one-period map is not smooth: at rtol 1e-8 the iterates wander at ~1e-9 for ever)
    rtol = 1e-8 if method == "auto" else 1e-10
    settings = SolverSettings(method=method, rtol=rtol, samples_per_period=spp)
    df, rms, used = [], [], []
    for w in speeds:
        model = model_at_speed(scene, float(w))
        fm = model.mesh_frequency
        if mode == "run":
            r = simulate(model, 200 / fm, settings, 100 / fm)
            x = r.outputs["dte"][r.steady][1:]  # whole periods (phase 0 once)
            df.append(r.peak_force_ratio)
            rms.append(float(np.std(x)))
            used.append(200)
            continue
        y0 = model.initial_state()
        scale = np.asarray(model.state_scale)
        t = np.arange(CHUNK * spp + 1) / (fm * spp)
        n = 0
        while True:
            y, _ = integrate(model, t, settings, y0)
            n += CHUNK
            change = np.max(np.abs(y[:, -1] - y[:, -1 - spp]) / scale)
            y0 = y[:, -1]
            if change < 1e-9 or n >= 2000:
                break
        out = model.outputs(t[-spp - 1:-1], y[:, -spp - 1:-1])
        df.append(float(np.max(out["mesh_force"]) / model.static_load))
        rms.append(float(np.std(out["dte"])))
        used.append(n)
    return np.array(df), np.array(rms), np.array(used)


def methods_table(args: argparse.Namespace) -> str:
    """The method comparison (steady vs transient); slow: minutes."""
    scene = load_scene(SCENE)
    speeds = np.linspace(500, 12000, args.speeds) * RPM
    ref = sweep_scene(scene, speeds, si=True, rtol=1e-12).curves[0]

    rows = []

    def err(df: np.ndarray, rms: np.ndarray) -> str:
        e_df = float(np.max(np.abs(df / ref.peak_force_ratio - 1)))
        e_rms = float(np.max(np.abs(rms / ref.rms_dte - 1)))
        return f"{e_df:.1e} / {e_rms:.1e}"

    t_st, ts_st, res = _timed(lambda: sweep_scene(scene, speeds, si=True), args.repeats)
    c = res.curves[0]
    rows.append(("steady (monodromy, expm)", t_st, ts_st, err(c.peak_force_ratio, c.rms_dte),
                 "measured"))
    t_run, ts_run, out = _timed(lambda: transient(scene, speeds, "run"), args.repeats)
    rows.append(("transient as `gear-dyn run` (200 periods, exact)", t_run, ts_run,
                 err(out[0], out[1]), "measured"))
    t_tun, ts_tun, out = _timed(lambda: transient(scene, speeds, "adaptive"), args.repeats)
    rows.append(("transient until converged (exact)", t_tun, ts_tun, err(out[0], out[1]),
                 "measured"))
    periods_used = out[2]
    sub = speeds[::25]
    t_dop, ts_dop, out = _timed(lambda: transient(scene, sub, "adaptive", "DOP853"), 1)
    ref_sub = ref
    e_df = float(np.max(np.abs(out[0] / ref_sub.peak_force_ratio[::25] - 1)))
    e_rms = float(np.max(np.abs(out[1] / ref_sub.rms_dte[::25] - 1)))
    scale = speeds.size / sub.size
    rows.append(("transient until converged (DOP853, rtol 1e-10)", t_dop * scale,
                 [t * scale for t in ts_dop], f"{e_df:.1e} / {e_rms:.1e}",
                 f"extrapolated from {sub.size} speeds ({t_dop:.2f} s)"))
    base = build_model(scene)

    lines = [
        "# Speed sweep benchmark: steady state vs transient integration",
        "",
        f"Command: `python benchmarks/bench_sweep.py --methods --speeds {args.speeds} "
        f"--repeats {args.repeats}`",
        "",
        "Scene `gear_dyn/scenes/helicopter_tail.toml` (the helicopter tail drive of Jiang et al. "
        "(2018), ISO 6336 rectangular stiffness, "
        f"zeta = {base.damping_ratio}), {args.speeds} speeds from 500 to 12000 rpm "
        f"(f_m / f_n = {23 * 500 / 60 / base.natural_frequency:.3f} .. "
        f"{23 * 12000 / 60 / base.natural_frequency:.3f}; the main resonance f_m = f_n at "
        f"{base.natural_frequency * 60 / 23:.0f} rpm is inside, the parametric tongue near "
        f"f_m = 2 f_n is above the range). One process; median of {args.repeats} runs "
        f"(single runs in brackets).",
        "",
        f"Machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores shared "
        f"with other jobs (load average at the end: "
        f"{', '.join(f'{x:.1f}' for x in os.getloadavg())}), Python "
        f"{platform.python_version()}.",
        "",
        "Accuracy: largest relative deviation over all speeds of the dynamic factor / RMS DTE "
        "from the steady state at rtol 1e-12.",
        "",
        "| method | time for all speeds (s) | per speed (ms) | vs steady | accuracy (DF / RMS) "
        "| note |",
        "|---|---|---|---|---|---|",
    ]
    for name, t, ts, acc, note in rows:
        single = ", ".join(f"{x:.2f}" for x in ts)
        lines.append(f"| {name} | {t:.2f} ({single}) | {1e3 * t / speeds.size:.2f} | "
                     f"{t / t_st:.1f} x | {acc} | {note} |")
    lines += [
        "",
        f"Transient until converged: {int(np.min(periods_used))} .. {int(np.max(periods_used))} "
        f"mesh periods (median {int(np.median(periods_used))}); longest where the largest "
        f"Floquet multiplier is close to 1 (max {float(np.max(c.spectral_radius)):.3f} in this "
        f"range, at {float(c.speed[np.argmax(c.spectral_radius)] / RPM):.0f} rpm).",
        "",
        f"Ratio transient-as-run / steady: **{t_run / t_st:.0f} x**; converged exact transient "
        f"/ steady: **{t_tun / t_st:.1f} x**; converged DOP853 transient / steady: "
        f"**{rows[3][1] / t_st:.0f} x** (extrapolated).",
        "",
    ]
    return "\n".join(lines)


def cli_costs(repeats: int, work: Path) -> dict[str, list[float]]:
    """Whole-process times (s) per repeat: start-up, sweeps of 2 and 2000 speeds, the backlash
    example sweep (71 speeds up and down)."""
    sweep = [GEAR_DYN, "sweep", str(SCENE), "--quiet"]
    cases = {
        "startup": [sys.executable, "-c", STARTUP, str(SCENE)],
        "sweep_2": [*sweep, "--speeds", "500 rpm:12000 rpm:2", "--out", str(work / "a")],
        "sweep_2_charts": [*sweep, "--speeds", "500 rpm:12000 rpm:2", "--out", str(work / "b"),
                           "--chart", "both"],
        "sweep_2000": [*sweep, "--speeds", "500 rpm:12000 rpm:2000", "--out", str(work / "c")],
        # the documented backlash example (docs/sweep.md), as a user runs it (serial)
        "backlash_71": [GEAR_DYN, "sweep", str(BACKLASH), "--quiet", "--speeds",
                        "3000 rpm:10000 rpm:71", "--out", str(work / "d")],
    }
    wall(cases["sweep_2"])  # warm the file cache and the pint cache once
    out: dict[str, list[float]] = {k: [] for k in cases}
    for _ in range(repeats):
        for k, cmd in cases.items():
            out[k].append(wall(cmd))
    out["fixed"] = [a - b for a, b in zip(out["sweep_2"], out["startup"], strict=True)]
    out["fixed_charts"] = [a - b for a, b in zip(out["sweep_2_charts"], out["startup"],
                                                 strict=True)]
    out["cli_per_speed_ms"] = [1e3 * (a - b) / 1998 for a, b in
                               zip(out["sweep_2000"], out["sweep_2"], strict=True)]
    return out


def kernel_costs(repeats: int, n: int = 2000) -> dict[str, list[float]]:
    """Per-speed ms of the whole in-process sweep and of the kernel alone, interleaved."""
    scene = load_scene(SCENE)
    factory = SceneModels.of(scene)
    rtol = factory.plan.settings.rtol
    speeds = np.linspace(500, 12000, n) * RPM
    sweep_scene(scene, speeds[:50], si=True)

    def kernel() -> None:
        for s in speeds:
            periodic_steady_state(factory(float(s)), rtol=rtol)

    out: dict[str, list[float]] = {"sweep_ms": [], "kernel_ms": [], "ratio": []}
    for _ in range(repeats):
        t_s, _r = timed(lambda: sweep_scene(scene, speeds, si=True))
        t_k, _ = timed(kernel)
        out["sweep_ms"].append(1e3 * t_s / n)
        out["kernel_ms"].append(1e3 * t_k / n)
        out["ratio"].append(t_s / t_k)
    return out


def _cases() -> list[tuple[str, Any, np.ndarray, dict[str, Any]]]:
    """(name, scene, speeds, [solver] overrides)."""
    lin, bl = load_scene(SCENE), load_scene(BACKLASH)
    bl_speeds = np.linspace(3000, 10000, 71) * RPM
    return [("linear, 1 speed (a pool's fixed cost)", lin, np.array([3000.0]) * RPM, {}),
            ("linear, 300 speeds (docs/sweep.md example)", lin,
             np.linspace(500, 12000, 300) * RPM, {}),
            ("linear, 20000 speeds", lin, np.linspace(500, 12000, 20000) * RPM, {}),
            ("backlash, 71 speeds up and down (docs/sweep.md example)", bl, bl_speeds, {}),
            ("backlash, 71 speeds up and down, DOP853 pinned", bl, bl_speeds,
             {"method": "DOP853"})]


def _same(a: Any, b: Any) -> bool:
    """Every curve array of two sweeps equal bit for bit (NaN where NaN)."""
    return all(ca.status == cb.status and all(
        np.array_equal(getattr(ca, n), getattr(cb, n), equal_nan=True)
        for n in ("speed", "dynamic_factor", "rms_dte", "ptp_dte", "mean_dte", "spectral_radius",
                  "separation", "backside", "spectrum", "state", "orbit_periods"))
        for ca, cb in zip(a.curves, b.curves, strict=True))


def parallel_costs(repeats: int, dask: bool) -> tuple[dict[str, dict[str, list[float]]],
                                                      dict[str, float], bool]:
    """Seconds per case and variant (serial, workers 2, Dask), the Dask cluster's start-up,
    and whether every parallel result equalled the serial one."""
    info: dict[str, float] = {}
    variants: dict[str, dict[str, Any]] = {"serial": {}, "workers 2": {"workers": 2}}
    cluster = client = None
    if dask:
        from distributed import Client, LocalCluster

        t0 = time.perf_counter()
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                               dashboard_address=None)
        client = Client(cluster)
        variants["dask"] = {"executor": client.get_executor()}
        info["dask_start_s"] = time.perf_counter() - t0
        lin = _cases()[1]
        # each Dask worker imports gear_dyn and builds the scene once: not in the figures
        info["dask_cold_s"] = timed(lambda: sweep_scene(lin[1], lin[2], si=True,
                                                        **variants["dask"]))[0]
    out: dict[str, dict[str, list[float]]] = {}
    same = True
    try:
        for _ in range(repeats):
            for name, scene, speeds, over in _cases():
                row = out.setdefault(name, {})
                ref = None
                for v, kw in variants.items():
                    t, res = timed(lambda kw={**kw, **over}, sc=scene, sp=speeds:
                                   sweep_scene(sc, sp, si=True, **kw))
                    row.setdefault(v, []).append(t)
                    ref = res if ref is None else ref
                    same = same and _same(ref, res)
    finally:
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()
    return out, info, same


def report(args: argparse.Namespace, cli: dict[str, list[float]],
           kern: dict[str, list[float]], par: dict[str, dict[str, list[float]]],
           info: dict[str, float], same: bool) -> str:
    lines = [
        "# Speed sweep benchmark: fixed cost, per-speed cost, what workers buy", "",
        f"Command: `python benchmarks/bench_sweep.py --repeats {args.repeats}"
        f"{' --no-dask' if args.no_dask else ''} --record`. Median of "
        f"{args.repeats} interleaved repeats (min..max); ratios formed within one repeat.", "",
        f"Machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores shared "
        f"with other jobs (load average at the end: "
        f"{', '.join(f'{x:.1f}' for x in os.getloadavg())}), Python "
        f"{platform.python_version()}.", "",
        "## Fixed cost of `gear-dyn sweep` (whole processes, serial; helicopter_tail)", "",
        "| process | wall time (s) |", "|---|---|",
        f"| start-up: import the CLI, load the scene | {spread(cli['startup'])} |",
        f"| `gear-dyn sweep --speeds 500 rpm:12000 rpm:2` (response, waterfall, CSV, JSON) | "
        f"{spread(cli['sweep_2'])} |",
        f"| the same with `--chart both` (stability.png) | {spread(cli['sweep_2_charts'])} |",
        f"| the same with 2000 speeds | {spread(cli['sweep_2000'])} |",
        f"| `gear-dyn sweep helicopter_tail_backlash.toml --speeds 3000 rpm:10000 rpm:71` "
        f"| {spread(cli['backlash_71'])} |", "",
        f"Fixed cost beyond start-up: **{spread(cli['fixed'])} s** (with the stability charts "
        f"{spread(cli['fixed_charts'])} s); the command's cost per speed "
        f"{spread(cli['cli_per_speed_ms'])} ms.", "",
        "## Per-speed cost against the steady-state kernel (in-process, 2000 speeds)", "",
        f"Whole sweep (`sweep_scene`, serial): {spread(kern['sweep_ms'])} ms per speed; the "
        f"kernel alone (`periodic_steady_state` per speed): {spread(kern['kernel_ms'])} ms; "
        f"**sweep / kernel = {spread(kern['ratio'], '.2f')}**.", "",
        "## What workers buy (in-process `sweep_scene` calls, seconds per sweep)", "",
        "Serial is the default; `workers=2` (`gear-dyn sweep --workers 2`) starts a process pool "
        "of 2 (spawn) in each call, its start-up included; Dask is a LocalCluster of 2 "
        "processes started beforehand (`--dask ADDRESS`).", "",
    ]
    variants = list(next(iter(par.values())).keys())
    ratios = [v for v in variants if v != "serial"]
    lines += ["| case | " + " | ".join(variants) + " | "
              + " | ".join(f"{v} / serial" for v in ratios) + " |",
              "|---" * (1 + len(variants) + len(ratios)) + "|"]
    for case, row in par.items():
        rs = [spread([b / a for a, b in zip(row["serial"], row[v], strict=True)], ".2f")
              for v in ratios]
        lines.append(f"| {case} | " + " | ".join(spread(row[v]) for v in variants) + " | "
                     + " | ".join(rs) + " |")
    lines += ["", "Every parallel sweep gave the serial sweep's numbers bit for bit: "
              f"{'yes' if same else 'NO'}."]
    if "dask_start_s" in info:
        lines += ["", f"Dask LocalCluster start {info['dask_start_s']:.2f} s and its first "
                  f"(cold) sweep of 300 speeds {info['dask_cold_s']:.2f} s (each worker "
                  "imports gear_dyn and builds the scene once), not in the table."]
    return "\n".join(lines) + "\n"


def jumps_table(args: argparse.Namespace) -> str:
    """The cost of the jumps from the orbits on the backlash example sweep (``--jumps``)."""
    from gear_dyn.analysis.sweep import find_jumps
    from gear_dyn.analysis.sweep.orbit_jumps import candidates

    scene = load_scene(BACKLASH)
    factory = SceneModels.of(scene)
    rows = []
    for n in (71, 141):
        speeds = np.linspace(3000.0, 10000.0, n) * RPM
        whole, check = [], []
        for _ in range(args.repeats):
            t_all, res = timed(lambda sp=speeds: sweep_scene(scene, sp, si=True, workers=1))
            t_j, _ = timed(lambda r=res: [find_jumps(c, factory, r.settings.rtol)
                                          for c in r.curves])
            whole.append(t_all)
            check.append(t_j)
        scale = factory(float(speeds[0])).state_scale
        cand = sum(len(candidates(c, scale)) for c in res.curves)
        found = "; ".join(f"{c.direction}: " + ", ".join(f"{j.fold_speed / RPM:.1f}"
                                                          for j in c.jumps)
                          for c in res.curves)
        share = [c / w for c, w in zip(check, whole, strict=True)]
        rows.append(f"| {n} up and down | {spread(whole)} | {spread(check)} | "
                    f"{spread(share, '.2f')} | {cand} of {2 * (n - 1)} | {found} |")
    load = ", ".join(f"{x:.1f}" for x in os.getloadavg())
    return "\n".join([
        "# Sweep jumps from the orbits: what the check costs",
        "",
        f"Command: `python benchmarks/bench_sweep.py --jumps --repeats {args.repeats}"
        f"{' --record' if args.record else ''}`. Median of {args.repeats} repeats (min..max).",
        "",
        f"Machine: {platform.machine()}, 2 cores shared with other jobs (load average at the "
        f"end: {load}), Python {platform.python_version()}.",
        "",
        "helicopter_tail_backlash, 3000..10000 rpm. The sweep (`sweep_scene`, serial) includes "
        "the jump check; the check alone is `find_jumps` run again on the sweep's curves. "
        "Only candidate pairs are continued (docs/sweep.md, How jumps are found).",
        "",
        "| speeds | sweep with jumps (s) | jump check alone (s) | check / sweep "
        "| pairs continued | folds of the jumps (rpm) |",
        "|---|---|---|---|---|---|",
        *rows, ""])


def _cpu_of_command(cmd: list[str], tree: Path = ROOT) -> float:
    """CPU time (user + system) of ``python -m gear_dyn.cli CMD...`` in a child process, in s,
    with gear_dyn imported from the source tree ``tree``."""
    return run_child([sys.executable, "-m", "gear_dyn.cli", *cmd], tree,
                     tree_env(tree, ENV or None)).cpu


def linear_table(args: argparse.Namespace) -> str:
    """Linear sweeps: whole commands, and the jump continuation they skip (``--linear``)."""
    from gear_dyn.analysis.sweep.orbit_jumps import candidates, check_pair

    span = ("500 rpm", "12000 rpm")
    with tempfile.TemporaryDirectory() as tmp:
        pe = Path(tmp) / "helicopter_tail_pe.toml"
        text = SCENE.read_text()
        assert 'method = "iso6336"' in text
        pe.write_text(text.replace('method = "iso6336"', 'method = "potential_energy"', 1))
        cases = [("potential_energy", pe, 40), ("potential_energy", pe, 160),
                 ("iso6336", SCENE, 50), ("iso6336", SCENE, 500)]
        trees = [ROOT] + ([args.before] if args.before else [])
        cpu: dict[tuple[int, int], list[float]] = {}
        for _ in range(args.repeats):  # interleaved
            for i, (_name, path, n) in enumerate(cases):
                for k, tree in enumerate(trees):
                    cpu.setdefault((i, k), []).append(_cpu_of_command(
                        ["sweep", str(path), "--speeds", f"{span[0]}:{span[1]}:{n}",
                         "--out", str(Path(tmp) / f"out{i}"), "--quiet"], tree))
        rows = []
        for i, (name, _p, n) in enumerate(cases):
            before = ""
            if args.before:
                ratio = [a / b for a, b in zip(cpu[(i, 1)], cpu[(i, 0)], strict=True)]
                before = f" {spread(cpu[(i, 1)])} | {spread(ratio, '.1f', 'x')} |"
            rows.append(f"| {name} | {n} | {spread(cpu[(i, 0)])} | "
                        f"{1e3 * statistics.median(cpu[(i, 0)]) / n:.1f} |{before}")
        skipped = []
        for name, path, n in (cases[0], cases[2]):  # once each: the skipped work is slow
            scene = load_scene(path)
            factory = SceneModels.of(scene)
            speeds = np.linspace(500.0, 12000.0, n) * RPM
            res = sweep_scene(scene, speeds, si=True, workers=1)
            c = res.curves[0]
            pairs = candidates(c, factory(float(speeds[0])).state_scale)
            t0 = time.process_time()
            found = [check_pair(c, i, factory, res.settings.rtol) for i in pairs]
            dt = time.process_time() - t0
            n_jumps = sum(j is not None for j in found)
            skipped.append(f"| {name} | {n} | {len(pairs)} of {n - 1} | {dt:.2f} | "
                           f"{n_jumps} |")
    load = ", ".join(f"{x:.1f}" for x in os.getloadavg())
    return "\n".join([
        "# Linear sweeps: only the work they need",
        "",
        f"Command: `python benchmarks/bench_sweep.py --linear --repeats {args.repeats}"
        f"{' --before DIR' if args.before else ''}"
        f"{' --record' if args.record else ''}`. CPU time (user + system) of whole processes, "
        f"median of {args.repeats} interleaved repeats (min..max); one BLAS thread.",
        "",
        f"Machine: {platform.machine()}, 2 cores shared with other jobs (load average at the "
        f"end: {load}), Python {platform.python_version()}.",
        "",
        f"`gear-dyn sweep SCENE --speeds \"{span[0]}:{span[1]}:N\" --quiet` of helicopter_tail "
        "(linear: no backlash) with its `iso6336` stiffness and with `[stiffness] method = "
        "\"potential_energy\"`. A linear model has one periodic response per speed where it is "
        "stable, so the sweep continues no orbit to look for jumps (docs/sweep.md, How jumps "
        "are found).",
        "",
        *(["`before`: the same commands, interleaved, on the source tree before linear "
           "sweeps skipped the jump continuation (`--before DIR`)", ""] if args.before else []),
        "| stiffness | speeds | command CPU (s) | per speed (ms) |"
        + (" before (s) | before / now |" if args.before else ""),
        "|---|---|---|---|" + ("---|---|" if args.before else ""),
        *rows,
        "",
        "The continuation the jump check ran on these sweeps before linear models skipped it "
        "(`check_pair` on the candidate pairs of the up sweep, in-process CPU, one run): "
        "what the skip saves; a linear model has no jump, so every jump it reported was false.",
        "",
        "| stiffness | speeds | pairs continued | CPU (s) | jumps reported |",
        "|---|---|---|---|---|",
        *skipped, ""])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--out", type=Path, default=ROOT / "benchmarks" / "out",
                    help="output folder (default benchmarks/out/, git-ignored)")
    ap.add_argument("--record", action="store_true",
                    help="write into benchmarks/results/ (the recorded figures)")
    ap.add_argument("--no-dask", action="store_true", help="skip the Dask cases")
    ap.add_argument("--methods", action="store_true",
                    help="instead: the slow steady-vs-transient comparison (sweep_methods.md)")
    ap.add_argument("--speeds", type=int, default=500, help="speeds of --methods")
    ap.add_argument("--jumps", action="store_true",
                    help="instead: the cost of the jumps from the orbits (sweep_jumps.md)")
    ap.add_argument("--linear", action="store_true",
                    help="instead: the cost of linear sweeps, whole commands (sweep_linear.md)")
    ap.add_argument("--before", type=Path, default=None, metavar="DIR",
                    help="with --linear: also time the commands on the gear_dyn source tree "
                    "DIR (e.g. a checkout of an older commit), interleaved")
    args = ap.parse_args()
    ENV.update(as_installed(ROOT / "gear_dyn"))
    out_dir = ROOT / "benchmarks" / "results" if args.record else args.out
    out_dir.mkdir(parents=True, exist_ok=True)
    if args.linear:
        text = linear_table(args)
        print(text)
        (out_dir / "sweep_linear.md").write_text(text)
        print(f"wrote {out_dir / 'sweep_linear.md'}")
        return
    if args.jumps:
        text = jumps_table(args)
        print(text)
        (out_dir / "sweep_jumps.md").write_text(text)
        print(f"wrote {out_dir / 'sweep_jumps.md'}")
        return
    if args.methods:
        text = methods_table(args)
        print(text)
        (out_dir / "sweep_methods.md").write_text(text)
        print(f"wrote {out_dir / 'sweep_methods.md'}")
        return
    with tempfile.TemporaryDirectory() as tmp:
        cli = cli_costs(args.repeats, Path(tmp))
    print(f"fixed cost beyond start-up {spread(cli['fixed'])} s", flush=True)
    kern = kernel_costs(args.repeats)
    print(f"sweep / kernel per speed {spread(kern['ratio'], '.2f')}", flush=True)
    par, info, same = parallel_costs(args.repeats, not args.no_dask)
    text = report(args, cli, kern, par, info, same)
    print(text)
    (out_dir / "sweep.md").write_text(text)
    print(f"wrote {out_dir / 'sweep.md'}")


if __name__ == "__main__":
    main()
