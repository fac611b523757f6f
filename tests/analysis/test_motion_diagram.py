"""The bifurcation diagram (gear_dyn.analysis.motion.diagram) and its plot.

Checks: the samples do not depend on where the blocks run (serial, another executor, other
block sizes: bit for bit, as the sweep driver promises); the period the samples suggest is the
period shooting confirms (:func:`gear_dyn.analysis.motion.classify_samples`); rows and plot
carry every sample.
"""

from __future__ import annotations

import concurrent.futures as cf
import json

import numpy as np
import pytest
from motion_cases import parametric_scene, speed_of

from gear_dyn.analysis.motion import BifurcationDiagram, DiagramOptions, bifurcation_diagram
from gear_dyn.errors import InputError
from gear_dyn.io import write_csv, write_json
from gear_dyn.scene.sweep import SceneModels

RATIOS = (2.2, 2.24, 2.28, 2.32)
OPTS = DiagramOptions(settle=300, samples=32)


@pytest.fixture(scope="module")
def diagram() -> tuple[SceneModels, list[float], BifurcationDiagram]:
    scene = parametric_scene()
    speeds = [speed_of(scene, r) for r in RATIOS]
    factory = SceneModels.of(scene)
    return factory, speeds, bifurcation_diagram(factory, speeds, options=OPTS, name="case")


def test_same_samples_wherever_the_blocks_run(diagram) -> None:
    factory, speeds, serial = diagram
    assert serial.executor == "serial"
    with cf.ThreadPoolExecutor(2) as ex:
        other = bifurcation_diagram(factory, speeds, options=OPTS, executor=ex, name="case")
    assert other.executor == "ThreadPoolExecutor"
    small = bifurcation_diagram(factory, speeds, options=OPTS, block=1, name="case")
    for res in (other, small):
        for a, b in zip(serial.curves, res.curves, strict=True):
            assert a.direction == b.direction
            assert np.array_equal(a.samples, b.samples)  # bit for bit
            assert np.array_equal(a.period, b.period)


def test_periods_as_shooting_confirms(diagram) -> None:
    _factory, speeds, serial = diagram
    up = serial.curve("up")
    assert up.speed.tolist() == sorted(speeds)
    assert serial.curve("down").speed.tolist() == sorted(speeds, reverse=True)
    assert up.samples.shape == (len(speeds), OPTS.samples, 2)
    # period-2 at 2.2 and 2.24, period-1 beyond, both ways: every period confirmed by shooting
    assert up.period.tolist() == [2, 2, 1, 1]
    assert up.label == ("period-2", "period-2", "period-1", "period-1")
    assert serial.curve("down").period.tolist() == [1, 1, 2, 2]
    assert np.all(np.isnan(up.lyapunov))  # no exponent where an orbit is confirmed
    # the samples of a confirmed orbit are the orbit's: n distinct points repeating exactly
    two = up.samples[0] / np.array([1e-5, 1.0])
    assert np.max(np.abs(two[2:] - two[:-2])) < 1e-9 < np.max(np.abs(two[1:] - two[:-1]))


def test_rows_and_plot_carry_every_sample(diagram, tmp_path) -> None:
    from gear_dyn.plots.bifurcation import plot_bifurcation

    _factory, speeds, res = diagram
    cols = res.columns()
    n = 2 * len(speeds) * OPTS.samples
    assert all(v.size == n for v in cols.values())
    assert set(cols["period"]) <= {1.0, 2.0}
    write_csv(tmp_path / "samples.csv", cols)
    back = np.genfromtxt(tmp_path / "samples.csv", delimiter=",", names=True)
    assert np.array_equal(back["x"], cols["x"])
    write_json(tmp_path / "diagram.json", res.to_dict())
    summary = json.loads((tmp_path / "diagram.json").read_text())
    assert [p["period"] for p in summary["curves"]["up"]] == res.curve("up").period.tolist()
    fig = res.plot()
    ax = fig.axes[0]
    drawn = [line for line in ax.get_lines() if line.get_label().startswith("sweep")]
    assert [line.get_label() for line in drawn] == ["sweep up", "sweep down"]
    assert all(line.get_ydata().size == len(speeds) * OPTS.samples for line in drawn)
    assert np.allclose(np.sort(drawn[0].get_ydata()), np.sort(res.curve("up").samples[:, :, 0]
                                                               .ravel() * 1e6))
    with pytest.raises(InputError, match="state = 'q'"):
        plot_bifurcation(res, state="q")


def test_bad_arguments_are_refused() -> None:
    with pytest.raises(InputError, match="samples"):
        DiagramOptions(samples=8)
    scene = parametric_scene()
    with pytest.raises(InputError, match="direction"):
        bifurcation_diagram(SceneModels.of(scene), [100.0], direction="sideways")


def test_classified_diagram_draws_its_lyapunov_exponents(diagram) -> None:
    """A diagram with Lyapunov exponents gets a second panel: each drawn exponent and error
    bar is the diagram's own, at its speed; a caller's single Axes gets the samples only."""
    import dataclasses

    from matplotlib.figure import Figure

    from gear_dyn.analysis.motion.diagram import RPM
    from gear_dyn.plots.bifurcation import plot_bifurcation

    _factory, speeds, res = diagram
    rng = np.random.default_rng(1)
    curves = []
    for c in res.curves:  # exponents at the first and the last speed only, as classified
        lam = np.full(c.speed.size, np.nan)
        err = np.full(c.speed.size, np.nan)
        lam[[0, -1]], err[[0, -1]] = rng.uniform(100, 1000, 2), rng.uniform(10, 50, 2)
        curves.append(dataclasses.replace(c, lyapunov=lam, lyapunov_error=err))
    classified = dataclasses.replace(res, curves=tuple(curves))
    fig = plot_bifurcation(classified)
    assert len(fig.axes) == 2  # samples, Lyapunov panel
    lower = fig.axes[1]
    assert "Lyapunov" in lower.get_ylabel()
    for c, bars in zip(classified.curves, lower.containers, strict=True):
        line, _caps, (segments,) = bars
        ok = np.isfinite(c.lyapunov)
        assert np.allclose(line.get_xdata(), c.speed[ok] / RPM)
        assert np.allclose(line.get_ydata(), c.lyapunov[ok])
        spans = np.array([seg[:, 1] for seg in segments.get_segments()])
        assert np.allclose(spans[:, 1] - spans[:, 0], 2 * c.lyapunov_error[ok])
    ax = Figure().subplots()
    plot_bifurcation(classified, ax=ax)
    assert len(ax.figure.axes) == 1  # the caller's Axes only
