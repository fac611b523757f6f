"""The spectra's labels read: after a draw at the size written, no two texts of a panel overlap,
and the sideband labels stand above the zoom's highest peak (not on the curve)."""

from __future__ import annotations

import itertools
from typing import Any

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.text import Text

import gear_dyn as gd
from gear_dyn.plots.run import plot_spectrum


def overlapping_texts(fig: Any) -> list[tuple[str, str]]:
    """Pairs of texts (axes texts and annotations) of one panel whose drawn extents overlap
    (an annotation's text alone: its leader line may cross other texts' space)."""
    FigureCanvasAgg(fig)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    found = []
    for ax in fig.axes:
        boxes = [(t.get_text(), Text.get_window_extent(t, renderer)) for t in ax.texts]
        found += [(a, b) for (a, ba), (b, bb) in itertools.combinations(boxes, 2)
                  if ba.overlaps(bb)]
    return found


def test_overlap_check_finds_overlaps() -> None:
    from matplotlib.figure import Figure

    fig = Figure()
    ax = fig.subplots()
    ax.text(0.5, 0.5, "first label")
    ax.text(0.52, 0.5, "second label")
    assert overlapping_texts(fig) == [("first label", "second label")]


@pytest.fixture(scope="module")
def eccentric() -> gd.Result:
    return gd.run_scene(gd.load_scene("eccentric_helical"), periods=40)


def test_eccentric_spectrum_labels_do_not_overlap(eccentric: gd.Result) -> None:
    fig = plot_spectrum(eccentric)
    assert overlapping_texts(fig) == []
    zoom = fig.axes[1]
    line = zoom.lines[0]
    f, a = line.get_xdata(), line.get_ydata()
    lo, hi = zoom.get_xlim()
    peak_px = zoom.transData.transform((0, float(np.max(a[(f >= lo) & (f <= hi)]))))[1]
    renderer = fig.canvas.get_renderer()
    sidebands = [t for t in zoom.texts if t.get_text().startswith("f_m")]
    assert len(sidebands) == 11  # f_m, f_m +- 1..3 f1, f_m +- 1..2 f2
    assert all(t.get_window_extent(renderer).y0 > peak_px for t in sidebands)


def test_excitation_spectrum_labels_do_not_overlap() -> None:
    """gear-dyn excitation eccentric_helical's spectra: the strongest peaks labelled, each label
    clear of the others (and of the marked peaks)."""
    from gear_dyn.cli.excitation import analyse
    from gear_dyn.plots.excitation import plot_excitation_spectra

    res = analyse(gd.load_scene("eccentric_helical"), samples_per_mesh=16)
    fig = plot_excitation_spectra(res["spectra"], res["peaks"], res["basis"])
    assert fig.get_size_inches()[0] == 12
    for ax in fig.axes:
        assert len(ax.texts) in range(1, 7)  # the 6 strongest peaks at most, at least one
    assert overlapping_texts(fig) == []
