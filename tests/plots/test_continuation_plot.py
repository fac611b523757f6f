"""The response-curve figure of a continuation (gear_dyn.plots.continuation)."""

from __future__ import annotations

import math

import matplotlib
import numpy as np
import pytest
from matplotlib.figure import Figure

from gear_dyn import SDOFModel, rectangular_stiffness
from gear_dyn.analysis.continuation import continue_orbits, sdof_family

matplotlib.use("Agg")

K = rectangular_stiffness(1.6, 8e5, 1.2e6)
WN = math.sqrt(K.mean)


@pytest.fixture(scope="module")
def branch():
    fam = sdof_family(SDOFModel(1.0, K, 0.05, 1040.0, 100.0, backlash=1e-3), "speed", teeth=20)
    return continue_orbits(fam, 0.84 * WN / 20, 0.9 * WN / 20)


def test_stable_solid_unstable_dashed_folds_labelled_with_their_speed(branch) -> None:
    fig = branch.plot()
    ax = fig.axes[0]
    styles = {line.get_linestyle() for line in ax.lines if len(line.get_xdata()) > 1}
    assert styles == {"-", "--"}
    (fold,) = branch.of_kind("fold")
    texts = [t.get_text() for t in ax.texts]
    assert f"fold {fold.parameter * 60 / (2 * math.pi):.6g} rpm" in texts
    # the solid and dashed curves meet at the fold: the fold's speed lies on both
    xs = [np.asarray(line.get_xdata()) for line in ax.lines if len(line.get_xdata()) > 1]
    rpm = fold.parameter * 60 / (2 * math.pi)
    assert all(x.min() <= rpm * (1 + 1e-6) and x.max() >= rpm * (1 - 1e-3) for x in xs)
    assert ax.get_xlabel() == "pinion speed (rpm)"


def test_draws_into_the_callers_axes_and_refuses_unknown_quantities(branch) -> None:
    fig = Figure()
    ax = fig.subplots()
    assert branch.plot(ax=ax, y="separation") is fig
    assert ax.get_ylabel().startswith("teeth apart")
    with pytest.raises(ValueError, match="y = 'force'"):
        branch.plot(y="force")


def test_stretches_meet_at_the_located_fold(branch) -> None:
    """A stable and an unstable stretch end at the located fold itself (its speed and RMS
    DTE, to rounding: the plot converts rad/s to rpm by its own factor), not at the branch
    point just past it (1e-3 away)."""
    (fold,) = branch.of_kind("fold")
    ax = branch.plot().axes[0]
    at = (fold.parameter * 60 / (2 * math.pi), fold.point.dte_rms * 1e6)
    ends = {}
    for line in ax.lines:
        x, y = np.asarray(line.get_xdata()), np.asarray(line.get_ydata())
        if x.size > 1:
            for i in (0, -1):
                if np.allclose((x[i], y[i]), at, rtol=1e-12, atol=0.0):
                    ends[line.get_linestyle()] = True
    assert ends == {"-": True, "--": True}
