"""Decimating a long line to its per-pixel envelope draws the same picture, and the run figures'
fixed margins are where they are asked to be."""

from __future__ import annotations

import io
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from PIL import Image

from gear_dyn.plots._axes import fixed_layout
from gear_dyn.plots._decimate import envelope
from gear_dyn.plots.run import plot_time_history
from gear_dyn.scene import load_scene, run_scene

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "scenes"


@pytest.fixture(scope="module")
def result() -> Any:
    return run_scene(load_scene(EXAMPLES / "helicopter_tail.toml"))


def pixels(fig: Figure) -> np.ndarray:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)  # as gear-dyn run saves it
    return np.asarray(Image.open(buf)).astype(int)


def test_envelope_keeps_extremes_ends_and_order() -> None:
    rng = np.random.default_rng(1)
    x = np.linspace(0.0, 1.0, 10_007)
    y = np.sin(400 * x) + 0.1 * rng.normal(size=x.size)
    xe, ye = envelope(x, y, 500)
    assert xe.size < x.size / 4
    assert np.all(np.diff(xe) > 0)  # in time order, no duplicates
    assert xe[0] == x[0] and xe[-1] == x[-1]
    assert ye.max() == y.max() and ye.min() == y.min()
    k = x.size // 500  # every block's extremes are kept
    for b in range(0, 500 * k, k):
        seg = slice(b, b + k)
        assert y[seg].max() in ye and y[seg].min() in ye
    assert envelope(x[:100], y[:100], 500)[0].size == 100  # short series: whole


def test_envelope_draws_the_same_pixels(result: Any) -> None:
    """gear-dyn run's whole-run panels: the envelope at 1500 blocks against every sample, same
    layout and dpi: no pixel differs by more than antialiasing shades (measured: max 27/255,
    0.2 % of the pixels by more than 8/255)."""
    full = pixels(plot_time_history(result))
    reduced = pixels(plot_time_history(result, blocks=1500))
    diff = np.abs(full - reduced).max(axis=2)
    assert diff.max() <= 64
    assert np.count_nonzero(diff > 8) < 0.02 * diff.size


def test_fixed_layout_margins_in_inches() -> None:
    fig = Figure(figsize=(13, 6))
    axes = fig.subplots(2, 2)
    fixed_layout(fig, left=0.72, right=0.15, top=0.62, bottom=0.55, wgap=0.75, hgap=0.25)
    fig.canvas = FigureCanvasAgg(fig)
    w, h = fig.get_size_inches()
    b00, b01 = axes[0, 0].get_position(), axes[0, 1].get_position()
    b10 = axes[1, 0].get_position()
    assert b00.x0 * w == pytest.approx(0.72)
    assert (1 - b01.x1) * w == pytest.approx(0.15)
    assert (b01.x0 - b00.x1) * w == pytest.approx(0.75)
    assert (b00.y0 - b10.y1) * h == pytest.approx(0.25)
    assert (1 - b00.y1) * h == pytest.approx(0.62) and b10.y0 * h == pytest.approx(0.55)


def test_period_envelope_bounds_every_sample_and_is_attained() -> None:
    """Each sample lies within its bin's [min, max]; each bin's bounds are samples of it; the
    bins span the run, one mesh period wide (the last takes the remainder) or whole numbers of
    periods under ``blocks``."""
    from gear_dyn.plots._decimate import period_envelope

    rng = np.random.default_rng(2)
    t = np.linspace(0.0, 0.1234, 9_001)
    y = np.sin(2 * np.pi * 1000 * t) * (1 + 5 * t) + 0.05 * rng.normal(size=t.size)
    edges, lo, hi = period_envelope(t, y, 1e-3)
    assert edges[0] == t[0] and edges[-1] == t[-1] and np.all(np.diff(edges) > 0)
    assert lo.size == hi.size == edges.size - 1 == 123
    np.testing.assert_allclose(np.diff(edges)[:-1], 1e-3, rtol=1e-9)
    b = np.clip(np.searchsorted(edges, t, side="right") - 1, 0, lo.size - 1)
    assert np.all(lo[b] <= y) and np.all(y <= hi[b])
    for i in range(lo.size):
        assert lo[i] in y[b == i] and hi[i] in y[b == i]
    e50, lo50, _ = period_envelope(t, y, 1e-3, blocks=50)
    assert lo50.size <= 50 and np.allclose(np.diff(e50)[:-1], 3e-3)
    assert lo50.min() == y.min()
    with pytest.raises(ValueError, match="period"):
        period_envelope(t, y, 0.0)


