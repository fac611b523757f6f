"""CPU time of ``gear-dyn response`` and ``run_scene``, before and after a change, and the floor.

Run:  python benchmarks/bench_startup.py [--before REF] [--repeats 5] [--out DIR] [--record]

Three figures, each in CPU time (user + system, one BLAS thread), measured in fresh processes
from two source trees in turn, before, after, before, after, ...: the git ref ``--before``
(default: where HEAD left main; extracted with ``git archive``, the compiled kernel copied
from this checkout) and this checkout.

- ``gear-dyn response helicopter_tail_backlash --speeds "3000 rpm:9500 rpm"``, the whole
  process (target: at most 0.5 s);
- ``run_scene(helicopter_tail)`` (linear, the ``exact`` route, error estimate and quasi-static
  reference included), per call: a child warms up with 5 calls, then times 5 batches of 20 and
  reports the fastest batch's mean (target: at most 5 ms);
- for this checkout, where the response command's time goes: a child that imports what it
  imports and runs each stage with ``time.process_time`` between them, and the floor, a
  process that only imports numpy and matplotlib's Figure and Agg canvas and saves two empty
  PNGs, the least any command that draws costs; apart, what pint (and dask) would add.

With ``--instructions`` (needs valgrind) also the instructions per ``run_scene`` call from
callgrind, ``(25 calls - 5 calls) / 20`` in one child per tree: a count that, unlike CPU time,
does not grow with the load of a shared machine.

Writes ``startup.md`` into ``--out`` (default ``benchmarks/out/``, git-ignored); ``--record``
writes it into ``benchmarks/results/``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from _timing import as_installed, run_child, source_tree, spread  # noqa: E402  (benchmarks/ is on sys.path)

ROOT = Path(__file__).resolve().parents[1]
ONE_THREAD = {var: "1" for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")}
RESPONSE = ["response", "helicopter_tail_backlash", "--speeds", "3000 rpm:9500 rpm"]

#: a child timing run_scene(helicopter_tail): ms per call of the fastest of 5 batches of 20
RUN_SCENE = """
import json, time
from gear_dyn import load_scene, run_scene
scene = load_scene("helicopter_tail")
for _ in range(5):
    run_scene(scene)
best = float("inf")
for _ in range(5):
    t0 = time.process_time()
    for _ in range(20):
        run_scene(scene)
    best = min(best, (time.process_time() - t0) / 20)
print(json.dumps(best * 1e3))
"""

#: a child making N run_scene(helicopter_tail) calls (for callgrind)
RUN_N = """
import sys
from gear_dyn import load_scene, run_scene
scene = load_scene("helicopter_tail")
for _ in range(int(sys.argv[1])):
    run_scene(scene)
"""

#: a child running the response command's stages one by one (CPU s of each)
STAGES = """
import json, sys, time
out = sys.argv[1]
T = time.process_time
marks = [("start", T())]
import numpy
marks.append(("import numpy", T()))
import matplotlib.figure, matplotlib.backends.backend_agg
marks.append(("import matplotlib Figure and Agg", T()))
from gear_dyn.analysis.continuation import ContinuationSettings, branch_samples, continue_orbits
from gear_dyn.cli.response import _speeds
from gear_dyn.io import save_figure, write_json, write_rows
from gear_dyn.plots.bifurcation import plot_branch_samples
from gear_dyn.plots.continuation import plot_branch
from gear_dyn.scene import load_scene
from gear_dyn.scene.sweep import SceneModels
marks.append(("import gear_dyn's modules", T()))
scene = load_scene("helicopter_tail_backlash")
lo, hi = _speeds("3000 rpm:9500 rpm")
family = SceneModels.of(scene)
marks.append(("load the scene (its units read without pint)"
              if "pint" not in sys.modules else "load the scene", T()))
settings = ContinuationSettings()
branch = continue_orbits(family, lo, hi, settings=settings, doublings=1)
marks.append(("continue the branch", T()))
strobe = branch_samples(branch, family, settings.rtol)
f1 = plot_branch(branch)
f2 = plot_branch_samples(strobe, title=scene.name)
marks.append(("draw the two figures (layout, labels)", T()))
save_figure(f1, out + "/response.png", dpi=120)
save_figure(f2, out + "/bifurcation.png", dpi=120)
write_rows(out + "/branch.csv", branch.rows())
write_json(out + "/branch.json", branch.to_dict())
marks.append(("render and write the PNGs, CSV, JSON", T()))
print(json.dumps([(a, t1 - t0) for (_, t0), (a, t1) in zip(marks, marks[1:])]))
"""

#: pint imported and its registry built (what reading a unit outside gear_dyn's table costs)
PINT = "import pint; pint.UnitRegistry(cache_folder=':auto:')"

#: the floor: the imports and an empty figure saved twice
FLOOR = """
import sys
import numpy
from matplotlib.figure import Figure
import matplotlib.backends.backend_agg
for name in ("a", "b"):
    fig = Figure(figsize=(8, 4))
    fig.subplots().plot([0, 1], [0, 1])
    fig.savefig(sys.argv[1] + "/" + name + ".png", dpi=120)
