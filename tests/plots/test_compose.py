"""A figure drawn in parts and laid over each other is the figure drawn whole, to one 8-bit
level (gear_dyn/plots/_compose.py): what `gear-dyn run` writes when it draws on two cores."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from matplotlib.image import imread

import gear_dyn as gd
from gear_dyn.io import save_figure
from gear_dyn.plots._compose import canvas_shape, column_of, lay_over, render_part, write_png
from gear_dyn.plots.run import plot_time_history, time_history_size

DPI = 110


@pytest.fixture(scope="module", params=["helicopter_tail", "eccentric_helical"])
def result(request: pytest.FixtureRequest) -> gd.Result:
    return gd.run_scene(gd.load_scene(request.param), periods=40)


def _png(path: Path) -> np.ndarray:
    return np.rint(imread(path) * 255).astype(int)


def test_parts_laid_over_are_the_whole_figure(result: gd.Result, tmp_path: Path) -> None:
    fig = plot_time_history(result, blocks=1500)
    assert {column_of(a) for a in fig.axes} == {0, 1}
    save_figure(plot_time_history(result, blocks=1500), tmp_path / "whole.png", dpi=DPI,
                pil_kwargs={"compress_level": 1})
    base = render_part(fig, DPI, lambda a: column_of(a) == 0, base=True)
    top = render_part(fig, DPI, lambda a: column_of(a) > 0, base=False)
    assert base.shape == top.shape == canvas_shape(time_history_size(result), DPI)
    assert tuple(fig.get_size_inches()) == time_history_size(result)
    assert top[0, 0, 3] == 0 and base[0, 0, 3] == 255  # the top is transparent around its axes
    write_png(lay_over(base, top), tmp_path / "parts.png", dpi=DPI, compress_level=1)
    whole, parts = _png(tmp_path / "whole.png"), _png(tmp_path / "parts.png")
    assert whole.shape == parts.shape
    diff = np.abs(whole - parts)
    # the transparent part holds colour and alpha in 8 bits, each rounded once per layer drawn
    # there: one level where one anti-aliased edge lies, two where two overlap; nothing else
    assert diff.max() <= 2
    assert np.count_nonzero(diff) < 1e-3 * diff.size
    # neither part alone is the figure: each column's lines are in one part only
    assert np.abs(base.astype(int) - whole).max() > 100
    assert np.count_nonzero(top[..., 3]) > 0.05 * top[..., 3].size


def test_render_part_leaves_the_figure_as_it_was(result: gd.Result) -> None:
    fig = plot_time_history(result)
    before = [(a.get_visible(), a.patch.get_visible()) for a in fig.axes]
    dpi, patch = fig.dpi, fig.patch.get_visible()
    render_part(fig, DPI, lambda a: column_of(a) > 0, base=False)
    assert [(a.get_visible(), a.patch.get_visible()) for a in fig.axes] == before
    assert (fig.dpi, fig.patch.get_visible()) == (dpi, patch)
    assert fig._suptitle is not None and fig._suptitle.get_visible()


def test_lay_over_by_alpha() -> None:
    base = np.full((1, 3, 4), 255, dtype=np.uint8)
    base[..., :3] = (10, 20, 30)
    top = np.zeros((1, 3, 4), dtype=np.uint8)
    top[0, :, :3] = (200, 100, 0)
    top[0, :, 3] = (0, 255, 51)  # transparent, opaque, 20 %
    out = lay_over(base, top)
    assert out[0, 0].tolist() == [10, 20, 30, 255]
    assert out[0, 1].tolist() == [200, 100, 0, 255]
    assert out[0, 2].tolist() == [48, 36, 24, 255]  # 0.2 * top + 0.8 * base, rounded
