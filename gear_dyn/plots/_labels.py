"""Text labels beside marked points that do not cover one another; a legend beside the axes."""

from __future__ import annotations

from collections.abc import Callable, Collection, Sequence
from typing import Any

from matplotlib.text import Text
from matplotlib.transforms import Bbox

#: offsets (points) and horizontal alignment tried in turn: beside the mark above and below,
#: then further up and down on the right and the left; from the third on, a thin leader line
#: joins the label to its mark
_OFFSETS = ((5, 3, "left"), (5, -3, "left"), (8, 20, "left"), (8, -20, "left"),
            (-8, 20, "right"), (-8, -20, "right"), (8, 34, "left"), (8, -34, "left"),
            (-8, 34, "right"), (-8, -34, "right"), (8, 48, "left"), (8, -48, "left"))
_BOX = {"facecolor": "white", "edgecolor": "none", "alpha": 0.8, "pad": 0.5}
_LEADER = {"arrowstyle": "-", "lw": 0.5, "color": "0.45", "shrinkA": 0, "shrinkB": 3}


def place_labels(axis: Any, marks: list[tuple[float, float, str]], fontsize: float = 7,
                 color: Any = None, box: bool = False, keyed: Collection[str] = (),
                 avoid: Sequence[tuple[float, float]] = ()) -> list[str]:
    """Write each mark's text beside its point (data coordinates), in x order, at the first
    offset of a fixed list where its text overlaps no label placed before it and no marked
    point and stays inside the axes (greedy; text extents from the figure's renderer once the
    axis limits are settled).

    A text that fits at no offset is written as a number instead, placed the same way, and a
    legend entry with that number as its marker carries the text (the key: read it with the
    axes' legend, drawn after this call). ``keyed``: texts written as numbers from the start
    (a second pass once the layout changed; their legend entries exist). ``color``: of the
    texts (None: the default text colour); ``box``: each text on a white, slightly
    transparent box (legible over curves); ``avoid``: more points (data coordinates) no label
    may cover, e.g. the same mark drawn on other samples.

    Returns
    -------
    list of str
        The texts written as numbers, in number order (1, 2, ...).
    """
    axis.get_xlim(), axis.get_ylim()  # settle the pending autoscaling: final data transform
    frame = axis.get_window_extent()  # a label outside the axes counts as one overlap
    # the marked points themselves (a 6-point square each): no label covers one
    r = 3 * axis.figure.dpi / 72
    points = [(x, y) for x, y, _ in marks] + list(avoid)
    placed: list[Any] = [Bbox.from_extents(px - r, py - r, px + r, py + r) for px, py in
                         axis.transData.transform(points)] if points else []
    key: list[str] = []
    for x, y, text in sorted(marks, key=lambda m: (m[0], m[1])):
        hits, i, ext = _best_offset(axis, text, x, y, fontsize, frame, placed)
        if text in keyed or hits:
            key.append(text)
            label = str(len(key))
            hits, i, ext = _best_offset(axis, label, x, y, fontsize, frame, placed)
            if text not in keyed:
                axis.plot([], [], ls="none", marker=f"${label}$", ms=5 if len(label) < 2 else 8,
                          color=color or "k", label=text)
        else:
            label = text
        dx, dy, ha = _OFFSETS[i]
        axis.annotate(label, (x, y), xytext=(dx, dy), textcoords="offset points",
                      fontsize=fontsize, ha=ha, va="bottom" if dy > 0 else "top",
                      arrowprops=_LEADER if i >= 2 else None, color=color,
                      bbox=_BOX if box else None)
        placed.append(ext)
    return key


def _best_offset(axis: Any, text: str, x: float, y: float, fontsize: float, frame: Any,
                 placed: list[Any]) -> tuple[int, int, Any]:
    """(overlaps, offset index, text extent) of the first offset where ``text`` overlaps
    nothing in ``placed`` and stays inside ``frame``, else of the one with fewest overlaps."""
    best: tuple[int, int, Any] | None = None
    for i, (dx, dy, ha) in enumerate(_OFFSETS):
        ann = axis.annotate(text, (x, y), xytext=(dx, dy), textcoords="offset points",
                            fontsize=fontsize, ha=ha, va="bottom" if dy > 0 else "top",
                            arrowprops=_LEADER if i >= 2 else None)
        ann.get_window_extent()  # places the text (and its leader)
        ext = Text.get_window_extent(ann).expanded(1.04, 1.15)  # the text alone
        inside = (frame.x0 <= ext.x0 and ext.x1 <= frame.x1 and frame.y0 <= ext.y0
                  and ext.y1 <= frame.y1)
        hits = sum(ext.overlaps(b) for b in placed) + (0 if inside else 1)
        ann.remove()
        if best is None or hits < best[0]:
            best = (hits, i, ext)
        if hits == 0:
            break
    assert best is not None
    return best


def label_marks(axis: Any, marks: list[tuple[float, float, str]], own_figure: bool,
                layout: Callable[[Any], None], fontsize: float = 8,
                avoid: Sequence[tuple[float, float]] = ()) -> None:
    """The marks' labels (:func:`place_labels`) and the legend (:func:`legend_beside`).

    On a figure of our own the legend is drawn and ``layout(figure)`` run first, so that the
    labels are placed on the axes as they will be drawn; if some labels became numbers, their
    key entries widen the legend: legend and layout are redone and the labels placed again on
    the final axes. On a caller's axes (their layout): labels, then the legend inside. The
    labels stand on white boxes (legible where a curve passes); ``avoid``: as in
    :func:`place_labels`.
    """
    if not own_figure:
        place_labels(axis, marks, fontsize, box=True, avoid=avoid)
        legend_beside(axis, own_figure=False, fontsize=fontsize)
        return
    legend_beside(axis, own_figure=True, fontsize=fontsize)
    layout(axis.figure)
    before = len(axis.texts)
    keyed = place_labels(axis, marks, fontsize, box=True, avoid=avoid)
    if keyed:
        for text in list(axis.texts)[before:]:
            text.remove()
        legend_beside(axis, own_figure=True, fontsize=fontsize)
        layout(axis.figure)
        if place_labels(axis, marks, fontsize, box=True, keyed=keyed, avoid=avoid) != keyed:
            legend_beside(axis, own_figure=True, fontsize=fontsize)  # a new number's entry


def legend_beside(axis: Any, own_figure: bool, fontsize: float = 7) -> None:
    """The legend right of the axes on a figure of our own (curves, marks and labels stay
    uncovered), at the best place inside a caller's axes (whose figure layout is theirs)."""
    if own_figure:
        axis.legend(fontsize=fontsize, loc="upper left", bbox_to_anchor=(1.01, 1.0),
                    borderaxespad=0.0)
    else:
        axis.legend(fontsize=fontsize, loc="best")


def legend_once() -> Callable[[str], str | None]:
    """A legend-label filter: each text the first time it is asked for, None after (one legend
    entry per kind of curve or mark)."""
    shown: set[str] = set()

    def once(text: str) -> str | None:
        if text in shown:
            return None
        shown.add(text)
        return text
    return once
