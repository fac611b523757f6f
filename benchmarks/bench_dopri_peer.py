"""gear_dyn's exact route against a compiled Dormand-Prince 5(4) peer on the helicopter tail.

Run:  python benchmarks/bench_dopri_peer.py [--repeats 5] [--out DIR] [--record]   (needs numba)

The peer is what an engineer who writes compiled code would use: Dormand-Prince 5(4) (Dormand
and Prince 1980) in numba, scipy's step control (safety 0.9, factors 0.2..10, error exponent
-1/5, RMS norm of the error over ``atol + rtol max(|y|, |y_new|)``), restarted at every
stiffness switch, its 4th-order dense output (Shampine 1986, scipy's coefficients) sampling the
same output grid. Same equations (m x'' + c x' + k(t) x = W, the scene's rectangular-wave
stiffness), same grid (200 mesh periods, 64 samples per period), same error measure
``max |x - x_ref| / (W / k_m)`` against the exact route (whose own error is rounding, 1e-13 or
less). For each target (1e-8, 1e-10) the peer takes the loosest rtol of the grid 10^(-k/4)
that meets it. CPU time (``time.process_time``), one BLAS thread, medians of interleaved
repeats; the JIT compile time is reported apart. Writes ``dopri_peer.md``.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numba  # noqa: E402
import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # this tree's gear_dyn, not another install

# Dormand-Prince 5(4): nodes, stages, 5th-order weights, error weights, dense output (scipy's)
C = np.array([0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0])
A = np.array([[0, 0, 0, 0, 0], [1 / 5, 0, 0, 0, 0], [3 / 40, 9 / 40, 0, 0, 0],
              [44 / 45, -56 / 15, 32 / 9, 0, 0],
              [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729, 0],
              [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656]])
B = np.array([35 / 384, 0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84])
E = np.array([-71 / 57600, 0, 71 / 16695, -71 / 1920, 17253 / 339200, -22 / 525, 1 / 40])
P = np.array([
    [1, -8048581381 / 2820520608, 8663915743 / 2820520608, -12715105075 / 11282082432],
    [0, 0, 0, 0],
    [0, 131558114200 / 32700410799, -68118460800 / 10900136933, 87487479700 / 32700410799],
    [0, -1754552775 / 470086768, 14199869525 / 1410260304, -10690763975 / 1880347072],
    [0, 127303824393 / 49829197408, -318862633887 / 49829197408,
     701980252875 / 199316789632],
    [0, -282668133 / 205662961, 2019193451 / 616988883, -1453857185 / 822651844],
    [0, 40617522 / 29380423, -110615467 / 29380423, 69997945 / 29380423]])


@numba.njit(cache=False)
def dopri(cuts, kvals, m, c, w, t_out, y0, rtol, atol):  # pragma: no cover - compiled
    """States on t_out of m x'' + c x' + k x = w, k = kvals[p] on [cuts[p], cuts[p+1]]."""
    n_out = t_out.size
    out = np.empty((2, n_out))
    y = y0.copy()
    K = np.empty((7, 2))
    ys = np.empty(2)
    iout = 0
    while iout < n_out and t_out[iout] <= cuts[0]:
        out[:, iout] = y
        iout += 1
    h = 1e-3 * (cuts[1] - cuts[0])
    for p in range(cuts.size - 1):
        ta, tb, k = cuts[p], cuts[p + 1], kvals[p]
        last = p == cuts.size - 2
        t = ta
        K[0, 0], K[0, 1] = y[1], (w - c * y[1] - k * y[0]) / m
        rejected = False
        while t < tb:
            h = min(h, tb - t)
            for s in range(1, 6):
                for j in range(2):
                    acc = y[j]
                    for q in range(s):
                        acc += h * A[s, q] * K[q, j]
                    ys[j] = acc
                K[s, 0], K[s, 1] = ys[1], (w - c * ys[1] - k * ys[0]) / m
            yn0 = y[0] + h * (B[0] * K[0, 0] + B[2] * K[2, 0] + B[3] * K[3, 0] + B[4] * K[4, 0]
                              + B[5] * K[5, 0])
            yn1 = y[1] + h * (B[0] * K[0, 1] + B[2] * K[2, 1] + B[3] * K[3, 1] + B[4] * K[4, 1]
                              + B[5] * K[5, 1])
            K[6, 0], K[6, 1] = yn1, (w - c * yn1 - k * yn0) / m
            e0 = 0.0
            e1 = 0.0
            for q in range(7):
                e0 += E[q] * K[q, 0]
                e1 += E[q] * K[q, 1]
            s0 = atol[0] + rtol * max(abs(y[0]), abs(yn0))
            s1 = atol[1] + rtol * max(abs(y[1]), abs(yn1))
            err = np.sqrt(0.5 * ((h * e0 / s0) ** 2 + (h * e1 / s1) ** 2))
            if err < 1.0:
                t_new = t + h if t + h < tb else tb
                while iout < n_out and (t_out[iout] < t_new or (last and t_out[iout] <= t_new)):
                    th = (t_out[iout] - t) / h
                    for j in range(2):
                        acc = 0.0
                        for q in range(7):
                            kq = K[q, j]
                            acc += kq * th * (P[q, 0] + th * (P[q, 1] + th * (P[q, 2]
                                                                             + th * P[q, 3])))
                        out[j, iout] = y[j] + h * acc
                    iout += 1
                factor = 10.0 if err == 0.0 else min(10.0, 0.9 * err ** -0.2)
                if rejected:
                    factor = min(1.0, factor)
                t = t_new
                y[0], y[1] = yn0, yn1
                K[0, 0], K[0, 1] = K[6, 0], K[6, 1]
                h *= factor
                rejected = False
            else:
                h *= max(0.2, 0.9 * err ** -0.2)
                rejected = True
    return out


