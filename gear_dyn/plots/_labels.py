"""Text labels beside marked points that do not cover one another; a legend beside the axes."""

from __future__ import annotations

from collections.abc import Callable
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
                 color: Any = None, box: bool = False) -> None:
    """Write each mark's text beside its point (data coordinates), in x order, at the first
    offset of a fixed list where its text overlaps no label placed before it and no marked
    point and stays inside the axes, else at the offset with the fewest overlaps (greedy; text
    extents from the figure's renderer once the axis limits are settled). ``color``: of the
    texts (None: the default text colour); ``box``: each text on a white, slightly transparent
    box (legible over curves).
    """
    axis.get_xlim(), axis.get_ylim()  # settle the pending autoscaling: final data transform
    frame = axis.get_window_extent()  # a label outside the axes counts as one overlap
    # the marked points themselves (a 6-point square each): no label covers one
    r = 3 * axis.figure.dpi / 72
    placed: list[Any] = [Bbox.from_extents(px - r, py - r, px + r, py + r) for px, py in
                         axis.transData.transform([(x, y) for x, y, _ in marks])] if marks else []
    for x, y, text in sorted(marks, key=lambda m: (m[0], m[1])):
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
        dx, dy, ha = _OFFSETS[best[1]]
        axis.annotate(text, (x, y), xytext=(dx, dy), textcoords="offset points",
                      fontsize=fontsize, ha=ha, va="bottom" if dy > 0 else "top",
                      arrowprops=_LEADER if best[1] >= 2 else None, color=color,
                      bbox=_BOX if box else None)
        placed.append(best[2])


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
