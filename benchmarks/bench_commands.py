"""CPU time of the long study commands, before and after a change, side by side in one run.

Run:  python benchmarks/bench_commands.py [--before REF] [--repeats 2] [--out DIR] [--record]

Each command below is run as a whole process (``python -m gear_dyn.cli ...``, one BLAS thread,
bytecode compiled as after ``pip install``) from two source trees in turn, before, after,
before, after, ...: the git ref ``--before`` (default: where HEAD left main; extracted with
``git archive`` into a temporary folder) and this checkout. The figure is CPU time (user +
system of the process and its children, from the operating system's accounting): on a machine
shared with other work the wall time grows with the load, the CPU time much less.

Targets (whole commands, CPU):

- ``bifurcation backlash_constant_stiffness --speeds "12000 rpm:12500 rpm:61" --classify``:
  at most 10 s;
- ``compare`` of helicopter_tail, helicopter_tail_relief and helicopter_tail_backlash over 131
  speeds: at most 5 s;
- ``response helicopter_tail_backlash --speeds "3000 rpm:9500 rpm"``: at most 0.5 s;
- ``sweep`` of every packaged linear single-DOF scene: per speed at most 5x the ``iso6336``
  scene's (helicopter_tail), and a coarse grid never costing more than a fine one. The cost per
  speed is the difference of a 640-speed and a 40-speed sweep over 600 (a whole sweep's fixed
  cost, start-up, scene, quasi-static run and figures, is 1-2 s: a few hundred speeds are
  needed for the per-speed part to stand out of the run-to-run spread).

Writes ``commands.md`` (``--name``) into ``--out`` (default ``benchmarks/out/``, git-ignored);
``--record`` writes it into ``benchmarks/results/``. The in-process sweep tables (the cost per
speed of ``sweep_scene``, and of the speed blocks alone, each tree in a child process) are made
only when a sweep command is among those run (``--only``).
"""

from __future__ import annotations

import argparse
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _timing import as_installed, run_child, source_tree, spread  # noqa: E402  (benchmarks/ is on sys.path)

