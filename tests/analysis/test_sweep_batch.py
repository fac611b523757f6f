"""The vectorised linear block against the per-speed steady path."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from gear_dyn.analysis.sweep import RPM, SweepOptions
from gear_dyn.analysis.sweep.batch import linear_block
from gear_dyn.analysis.sweep.points import steady_point
from gear_dyn.scene import load_scene
from gear_dyn.scene.sweep import SceneModels

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"
TAIL = SCENES / "helicopter_tail.toml"
BACKLASH = SCENES / "helicopter_tail_backlash.toml"
FIELDS = ("peak_force_ratio", "rms_dte", "ptp_dte", "mean_dte", "spectral_radius", "separation")


def test_linear_block_equals_per_speed_path() -> None:
    # 500..30000 rpm crosses the main resonance and the parametric tongue near f_m = 2 f_n
    # (unstable speeds: NaN points in both paths)
    factory = SceneModels.of(load_scene(TAIL))
    settings = factory.plan.settings
    opts = SweepOptions()
    speeds = np.linspace(500, 30000, 150) * RPM
    ref = [steady_point(factory(s), s, settings, opts, None)[0] for s in speeds]
    got = linear_block([factory(s) for s in speeds], speeds, settings, opts)
    assert got is not None
    assert [p.status for p in got] == [p.status for p in ref]
    assert sum(p.status == "unstable" for p in ref) > 0
    for name in FIELDS:
        a = np.array([getattr(p, name) for p in ref])
        b = np.array([getattr(p, name) for p in got])
        assert np.array_equal(np.isnan(a), np.isnan(b)), name
        ok = np.isfinite(a)
        # both exact up to rounding (products of ~70 exponentials): 1e-10 is 1e4 x that
        assert np.allclose(b[ok], a[ok], rtol=1e-10, atol=0), name
    for p, q in zip(ref, got, strict=True):
        if p.status != "unstable":
            assert np.allclose(q.spectrum, p.spectrum, rtol=0, atol=1e-10 * np.max(p.spectrum))
            assert np.allclose(q.state, p.state, rtol=1e-10, atol=0)


def test_linear_block_declines_backlash() -> None:
    factory = SceneModels.of(load_scene(BACKLASH))
    speeds = [3000 * RPM, 4000 * RPM]
    assert linear_block([factory(s) for s in speeds], speeds, factory.plan.settings,
                        SweepOptions()) is None
