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