ROOT = Path(__file__).resolve().parents[1]
ONE_THREAD = {var: "1" for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")}
COMPARED = ("helicopter_tail", "helicopter_tail_relief", "helicopter_tail_backlash")
#: the packaged linear single-DOF scenes (no backlash); the first is the iso6336 reference
LINEAR = ("helicopter_tail", "helicopter_tail_relief", "rail_helical_ltca")
SWEEP_SPEEDS = "2000 rpm:6000 rpm:{n}"
SWEEP_GRIDS = (40, 640)
#: name, arguments after ``gear-dyn``, target CPU s (None: judged per speed)
COMMANDS: tuple[tuple[str, list[str], float | None], ...] = (
    ("bifurcation 61 speeds --classify",
     ["bifurcation", "backlash_constant_stiffness", "--speeds", "12000 rpm:12500 rpm:61",
      "--classify"], 10.0),
    ("compare 3 scenes x 131 speeds",
     ["compare", *COMPARED, "--speeds", "2000 rpm:9500 rpm:131", "--quiet"], 5.0),
    ("response helicopter_tail_backlash",
     ["response", "helicopter_tail_backlash", "--speeds", "3000 rpm:9500 rpm"], 0.5),
    *((f"sweep {s} {n} speeds",
       ["sweep", s, "--speeds", SWEEP_SPEEDS.format(n=n), "--no-progress"], None)
      for s in LINEAR for n in SWEEP_GRIDS),
)


def cpu_of(tree: Path, args: list[str], out: Path, env: dict[str, str]) -> float:
    """CPU s (user + system) of ``python -m gear_dyn.cli ARGS --out OUT`` run in ``tree``."""
    return run_child([sys.executable, "-m", "gear_dyn.cli", *args, "--out", str(out)], tree,
                     env).cpu


#: what a command that reads units and writes a figure imports before any work
FLOOR = "import numpy, scipy.integrate, pint, matplotlib.figure, matplotlib.backends.backend_agg"


def import_cpu(env: dict[str, str]) -> float:
    """CPU s of a process that only imports :data:`FLOOR`."""
    return run_child([sys.executable, "-c", FLOOR], env=env).cpu


def per_speed_cpu(name: str, tree: Path = ROOT) -> float:
    """CPU s per speed of ``sweep_scene`` of the packaged scene ``name``, in this process
    (with the gear_dyn of ``tree``): (361 speeds - 37 speeds) / 324 over 1000-6000 rpm, so the
    fixed cost (model, quasi-static run) drops out, as ``bench_sweep_stiffness.py`` measures
    it."""
    if str(tree) not in sys.path:  # that tree's gear_dyn, not another installed one
        sys.path.insert(0, str(tree))
    import numpy as np

    from gear_dyn.scene import load_scene
    from gear_dyn.scene.sweep import sweep_scene

    scene = load_scene(tree / "gear_dyn" / "scenes" / f"{name}.toml")
    rpm = 2 * np.pi / 60

    def cpu(n: int) -> float:
        t0 = time.process_time()
        sweep_scene(scene, np.linspace(1000, 6000, n) * rpm, si=True)
        return time.process_time() - t0
    cpu(2)  # imports, caches
    return (cpu(361) - cpu(37)) / 324


def block_cpu(name: str, tree: Path = ROOT) -> float:
    """CPU s per speed of the linear speed blocks alone of the packaged scene ``name`` (with
    the gear_dyn of ``tree``): ``linear_block`` over 640 speeds, 1000-6000 rpm, in the sweep's
    blocks of 32, the models built beforehand; the part of a linear sweep that grows with the
    number of speeds, without the fixed costs whose spread hides it in :func:`per_speed_cpu`."""
    if str(tree) not in sys.path:
        sys.path.insert(0, str(tree))
    import numpy as np

    from gear_dyn.analysis.sweep.batch import linear_block
    from gear_dyn.analysis.sweep.types import SweepOptions
    from gear_dyn.scene import load_scene
    from gear_dyn.scene.sweep import SceneModels

    factory = SceneModels.of(load_scene(tree / "gear_dyn" / "scenes" / f"{name}.toml"))
    speeds = np.linspace(1000, 6000, 640) * 2 * np.pi / 60
    models = [factory(float(s)) for s in speeds]
    settings, opts = factory.plan.settings, SweepOptions()
    linear_block(models[:32], speeds[:32], settings, opts)  # imports, caches
    t0 = time.process_time()
    for i in range(0, speeds.size, 32):
        if linear_block(models[i:i + 32], speeds[i:i + 32], settings, opts) is None:
            raise RuntimeError(f"{name}: not a linear block")
    return (time.process_time() - t0) / speeds.size


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", default="",
                    help="git ref of the 'before' tree (default: where HEAD left main)")
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--out", type=Path, default=ROOT / "benchmarks" / "out")
    ap.add_argument("--record", action="store_true", help="write into benchmarks/results/")
    ap.add_argument("--only", default="", help="run only commands whose name contains this")
    ap.add_argument("--name", default="commands",
                    help="file name of the table, without .md (default: commands)")
    ap.add_argument("--per-speed", default="", metavar="SCENE",
                    help="instead: print the in-process CPU s per speed of sweeping SCENE with "
                         "the gear_dyn of --tree (what the in-process table runs in a child)")
    ap.add_argument("--blocks", action="store_true",
                    help="with --per-speed: the speed blocks alone (block_cpu)")
    ap.add_argument("--tree", type=Path, default=ROOT, help="with --per-speed")
    args = ap.parse_args()
    if args.per_speed:
        measure = block_cpu if args.blocks else per_speed_cpu
        print(measure(args.per_speed, args.tree.resolve()))
        return
    out_dir = ROOT / "benchmarks" / "results" if args.record else args.out
    out_dir.mkdir(parents=True, exist_ok=True)
    commands = [c for c in COMMANDS if args.only in c[0]]
    before = args.before or subprocess.run(["git", "merge-base", "HEAD", "main"], cwd=ROOT,
                                           check=True, capture_output=True,
                                           text=True).stdout.strip()
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        (work / "before").mkdir()
        trees = {"before": source_tree(before, work / "before", kernel="build"), "after": ROOT}
        envs = {k: {**as_installed(t / "gear_dyn"), **ONE_THREAD} for k, t in trees.items()}
        cpu: dict[str, dict[str, list[float]]] = {c[0]: {"before": [], "after": []}
                                                  for c in commands}
        for _name, cmd, _target in commands:  # warm-up: bytecode, pint's cache, file caches
            for key, tree in trees.items():
                cpu_of(tree, cmd, work / "o", envs[key])
        for _ in range(args.repeats):
            for name, cmd, _target in commands:
                for key, tree in trees.items():
                    cpu[name][key].append(cpu_of(tree, cmd, work / "o", envs[key]))
                print(name, {k: round(v[-1], 2) for k, v in cpu[name].items()}, flush=True)
        floor = [import_cpu(envs["after"]) for _ in range(args.repeats)]
        # the in-process cost per speed, each tree in a child process, in turn
        swept = [s for s in LINEAR if any(c[0].startswith(f"sweep {s} ") for c in commands)]
        inproc: dict[str, dict[str, list[float]]] = {s: {"before": [], "after": []}
                                                     for s in swept}
        blocks: dict[str, dict[str, list[float]]] = {s: {"before": [], "after": []}
                                                     for s in swept}
        for _ in range(args.repeats if inproc else 0):
            for s in swept:
                for table, extra in ((inproc, []), (blocks, ["--blocks"])):
                    for key, tree in trees.items():
                        out = subprocess.run([sys.executable, __file__, "--per-speed", s,
                                              "--tree", str(tree), *extra], cwd=tree,
                                             env=envs[key], check=True, capture_output=True,
                                             text=True).stdout
                        table[s][key].append(float(out.split()[-1]))
    med = {n: {k: statistics.median(v) for k, v in d.items()} for n, d in cpu.items()}
    lines = ["# Long study commands: CPU time before and after", "",
             f"`python benchmarks/bench_commands.py --repeats {args.repeats}"
             f"{f' --before {args.before}' if args.before else ''}"
             f"{f' --only {args.only!r}' if args.only else ''}"
             f"{f' --name {args.name}' if args.name != 'commands' else ''}"
             f"{' --record' if args.record else ''}` (before: "
             f"{args.before or 'the commit where this branch left main'}; after: this "
             f"checkout) on {platform.machine()}, "
             f"Python {platform.python_version()}, {len(commands)} commands, each run "
             f"{args.repeats} times from each tree in turn after a warm-up, one BLAS thread. "
             "CPU s, median (min..max).", "",
             "| command | before | after | after / before | target |",
             "| --- | --- | --- | --- | --- |"]
    for name, _cmd, target in commands:
        b, a = cpu[name]["before"], cpu[name]["after"]
        ratios = [y / x for x, y in zip(b, a, strict=True)]
        verdict = ("" if target is None else
                   f"<= {target:g} s: {'met' if med[name]['after'] <= target else 'not met'}")
        lines.append(f"| {name} | {spread(b)} | {spread(a)} | {spread(ratios, unit='x')} | "
                     f"{verdict} |")
    lines += ["", f"Floor of any command that parses units and draws: `python -c \"{FLOOR}\"` "
              f"{spread(floor)} CPU s."]
    per_speed = {}
    for s in LINEAR:
        fine, coarse = (f"sweep {s} {n} speeds" for n in reversed(SWEEP_GRIDS))
        if fine in med and coarse in med:
            per_speed[s] = {k: (med[fine][k] - med[coarse][k]) / (SWEEP_GRIDS[1] - SWEEP_GRIDS[0])
                            for k in ("before", "after")}
    if per_speed:
        ref = per_speed.get(LINEAR[0])
        lines += ["", "Sweeps of the linear scenes, cost per speed (CPU ms, from the medians: "
                  f"({SWEEP_GRIDS[1]}-speed - {SWEEP_GRIDS[0]}-speed) / "
                  f"{SWEEP_GRIDS[1] - SWEEP_GRIDS[0]}) and against the iso6336 scene "
                  f"({LINEAR[0]}); target <= 5x.", "",
                  "| scene | before ms/speed | after ms/speed | before / iso6336 | "
                  "after / iso6336 |", "| --- | --- | --- | --- | --- |"]

        def rel(d: dict[str, float], key: str) -> str:
            return (f"{d[key] / ref[key]:.2g}x" if ref and ref[key] > 0 and d[key] > 0
                    else "within the spread")

        for s, d in per_speed.items():
            lines.append(f"| {s} | {1e3 * d['before']:.3g} | {1e3 * d['after']:.3g} | "
                         f"{rel(d, 'before')} | {rel(d, 'after')} |")
    titles = ((inproc, "The same, in one process (`sweep_scene`, 361 - 37 speeds over "
                       "1000-6000 rpm, CPU, each tree in a child process in turn; the ratios "
                       "within each repeat):"),
              (blocks, "The speed blocks alone (`linear_block` over 640 speeds, 1000-6000 rpm, "
                       "in the sweep's blocks of 32, models built beforehand: the part of a "
                       "linear sweep that grows with the speeds, free of the fixed costs whose "
                       "spread the differences above carry; CPU, each tree in a child process "
                       "in turn):"))
    for table, title in titles if LINEAR[0] in inproc else ():
        def ratios(s: str, key: str, t: dict[str, dict[str, list[float]]] = table
                   ) -> list[float]:
            return [a / b for a, b in zip(t[s][key], t[LINEAR[0]][key], strict=True)]

        lines += ["", title, "",
                  "| scene | before ms/speed | after ms/speed | after / before | "
                  "before / iso6336 | after / iso6336 (target <= 5x) |",
                  "| --- | --- | --- | --- | --- | --- |"]
        for s, d in table.items():
            gain = [a / b for a, b in zip(d["after"], d["before"], strict=True)]
            lines.append(f"| {s} | {spread([1e3 * x for x in d['before']])} | "
                         f"{spread([1e3 * x for x in d['after']])} | {spread(gain, '.2g', 'x')} | "
                         f"{spread(ratios(s, 'before'), '.2g', 'x')} | "
                         f"{spread(ratios(s, 'after'), '.2g', 'x')} |")
    text = "\n".join(lines) + "\n"
    (out_dir / f"{args.name}.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
