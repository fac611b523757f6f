"""The forerunner's quick matplotlib import (gear_dyn/plots/_warm.py) changes no figure: a fresh
process made ready by import_for_files writes the same PNG bytes as one that imported
matplotlib as usual; matplotlib's own functions are restored after it."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

DRAW = """
import sys
if sys.argv[1] == "quick":
    from gear_dyn.plots._warm import SKIPPED, import_for_files
    import_for_files()
    import matplotlib.artist as artist
    from matplotlib.lines import Line2D
    assert artist.kwdoc is not None and artist.kwdoc.__name__ == "kwdoc"
    assert "_update_set_signature_and_docstring" in vars(artist.Artist)
    assert SKIPPED in (Line2D.set.__doc__ or "") or Line2D.set.__doc__ is None
else:
    import matplotlib.figure
    from matplotlib.lines import Line2D
    assert "Supported properties" in Line2D.set.__doc__
import gear_dyn as gd
from gear_dyn.io import save_figure
from gear_dyn.plots.run import plot_spectrum, plot_time_history
r = gd.run_scene(gd.load_scene("helicopter_tail"), periods=40)
fig = plot_time_history(r)
fig.axes[0].lines[0].set(lw=1.5, c="tab:red")  # set() with aliases still works
save_figure(fig, sys.argv[2] + "/t.png", dpi=80)
save_figure(plot_spectrum(r), sys.argv[2] + "/s.png", dpi=80)
"""


def test_quick_import_draws_the_same_bytes(tmp_path: Path) -> None:
    for how in ("quick", "usual"):
        (tmp_path / how).mkdir()
        subprocess.run([sys.executable, "-c", DRAW, how, str(tmp_path / how)], check=True,
                       env={**__import__("os").environ, "MPLBACKEND": "Agg"})
    for name in ("t.png", "s.png"):
        assert (tmp_path / "quick" / name).read_bytes() == (tmp_path / "usual" / name).read_bytes()
