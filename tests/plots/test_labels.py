"""Labels of marked points (plots._labels.place_labels) do not cover one another."""

from __future__ import annotations

from matplotlib.figure import Figure
from matplotlib.text import Text

from gear_dyn.plots._labels import place_labels


def test_crowded_labels_do_not_overlap() -> None:
    fig = Figure(figsize=(8, 4.5))
    ax = fig.add_subplot()
    ax.plot([0, 100], [0, 100])
    # six marks within a label's width of each other, as at the folds and doublings of a
    # period-doubling cascade
    marks = [(80 + 0.7 * i, 50 + (-1) ** i * 0.8 * i, f"PD {11700 + 50 * i} rpm") for i in range(6)]
    place_labels(ax, marks)
    assert sorted(t.get_text() for t in ax.texts) == sorted(m[2] for m in marks)
    boxes = []
    for t in ax.texts:
        t.get_window_extent()
        boxes.append(Text.get_window_extent(t))
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert not a.overlaps(b)
    # each label points at its own mark
    for t in ax.texts:
        x, y = t.xy
        assert any(abs(x - m[0]) < 1e-12 and abs(y - m[1]) < 1e-12 and t.get_text() == m[2]
                   for m in marks)
