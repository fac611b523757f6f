"""Figures of the slice loaded contact draw into given axes or make their own figure."""

from __future__ import annotations

import math

import numpy as np
from matplotlib.figure import Figure

from gear_dyn.analysis.relief_study import relief_study
from gear_dyn.geometry import GearPair
from gear_dyn.modification.analysis import rule_modifications, slice_cases
from gear_dyn.modification.slice_contact import SliceOptions, slice_contact
from gear_dyn.plots.contact import plot_face_load, plot_relief_study, plot_slice_stiffness

RAIL = GearPair(23, 79, 6e-3, math.radians(20), 70e-3, math.radians(20), x1=0.3, x2=-0.1)
OPTS = SliceOptions(8, 8)


def test_face_load_and_stiffness_plots() -> None:
    fig = Figure()
    axes = fig.subplots(2, 1)
    out = plot_face_load(slice_contact(RAIL, [500.0, 2000.0], options=OPTS), index=1,
                         title="rail", ax=axes)
    assert out is fig and axes[0].collections and axes[1].lines
    cases = slice_cases(RAIL, 2000.0, {"unmodified": None}, options=OPTS)
    own = plot_slice_stiffness(cases)
    assert isinstance(own, Figure) and len(own.axes[0].lines) == 1


def test_relief_study_plot_marks_the_best_design() -> None:
    study = relief_study(RAIL, [500.0, 2000.0], rule_modifications(RAIL, 2000.0), options=OPTS)
    fig = plot_relief_study(study)
    labels = [line.get_label() for line in fig.axes[0].lines]
    assert f"{study.best} (best)" in labels and len(labels) == len(study.names)


def test_relief_study_plot_with_dynamics_marks_the_lowest_peak_force() -> None:
    designs = rule_modifications(RAIL, 2000.0)
    study = relief_study(RAIL, [2000.0], {k: designs[k] for k in ("unmodified", "niemann")},
                         options=OPTS, speeds=[300.0, 400.0])
    fig = Figure()
    axes = fig.subplots(2, 2)
    assert plot_relief_study(study, ax=axes) is fig
    labels = [line.get_label() for line in axes[0, 1].lines]
    assert f"{study.dynamics.best} (lowest peak force)" in labels and len(labels) == 2
    np.testing.assert_allclose(axes[0, 1].lines[0].get_ydata(),
                               study.dynamics.peak_force_ratio[0])
