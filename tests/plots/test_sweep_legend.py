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


def test_legend_without_separation_names_only_the_curve_and_its_peak() -> None:
    # the peak of this range is at its lower end: the dynamic factor falls above resonance
    labels = _labels(np.linspace(10000, 12000, 5))
    assert labels[0] == "K_dyn, simulated"
    assert len(labels) == 2 and labels[1].startswith("peak ")
    assert labels[1].endswith(" at 10000 rpm")


def test_legend_with_separation_marks_it_once_and_no_absent_kind() -> None:
    labels = _labels(np.linspace(7000, 8000, 11))  # f_m = f_n at 7599 rpm: the teeth separate
    # a linear scene: the teeth would separate, the model does not hold there; said once
    assert sum(lab.startswith("F < 0: linear model invalid") for lab in labels) == 1
    assert "teeth separate" not in labels
    assert "back-side contact" not in labels  # no backlash in this scene
    assert sum(lab.startswith("peak ") for lab in labels) == 1
    assert labels[0] == "K_dyn, simulated"
