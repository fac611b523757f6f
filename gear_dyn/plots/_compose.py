"""One figure drawn in parts (by two processes at once), the parts laid over each other.

A figure whose subplot columns do not overlap (fixed margins and gaps, ``fixed_layout``) can be
rendered as two images: a *base* with the figure's background, its figure-level texts and some
of its axes, and a transparent *top* with the other axes. Laying the top over the base
(straight alpha "over") gives the pixels of the whole figure drawn at once to within one 8-bit
level per overlapping anti-aliased edge in the top part (its colour and alpha are rounded to 8
bits once per layer): about 100 pixels of a million differ, by 1 or 2
(tests/plots/test_compose.py). The PNG is written by the same call ``savefig`` makes.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from numpy.typing import NDArray

from gear_dyn.io import write_bytes

Image = NDArray[np.uint8]


def column_of(ax: Any) -> int:
    """The first grid column an Axes spans (0 for an Axes outside a grid)."""
    spec = ax.get_subplotspec()
    return 0 if spec is None else int(spec.colspan.start)


def canvas_shape(size: tuple[float, float], dpi: float) -> tuple[int, int, int]:
    """``(height, width, 4)`` of the RGBA image of a figure of ``size`` (width, height) inches
    rendered at ``dpi`` (Agg truncates the size in pixels, so does this)."""
    w, h = size
    return int(h * dpi), int(w * dpi), 4


def render_part(fig: Any, dpi: float, keep: Callable[[Any], bool], base: bool) -> Image:
    """RGBA image of ``fig`` at ``dpi`` with only the Axes for which ``keep(ax)`` holds.

    ``base``: with the figure's background patch, texts and legends; otherwise transparent
    around the kept Axes. The figure is left as it was.
    """
    hidden = [a for a in fig.axes if a.get_visible() and not keep(a)]
    if not base:
        hidden += [fig.patch, *(a for a in (*fig.texts, *fig.legends) if a.get_visible())]
        if fig._suptitle is not None and fig._suptitle.get_visible():
            hidden.append(fig._suptitle)
    old_dpi = fig.dpi
    try:
        for artist in hidden:
            artist.set_visible(False)
        fig.set_dpi(dpi)
        canvas = FigureCanvasAgg(fig)
        canvas.draw()
        return np.array(canvas.buffer_rgba(), dtype=np.uint8)
    finally:
        for artist in hidden:
            artist.set_visible(True)
        fig.set_dpi(old_dpi)


def lay_over(base: Image, top: Image) -> Image:
    """``top`` laid over the opaque ``base`` (straight alpha), rounded to 8 bits.

    Only the box around the top's non-transparent pixels is mixed, in integers:
    ``(t a + b (255 - a) + 127) // 255`` is ``t a / 255 + b (1 - a / 255)`` rounded (the
    fraction is k / 255, never one half).
    """
    out = base.copy()
    alpha = top[..., 3]
    rows = np.flatnonzero(alpha.any(axis=1))
    cols = np.flatnonzero(alpha.any(axis=0))
    if rows.size == 0:
        return out
    box = np.s_[rows[0]:rows[-1] + 1, cols[0]:cols[-1] + 1]
    a = alpha[box][..., None].astype(np.uint16)  # t a + b (255 - a) + 127 <= 65152
    mixed = top[box][..., :3] * a + base[box][..., :3] * (255 - a) + 127
    out[box][..., :3] = mixed // 255
    return out


def write_png(image: Image, path: str | Path, dpi: float, **pil_kwargs: Any) -> Path:
    """Write an RGBA image as ``savefig(path, dpi=dpi, pil_kwargs=...)`` writes a figure
    (the same matplotlib call, so the same PNG metadata), atomically."""
    import io

    from matplotlib.image import imsave

    buf = io.BytesIO()
    imsave(buf, image, format="png", origin="upper", dpi=dpi, pil_kwargs=pil_kwargs or None)
    return write_bytes(path, buf.getvalue())


__all__ = ["canvas_shape", "column_of", "lay_over", "render_part", "write_png"]
