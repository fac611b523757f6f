"""The sweep response plot's legend names what the plot shows, each kind once."""

from __future__ import annotations

import numpy as np

from gear_dyn.analysis.sweep import RPM
from gear_dyn.plots.sweep import plot_sweep_response
from gear_dyn.scene import load_scene
from gear_dyn.scene.sweep import sweep_scene


def _labels(speeds_rpm: np.ndarray) -> list[str]:
    res = sweep_scene(load_scene("helicopter_tail"), speeds_rpm * RPM, si=True, workers=1)
    fig = plot_sweep_response(res)
    return list(fig.axes[0].get_legend_handles_labels()[1])


def test_legend_without_separation_names_only_the_curve() -> None:
    assert _labels(np.linspace(10000, 12000, 5)) == ["simulated (steady state)"]


def test_legend_with_separation_marks_it_once_and_no_absent_kind() -> None:
    labels = _labels(np.linspace(7000, 8000, 11))  # f_m = f_n at 7599 rpm: the teeth separate
    assert labels.count("teeth separate") == 1
    assert "back-side contact" not in labels  # no backlash in this scene
    assert labels[0] == "simulated (steady state)"
