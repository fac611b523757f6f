"""The co-simulation figure's difference panels read without an offset: a difference of a few
picometres is drawn in pm, not as 1e-6 um."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg

from gear_dyn.plots.cosim import diff_unit, overlay_figure


def test_diff_unit_reads_at_least_one() -> None:
    assert diff_unit("dte", np.array([3e-12, -2e-12])) == ("pm", 1e12)
    assert diff_unit("dte", np.array([4e-8])) == ("nm", 1e9)
    assert diff_unit("dte", np.array([2e-5])) == ("µm", 1e6)
    assert diff_unit("mesh_force", np.array([0.02])) == ("mN", 1e3)
    assert diff_unit("dte", np.zeros(3)) == ("µm", 1e6)
    assert diff_unit("other", np.array([1.0])) == ("SI", 1.0)


def test_overlay_difference_panel_has_no_offset() -> None:
    fm = 450.0
    t = np.linspace(0.0, 20 / fm, 2001)
    ref = 20e-6 + 5e-6 * np.sin(2 * np.pi * fm * t)
    fmu = ref + 3e-12 * np.cos(2 * np.pi * fm * t)   # picometres apart
    report = SimpleNamespace(
        outputs=["dte"], t=t, mesh_frequency=fm, steps=[SimpleNamespace(step=1e-5)],
        bounds=None, ref_y=[ref], fmu_y=[fmu], reference_method="DOP853", fmu_method="RK45",
        scene_name="test", rtol=1e-10, passed=True)
    fig = overlay_figure(report)
    FigureCanvasAgg(fig)
    fig.canvas.draw()
    d = fig.axes[1]
    assert d.get_ylabel() == "diff (pm)"
    assert d.yaxis.get_major_formatter().get_offset() == ""
    lo, hi = d.get_ylim()
    assert hi == pytest.approx(3.0, rel=0.2) and lo == pytest.approx(-3.0, rel=0.2)
