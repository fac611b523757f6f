"""A sweep on a process pool (``workers=2``) reports exactly the numbers of the serial sweep.

Second method: the serial run in the calling process. The blocks, and the state each block of a
continuation starts from, do not depend on where they run, so every reported number (each curve's
arrays, the CSV columns, the sweep.json summary) must be equal bit for bit, NaN where NaN. Cases:
the linear helicopter tail pair across its parametric tongue (unstable speeds: NaN rows), and the
backlash pair up and down across its jumps in blocks of 2 speeds (each block continues from the
previous block's orbit, so the continuation crosses block boundaries on the pool's processes).
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from gear_dyn.analysis.sweep import RPM, SweepCurve, summarize_sweep, sweep_columns
from gear_dyn.scene import load_scene
from gear_dyn.scene.sweep import sweep_scene

SCENES = Path(__file__).resolve().parents[2] / "gear_dyn" / "scenes"
CASES = {
    # 1000..16000 rpm: main resonance and the tongue near f_m = 2 f_n (about 15000 rpm)
    "linear": ("helicopter_tail.toml", np.linspace(1000.0, 16000.0, 40), 8),
    # 4600..6400 rpm: the jump up (sweep up) and the jump down (sweep down), settled points
    "backlash": ("helicopter_tail_backlash.toml", np.arange(4600.0, 6401.0, 300.0), 2),
}


def _same(a: Any, b: Any, where: str) -> None:
    """Equal bit for bit (NaN equal to NaN), recursively through dicts and lists."""
    if isinstance(a, dict):
        assert a.keys() == b.keys(), where
        for k in a:
            _same(a[k], b[k], f"{where}.{k}")
    elif isinstance(a, list | tuple):
        assert len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            _same(x, y, f"{where}[{i}]")
    elif isinstance(a, np.ndarray):
        assert a.dtype == b.dtype and np.array_equal(a, b, equal_nan=a.dtype.kind == "f"), where
    elif isinstance(a, float) and math.isnan(a):
        assert isinstance(b, float) and math.isnan(b), where
    else:
        assert a == b, where


@pytest.mark.parametrize("case", sorted(CASES))
def test_pool_of_two_reports_the_serial_numbers(case: str) -> None:
    name, rpm, block = CASES[case]
    scene = load_scene(SCENES / name)
    serial = sweep_scene(scene, rpm * RPM, si=True, block=block)
    pool = sweep_scene(scene, rpm * RPM, si=True, block=block, workers=2)
    assert serial.executor == "serial"
    assert pool.executor == "process pool, 2 workers"
    assert [c.direction for c in pool.curves] == [c.direction for c in serial.curves]
    if case == "linear":
        assert "unstable" in serial.curves[0].status  # NaN rows are compared too
    else:
        assert [c.direction for c in serial.curves] == ["up", "down"]
        assert all("settled" in c.status for c in serial.curves)  # the jumps are inside
    for a, b in zip(serial.curves, pool.curves, strict=True):
        for f in dataclasses.fields(SweepCurve):
            _same(getattr(a, f.name), getattr(b, f.name), f"{a.direction}.{f.name}")
    _same(sweep_columns(serial), sweep_columns(pool), "sweep.csv")
    s, p = summarize_sweep(serial), summarize_sweep(pool)
    for key in ("run_time_s", "executor"):  # where and how long it ran: not a result
        s.pop(key), p.pop(key)
    _same(s, p, "sweep.json")
    for name in ("natural_frequency", "static_load", "nonlinear"):
        _same(getattr(serial, name), getattr(pool, name), name)
    _same(serial.orders, pool.orders, "orders")
