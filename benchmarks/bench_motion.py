"""Motion classification and bifurcation diagrams: cost per mesh period, by route.

Run:  python benchmarks/bench_motion.py [--repeats 5] [--out DIR] [--record]

On the parametric backlash scene of docs/motion.md (the packaged backlash pair with rectangular
stiffness 0.5e9 / 1.5e9 N/m, damping ratio 0.02) at f_m / f_n = 2.0 (chaos: contact changes in
every period), from a state on the attractor, interleaved repeats:

1. stroboscopic samples, 200 mesh periods: the exact piecewise flow (``exact_contact``) against
   event-located DOP853 (rtol 1e-10; what a transmission error or smooth stiffness gets);
2. the largest Lyapunov exponent, 100 mesh periods: the exact sensitivity (closed form and
   saltation matrices) against the event-located variational equations (DOP853, rtol 1e-8);
3. a bifurcation diagram of 24 speeds (f_m / f_n = 1.95..2.3, up and down, 100 settling
   periods and 32 samples per speed) serial and on a pool of two processes (``workers=2``,
   its start-up included): the up and down chains side by side.

Medians (min..max) per mesh period in ms; ratios formed within one repeat. Writes ``motion.md``
into ``--out`` (default ``benchmarks/out/``, git-ignored); ``--record`` into
``benchmarks/results/``.
"""

from __future__ import annotations

import math
import os
import platform
import tomllib

import numpy as np
from _timing import bench_args, output_dir, spread, timed  # noqa: E402  (benchmarks/ is on sys.path)

from gear_dyn.analysis.motion import (
    DiagramOptions,
    bifurcation_diagram,
    flow_periods,
    largest_lyapunov,
    stroboscopic,
)
from gear_dyn.analysis.stability import flow_on_grid
from gear_dyn.scene import build_model, parse_scene
from gear_dyn.scene.packaged import scene_path
from gear_dyn.scene.sweep import SceneModels


def _scene():
    data = tomllib.loads(scene_path("helicopter_tail_backlash").read_text())
    data["stiffness"] = {"method": "rectangular", "single": "0.5e9 N/m", "double": "1.5e9 N/m"}
    data["damping"] = {"ratio": 0.02}
    data["scene"]["name"] = "parametric_backlash"
    return parse_scene(data, "parametric_backlash.toml")


def main() -> None:
    args = bench_args(__doc__.splitlines()[0], None, repeats=5)
    out = output_dir(args)
    scene = _scene()
    factory = SceneModels.of(scene)
    fn = build_model(scene).natural_frequency
    speed = 2.0 * fn * 2 * math.pi / 23
    model = factory(speed)
    y0 = stroboscopic(model, model.initial_state(), 300, 1)[-1]
    t = np.arange(201) / model.mesh_frequency
    speeds = np.linspace(1.95, 2.3, 24) * fn * 2 * math.pi / 23
    opts = DiagramOptions(settle=100, samples=32)
    rows: dict[str, list[float]] = {k: [] for k in (
        "exact", "dop", "dop/exact", "lyap_exact", "lyap_var", "var/exact", "serial", "pool",
        "pool/serial")}
    same = True
    for _ in range(args.repeats):
        te, _ = timed(lambda: flow_periods(model, y0, 200))
        td, _ = timed(lambda: flow_on_grid(model, y0, t, 1e-10))
        le, _ = timed(lambda: largest_lyapunov(model, y0, 100, 10, align=0, route="exact"))
        lv, _ = timed(lambda: largest_lyapunov(model, y0, 100, 10, align=0, rtol=1e-8,
                                               route="variational"))
        ts, serial = timed(lambda: bifurcation_diagram(factory, speeds, options=opts))
        tp, pool = timed(lambda: bifurcation_diagram(factory, speeds, options=opts, workers=2))
        same = same and all(np.array_equal(a.samples, b.samples, equal_nan=True)
                            for a, b in zip(serial.curves, pool.curves, strict=True))
        for key, val in (("exact", te / 200e-3), ("dop", td / 200e-3), ("dop/exact", td / te),
                         ("lyap_exact", le / 100e-3), ("lyap_var", lv / 100e-3),
                         ("var/exact", lv / le), ("serial", ts), ("pool", tp),
                         ("pool/serial", tp / ts)):
            rows[key].append(val)
    load = ", ".join(f"{v:.1f}" for v in os.getloadavg())
    x = {k: spread(v, ".3g", "x" if "/" in k else "") for k, v in rows.items()}
    strobe = " | ".join((x["exact"], x["dop"], x["dop/exact"]))
    lyap = " | ".join((x["lyap_exact"], x["lyap_var"], x["var/exact"]))
    verdict = "yes" if same else "NO"
    text = f"""# Motion: cost per mesh period by route, and the diagram on two processes

Command: `python benchmarks/bench_motion.py --repeats {args.repeats} --record`. Median of
{args.repeats} interleaved repeats (min..max); ratios formed within one repeat.

Machine: {platform.machine()}, {os.cpu_count()} cores shared with other jobs (load average at
the end: {load}), Python {platform.python_version()}.

Scene: the parametric backlash scene of docs/motion.md at f_m / f_n = 2.0 (chaos), from a state
on the attractor.

| what | exact piecewise flow | event-located DOP853 | DOP853 / exact |
|---|---|---|---|
| stroboscopic samples, ms per mesh period (200 periods; DOP853 rtol 1e-10) | {strobe} |
| Lyapunov exponent, ms per mesh period (100 periods; variational rtol 1e-8) | {lyap} |

Bifurcation diagram, 24 speeds up and down (100 settling periods and 32 samples each): serial
{x["serial"]} s, `workers=2` {x["pool"]} s (pool start-up included), ratio
{x["pool/serial"]}. Same samples bit for bit: {verdict}.
"""
    (out / "motion.md").write_text(text)
    print(text)


if __name__ == "__main__":  # the process pool imports this file
    main()