def main(argv: list[str] | None = None) -> int:
    from gear_dyn.scene import build_plan, load_scene
    from gear_dyn.scene.packaged import resolve_scene
    from gear_dyn.solvers.exact import propagate_exact
    from gear_dyn.solvers.simulate_bare import output_grid

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--calls", type=int, default=20)
    ap.add_argument("--out", type=Path, default=HERE / "out")
    ap.add_argument("--record", action="store_true")
    args = ap.parse_args(argv)
    import gear_dyn

    assert Path(gear_dyn.__file__).resolve().parent == HERE.parent / "gear_dyn", gear_dyn.__file__
    plan = build_plan(load_scene(resolve_scene("helicopter_tail")))
    model = plan.model
    t = output_grid(model, float(plan.t_end), plan.settings)
    y0 = np.asarray(model.initial_state(), dtype=float)
    pieces = model.linear_segments(float(t[0]), float(t[-1]))
    cuts = np.array([p[0] for p in pieces] + [pieces[-1][1]])
    kvals = np.array([-p[2][1, 0] * model.mass for p in pieces])
    xs = model.static_load / model.mean_stiffness
    scale = np.asarray(model.state_scale, dtype=float)
    ref, _ = propagate_exact(model, t)

    def peer(rtol: float) -> np.ndarray:
        return dopri(cuts, kvals, model.mass, model.damping, model.static_load, t, y0, rtol,
                     rtol * scale)

    start = time.process_time()
    peer(1e-6)
    jit = time.process_time() - start

    def cpu(fn: object) -> float:
        ts = []
        for _ in range(args.calls):
            t0 = time.process_time()
            fn()  # type: ignore[operator]
            ts.append(time.process_time() - t0)
        return statistics.median(ts)

    lines = [
        "# gear_dyn's exact route against a compiled Dormand-Prince 5(4) peer (helicopter tail)",
        "",
        f"Command: `python benchmarks/bench_dopri_peer.py --repeats {args.repeats} --calls "
        f"{args.calls}`. numba {numba.__version__}; peer JIT compile time {jit:.3g} s CPU (not "
        "in the figures). CPU time per run of 200 mesh periods (64 samples per period), "
        f"medians of {args.calls} calls, median over {args.repeats} interleaved repeats. Error: "
        "max |x - x_ref| / (W/k_m) against the exact route.",
        "",
        "| target max error | peer rtol | peer error | peer CPU | exact CPU | peer / exact |",
        "|---|---|---|---|---|---|",
    ]
    for target in (1e-8, 1e-10):
        rtol, err = None, None
        for k in range(16, 57):
            r = 10.0 ** (-k / 4)
            e = float(np.max(np.abs(peer(r)[0] - ref[0])) / xs)
            if e <= target:
                rtol, err = r, e
                break
        assert rtol is not None, target
        ratios, tp, te = [], [], []
        for _ in range(args.repeats):
            a = cpu(lambda rtol=rtol: peer(rtol))
            b = cpu(lambda: propagate_exact(model, t))
            tp.append(a)
            te.append(b)
            ratios.append(a / b)
        lines.append(f"| {target:g} | {rtol:.3g} | {err:.2g} | {statistics.median(tp) * 1e3:.3g} "
                     f"ms | {statistics.median(te) * 1e3:.3g} ms | "
                     f"{statistics.median(ratios):.2f}x |")
    lines += ["", "The exact route's own error is rounding: tests/solvers/test_kernel.py holds it "
              "to 1e-12 of W/k_m against a step-by-step scipy expm reference.", ""]
    text = "\n".join(lines) + "\n"
    out_dir = HERE / "results" if args.record else args.out
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "dopri_peer.md").write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
