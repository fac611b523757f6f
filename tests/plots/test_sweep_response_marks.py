"""What response.png states, read from its artists (not its pixels): the hysteresis band
shaded where the up and down sweeps sit on different orbits, the main resonance named when it
lies outside the swept range, and the marks of a negative mesh force on a linear model labelled
as the places where that model is invalid."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest
from matplotlib.colors import to_rgba

import gear_dyn as gd
from gear_dyn.analysis.sweep import RPM, hysteresis_ranges
from gear_dyn.cli.app import main
from gear_dyn.plots.sweep import plot_sweep_response
from gear_dyn.scene.sweep import model_at_speed

HYSTERESIS_RGBA = to_rgba("tab:orange", 0.15)


def _span_x(patch: Any) -> tuple[float, float]:
    """Data x range of an ``axvspan`` patch (a Rectangle, or a Polygon in older matplotlib)."""
    if hasattr(patch, "get_width"):
        return float(patch.get_x()), float(patch.get_x() + patch.get_width())
    xy = np.asarray(patch.get_xy())
    return float(xy[:, 0].min()), float(xy[:, 0].max())


def _hysteresis_spans(ax: Any) -> list[tuple[float, float]]:
    return sorted(_span_x(p) for p in ax.patches
                  if np.allclose(p.get_facecolor(), HYSTERESIS_RGBA))


@pytest.fixture(scope="module")
def backlash() -> Any:
    return gd.sweep_scene(gd.load_scene("helicopter_tail_backlash"), "4000 rpm:8000 rpm:41")


def test_hysteresis_band_is_shaded_where_the_branches_differ(backlash: Any) -> None:
    res = backlash
    fig = plot_sweep_response(res)
    ranges = hysteresis_ranges(res)
    assert ranges  # the softening jumps of Kahraman & Singh (1990) are inside this range
    step = 100.0  # rpm between speeds: 4000..8000 in 41
    want = [(a - step / 2, b + step / 2) for a, b in ranges]
    for ax in fig.axes[:3]:  # every panel shades the same speeds
        spans = _hysteresis_spans(ax)
        assert len(spans) == len(want)
        np.testing.assert_allclose(spans, want, rtol=1e-12)
    labels = fig.axes[0].get_legend_handles_labels()[1]
    assert sum(lab.startswith("hysteresis: up and down") for lab in labels) == 1
    # the shaded speeds are those where both sweeps found periodic orbits that differ: RMS
    # DTE of the two branches apart by more than 5 %, and within 5 % everywhere else
    up, down = res.curve("up"), res.curve("down")
    rpm = up.speed / RPM
    d = down.rms_dte[::-1]
    differ = np.abs(up.rms_dte - d) > 0.05 * np.maximum(up.rms_dte, d)
    shaded = np.zeros(rpm.size, dtype=bool)
    for a, b in want:
        shaded |= (rpm > a) & (rpm < b)
    periodic = np.array([s in ("periodic", "settled") for s in up.status]) & \
        np.array([s in ("periodic", "settled") for s in down.status])[::-1]
    assert np.array_equal(shaded, differ & periodic)


def test_resonance_outside_the_range_is_named(tmp_path: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    scene = gd.load_scene("helicopter_tail")
    res = gd.sweep_scene(scene, "1000 rpm:6000 rpm:11")
    # independent: f_m = z1 n / 60 = f_n at n = 60 f_n / z1
    fn = model_at_speed(scene, 1000 * RPM).natural_frequency
    z1 = scene.tables["gear"]["teeth_pinion"]
    n_res = 60 * fn / z1
    assert n_res > 6000
    note = f"f_m = f_n at {n_res:.0f} rpm, above the range"
    fig = plot_sweep_response(res)
    assert note in fig.get_suptitle()
    # the top axis names only the resonances inside the range (f_n/3, f_n/2), not f_n
    top = [a for a in fig.axes[0].child_axes if "f_m / f_n" in a.get_xlabel()][0]
    ticks = [t.get_text() for t in top.get_xticklabels()]
    assert ticks == ["f_n/3", "f_n/2"]
    out = tmp_path / "sw"
    assert main(["sweep", "helicopter_tail", "--speeds", "1000 rpm:6000 rpm:11", "--out",
                 str(out), "--no-progress"]) == 0
    assert f"  {note}\n" in capsys.readouterr().out


def test_negative_force_marks_say_the_linear_model_is_invalid() -> None:
    scene = gd.load_scene("helicopter_tail")  # linear: no [backlash]
    res = gd.sweep_scene(scene, "7600 rpm:9600 rpm:11")
    fig = plot_sweep_response(res)
    ax = fig.axes[0]
    marks = [ln for ln in ax.lines if ln.get_marker() == "x"]
    assert len(marks) == 1
    label = marks[0].get_label()
    assert label.startswith("F < 0: linear model invalid here") and "[backlash]" in label
    assert label in [t.get_text() for t in ax.get_legend().get_texts()]
    c = res.curves[0]
    marked = np.isin(c.speed / RPM, marks[0].get_xdata())
    assert marked.any() and not marked.all()
    np.testing.assert_array_equal(marks[0].get_ydata(), c.dynamic_factor[marked])
    # a second method: the transient run at a marked speed has a negative mesh force, and at an
    # unmarked speed none
    for i, negative in ((int(np.flatnonzero(marked)[0]), True),
                        (int(np.flatnonzero(~marked)[0]), False)):
        run = gd.run_scene(scene, speed=float(c.speed[i]), si=True)
        assert (run.extra["contact"]["min_force_n"] < 0) is negative
    # with backlash the same marks are real contact loss, and say so
    bl = plot_sweep_response(gd.sweep_scene(gd.load_scene("helicopter_tail_backlash"),
                                            "7000 rpm:8000 rpm:5", direction="up"))
    labels = bl.axes[0].get_legend_handles_labels()[1]
    assert "teeth separate" in labels
    assert not any(lab.startswith("F < 0") for lab in labels)