"""


def cpu(cmd: list[str], cwd: Path, env: dict[str, str]) -> tuple[float, str]:
    """CPU s (user + system) of a child process, and its stdout."""
    done = run_child(cmd, cwd, env)
    return done.cpu, done.stdout


def instructions(tree: Path, env: dict[str, str], calls: int) -> float:
    """Instructions callgrind counts in a child making ``calls`` run_scene calls."""
    done = subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null",
                           sys.executable, "-c", RUN_N, str(calls)], cwd=tree, env=env,
                          check=True, capture_output=True, text=True)
    return float(done.stderr.split("Collected :")[1].split()[0])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", default="",
                    help="git ref of the 'before' tree (default: where HEAD left main)")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--out", type=Path, default=ROOT / "benchmarks" / "out")
    ap.add_argument("--record", action="store_true", help="write into benchmarks/results/")
    ap.add_argument("--instructions", action="store_true",
                    help="also count run_scene's instructions with callgrind (valgrind)")
    args = ap.parse_args()
    out_dir = ROOT / "benchmarks" / "results" if args.record else args.out
    out_dir.mkdir(parents=True, exist_ok=True)
    before = args.before or subprocess.run(["git", "merge-base", "HEAD", "main"], cwd=ROOT,
                                           check=True, capture_output=True,
                                           text=True).stdout.strip()
    py = sys.executable
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        (work / "before").mkdir()
        (work / "o").mkdir()
        trees = {"before": source_tree(before, work / "before", kernel="copy"), "after": ROOT}
        envs = {k: {**as_installed(t / "gear_dyn"), **ONE_THREAD, "PYTHONPATH": str(t)}
                for k, t in trees.items()}
        response: dict[str, list[float]] = {k: [] for k in trees}
        per_call: dict[str, list[float]] = {k: [] for k in trees}
        for key, tree in trees.items():  # warm-up: bytecode, pint's cache, file caches
            cpu([py, "-m", "gear_dyn.cli", *RESPONSE, "--out", str(work / "r")], tree,
                envs[key])
        for _ in range(args.repeats):
            for key, tree in trees.items():
                response[key].append(cpu([py, "-m", "gear_dyn.cli", *RESPONSE, "--out",
                                          str(work / "r")], tree, envs[key])[0])
                per_call[key].append(json.loads(cpu([py, "-c", RUN_SCENE], tree,
                                                    envs[key])[1]))
            print({k: (round(response[k][-1], 2), round(per_call[k][-1], 2)) for k in trees},
                  flush=True)
        stages: dict[str, list[float]] = {}
        floor: list[float] = []
        for _ in range(args.repeats):
            _t, text = cpu([py, "-c", STAGES, str(work / "o")], ROOT, envs["after"])
            for name, dt in json.loads(text):
                stages.setdefault(name, []).append(dt)
            floor.append(cpu([py, "-c", FLOOR, str(work / "o")], ROOT, envs["after"])[0])
        dask = [cpu([py, "-c", "import dask"], ROOT, envs["after"])[0]
                for _ in range(args.repeats)]
        pint = [cpu([py, "-c", PINT], ROOT, envs["after"])[0] for _ in range(args.repeats)]
        bare = [cpu([py, "-c", "pass"], ROOT, envs["after"])[0] for _ in range(args.repeats)]
        counted = {k: (instructions(t, envs[k], 25) - instructions(t, envs[k], 5)) / 20
                   for k, t in trees.items()} if args.instructions else {}

    def ratio(key: str) -> str:
        pairs = zip(response["before"], response["after"], strict=True) if key == "r" else zip(
            per_call["before"], per_call["after"], strict=True)
        return spread([a / b for b, a in pairs], unit="x")

    med_r = statistics.median(response["after"])
    med_c = statistics.median(per_call["after"])
    lines = [
        "# Start-up and small runs: CPU time before and after", "",
        f"`python benchmarks/bench_startup.py --repeats {args.repeats}"
        f"{f' --before {args.before}' if args.before else ''}"
        f"{' --record' if args.record else ''}{' --instructions' if args.instructions else ''}`"
        " (before: "
        f"{args.before or 'the commit where this branch left main'}; after: this checkout) on "
        f"{platform.machine()}, Python {platform.python_version()}, {os.cpu_count()} cores, "
        f"one BLAS thread; each figure measured {args.repeats} times from each tree in turn "
        "after a warm-up. Median (min..max).", "",
        "| what | before | after | after / before | target |",
        "| --- | --- | --- | --- | --- |",
        f"| `gear-dyn response helicopter_tail_backlash --speeds \"3000 rpm:9500 rpm\"`, CPU s "
        f"| {spread(response['before'])} | {spread(response['after'])} | {ratio('r')} | "
        f"<= 0.5 s: {'met' if med_r <= 0.5 else 'not met'} |",
        f"| `run_scene(helicopter_tail)`, CPU ms per call | {spread(per_call['before'])} | "
        f"{spread(per_call['after'])} | {ratio('c')} | "
        f"<= 5 ms: {'met' if med_c <= 5.0 else 'not met'} |",
        *([f"| `run_scene(helicopter_tail)`, million instructions per call (callgrind) | "
           f"{counted['before'] / 1e6:.4g} | {counted['after'] / 1e6:.4g} | "
           f"{counted['after'] / counted['before']:.3g}x | |"] if counted else []),
        "", "Where the response command's CPU time goes (this checkout, its stages in one "
        "process, CPU s):", "", "| stage | CPU s |", "| --- | --- |",
    ]
    lines += [f"| {name} | {spread(v)} |" for name, v in stages.items()]
    lines += [f"| total | {spread([sum(x) for x in zip(*stages.values(), strict=True)])} |",
              "", "The floor of a command that draws two PNGs (numpy, matplotlib's Figure and "
              f"Agg canvas, two empty figures saved): {spread(floor)} CPU s, of it the bare "
              f"interpreter {spread(bare)} s. Reading a unit outside gear_dyn's table of the "
              "plainest spellings imports pint and builds its registry: a process doing only "
              f"that costs {spread(pint)} CPU s, of it `import dask` alone (pint imports it "
              f"when it is installed, as with gear_dyn's dask extra) {spread(dask)} s; the "
              "response command's units are all in the table."]
    text = "\n".join(lines) + "\n"
    (out_dir / "startup.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
