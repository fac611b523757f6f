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


def test_labels_that_fit_nowhere_become_a_numbered_key() -> None:
    """Twenty marks on one spot, as at the end of a period-doubling cascade: the labels that
    cannot stand beside their mark without covering another label or a mark are numbered, each
    number's text is a legend entry; after the final layout no two texts overlap and every
    mark's text is shown once (beside its mark or in the key)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from gear_dyn.plots._axes import tidy
    from gear_dyn.plots._labels import label_marks

    fig = Figure(figsize=(8, 4.5))
    ax = fig.add_subplot()
    ax.plot([0, 100], [0, 100], label="curve")
    marks = [(80 + 0.2 * i, 50 + 0.3 * (-1) ** i * i, f"PD {11700 + 10 * i} rpm")
             for i in range(20)]
    avoid = [(x, y - 3) for x, y, _ in marks]
    label_marks(ax, marks, own_figure=True, layout=tidy, avoid=avoid)
    FigureCanvasAgg(fig)
    fig.canvas.draw()
    texts = [t.get_text() for t in ax.texts]
    key = [t.get_text() for t in ax.get_legend().get_texts()][1:]
    assert key, "some labels must have become numbers"
    assert sorted(texts) == sorted([m[2] for m in marks if m[2] not in key]
                                   + [str(n) for n in range(1, len(key) + 1)])
    assert sorted(key + [t for t in texts if not t.isdigit()]) == sorted(m[2] for m in marks)
    boxes = [Text.get_window_extent(t) for t in ax.texts]
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert not a.overlaps(b)
