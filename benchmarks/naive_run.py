"""The naive reference of the whole-command benchmarks: what a user writes by hand.

Run:  python benchmarks/naive_run.py PARAMS.json OUT_DIR

Integrates the single-DOF mesh model ``m x'' + c x' + k(t) x = W`` (dead-zone backlash when
``half_gap`` is given) with one ``solve_ivp(RK45)`` call over the whole span, a plain Python
right-hand side (an ``if`` on the mesh phase for the rectangular stiffness), and saves the two
figures ``gear-dyn run`` draws: the time history and the amplitude spectrum of the steady window
(pyplot, Agg). Writes ``y.npy`` (the states on the output grid) so the caller can measure its
error. It imports nothing from gear_dyn: the model's numbers come from PARAMS.json.
"""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

_T0 = time.perf_counter()
_LAPS: list[tuple[str, float]] = []


def lap(name: str) -> None:
    """Phase times for benchmarks/bench_cli.py (printed to stderr with NAIVE_PHASES=1)."""
    _LAPS.append((name, time.perf_counter()))


import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

lap("imports (numpy, scipy.integrate, matplotlib.pyplot)")


def main(argv: list[str]) -> int:
    p = json.loads(Path(argv[0]).read_text())
    out = Path(argv[1])
    out.mkdir(parents=True, exist_ok=True)
    m, c, w, fm = p["mass"], p["damping"], p["static_load"], p["mesh_frequency"]
    f_switch, k_hi, k_lo = p["f_switch"], p["k_hi"], p["k_lo"]
    gap = p.get("half_gap")

    def rhs(t: float, y: np.ndarray) -> list[float]:
        k = k_hi if (fm * t) % 1.0 < f_switch else k_lo
        x = y[0]
        if gap is not None:
            x = x - gap if x > gap else (x + gap if x < -gap else 0.0)
        return [y[1], (w - c * y[1] - k * x) / m]

    t = np.linspace(0.0, p["t_end"], p["n_samples"])
    sol = solve_ivp(rhs, (0.0, t[-1]), p["y0"], method="RK45", t_eval=t, rtol=p["rtol"],
                    atol=np.asarray(p["atol"]))
    np.save(out / "y.npy", sol.y)
    lap("solve (RK45)")

    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot(t * 1e3, sol.y[0] * 1e6)
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("DTE (um)")
    fig.savefig(out / "time_history.png", dpi=100)
    plt.close(fig)
    lap("time plot")

    steady = t >= t[-1] / 2
    x = sol.y[0][steady]
    amp = 2 * np.abs(np.fft.rfft(x - x.mean())) / len(x)
    freq = np.fft.rfftfreq(len(x), t[1] - t[0])
    fig, ax = plt.subplots(figsize=(8, 4))
    ax.semilogy(freq, amp * 1e6)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("amplitude (um)")
    fig.savefig(out / "spectrum.png", dpi=100)
    plt.close(fig)
    lap("spectrum plot")
    if os.environ.get("NAIVE_PHASES"):
        prev = _T0
        for name, t in _LAPS:
            print(f"{name}\t{t - prev:.4f}", file=sys.stderr)
            prev = t
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