def test_whole_run_band_bounds_the_run_and_zoom_is_lines(result: Any) -> None:
    """gear-dyn run / demo: the whole-run panels draw no line of every sample (it would fill the
    panel) but the band between each mesh period's extremes, which holds every sample at its
    time; the zoom column draws the last 10 periods as lines, their span marked on the left."""
    from matplotlib.patches import StepPatch

    fig = plot_time_history(result, blocks=1500)
    ax_dte, ax_force = fig.axes[0], fig.axes[2]
    assert all(len(line.get_xdata()) < 2000 for line in ax_dte.lines)
    t_ms = result.t * 1e3
    for ax, y in ((ax_dte, result.outputs["dte"] * 1e6),
                  (ax_force, result.outputs["mesh_force"] / 1e3)):
        bands = [p for p in ax.patches if isinstance(p, StepPatch) and p.get_fill()]
        assert len(bands) == 1
        hi, edges, lo = bands[0].get_data()
        assert edges[0] == t_ms[0] and edges[-1] == t_ms[-1]
        assert hi.size == int((result.t[-1] - result.t[0]) * result.mesh_frequency + 1e-9)
        b = np.clip(np.searchsorted(edges, t_ms, side="right") - 1, 0, hi.size - 1)
        assert np.all(lo[b] <= y) and np.all(y <= hi[b])
        assert hi.max() == y.max() and lo.min() == y.min()
    zoom = fig.axes[1].lines[0].get_xdata()
    assert zoom[-1] - zoom[0] == pytest.approx(10e3 / result.mesh_frequency, rel=0.01)
    labels = [t.get_text() for t in ax_dte.get_legend().get_texts()]
    assert "steady-state window" in labels and "last 10 mesh periods (right)" in labels
    assert ax_dte.get_title() == "whole run: max / min per mesh period"


def test_excitation_whole_span_is_a_band_holding_every_sample() -> None:
    """gear-dyn excitation's whole-span column: thousands of mesh cycles as the band between
    each mesh period's extremes (every sample inside it), the first periods as lines."""
    from matplotlib.patches import StepPatch

    from gear_dyn.cli.excitation import analyse
    from gear_dyn.plots.excitation import plot_excitation_time

    res = analyse(load_scene("eccentric_helical"), samples_per_mesh=16)
    fig = plot_excitation_time(res["t"], res["series"], res["basis"])
    t = res["t"]
    for row, key in enumerate(k for k in ("w2", "contact_length", "friction_force",
                                          "friction_torque_pinion") if k in res["series"]):
        ax = fig.axes[2 * row]
        (band,) = [p for p in ax.patches if isinstance(p, StepPatch) and p.get_fill()]
        hi, edges, lo = band.get_data()
        y = np.asarray(res["series"][key]) * (1e3 if key == "contact_length" else 1.0)
        b = np.clip(np.searchsorted(edges, t, side="right") - 1, 0, hi.size - 1)
        assert np.all(lo[b] <= y) and np.all(y <= hi[b])
        assert hi.size == int((t[-1] - t[0]) * res["basis"].mesh + 1e-9)
        assert not ax.lines or all(len(line.get_xdata()) <= 2 * hi.size + 2 for line in ax.lines)
