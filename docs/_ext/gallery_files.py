"""sphinx-gallery glue: each example writes its figures as PNG files; the gallery shows those.

The examples draw on ``matplotlib.figure.Figure`` objects (no pyplot state) and save them with
:func:`gear_dyn.io.save_figure`, so the pictures on a gallery page are the very files a user
gets from ``python examples/plot_NAME.py OUT_DIR``. :func:`example_argv` hands every example a
fresh output folder under ``docs/_build/gallery-out/``; :func:`scrape_pngs` (an image scraper,
as in sphinx-gallery's "custom scrapers" guide) copies the PNG files that appeared there into
the gallery. conf.py names both by their module path so the Sphinx configuration stays
picklable.
"""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any

from sphinx_gallery.scrapers import figure_rst


def _out_dir(gallery_conf: dict[str, Any], src_file: str) -> Path:
    return Path(gallery_conf["src_dir"]) / "_build" / "gallery-out" / Path(src_file).stem


def example_argv(gallery_conf: dict[str, Any], script_vars: dict[str, Any]) -> list[str]:
    """The command-line arguments of one example: a fresh output folder (``OUT_DIR``)."""
    out = _out_dir(gallery_conf, script_vars["src_file"])
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    return [str(out)]


def scrape_pngs(block: Any, block_vars: dict[str, Any], gallery_conf: dict[str, Any]) -> str:
    """Copy the PNG files the example has written since the last block into the gallery."""
    out = _out_dir(gallery_conf, block_vars["src_file"])
    shown = out / ".shown"
    seen = set(shown.read_text().split("\n")) if shown.exists() else set()
    new = [p for p in sorted(out.rglob("*.png")) if str(p.relative_to(out)) not in seen]
    images = []
    for png in new:
        target = block_vars["image_path_iterator"].next()
        shutil.copyfile(png, target)
        images.append(target)
    shown.write_text("\n".join(seen | {str(p.relative_to(out)) for p in new}))
    return figure_rst(images, gallery_conf["src_dir"])


class TutorialFirst:
    """Gallery order: the tutorial first, then the examples by file name (sphinx-gallery's
    ``within_subsection_order`` sort key)."""

    def __init__(self, src_dir: str) -> None:
        self.src_dir = src_dir

    def __call__(self, filename: str) -> tuple[int, str]:
        return (0 if filename == "plot_tutorial.py" else 1, filename)
