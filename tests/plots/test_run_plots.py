"""The run's spectrum and time plots show the physics: f_n in range, marks in Hz, noise floor,
sidebands of the eccentric pair, and the DTE's kinematic and elastic parts named apart."""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.figure import Figure

import gear_dyn as gd
from gear_dyn.analysis.report import summarize
from gear_dyn.errors import InputError
from gear_dyn.plots.run import noise_floor, plot_spectrum, plot_time_history, spectrum_marks
from gear_dyn.scene.packaged import packaged_names

#: enough mesh periods for a steady window, few enough for a fast test
PERIODS = 40


@pytest.fixture(scope="module", params=packaged_names())
def result(request: pytest.FixtureRequest) -> gd.Result:
    scene = gd.load_scene(request.param)
    res = gd.run_scene(scene, periods=PERIODS)
    summarize(res)
    return res


def _texts(fig: Figure) -> str:
    return " ".join(t.get_text() for ax in fig.axes for t in ax.texts)


def test_spectrum_range_contains_fn_and_the_harmonic_above(result: gd.Result) -> None:
    marks = spectrum_marks(result)
    assert marks.natural is not None  # every example scene's model states its f_n
    fig = plot_spectrum(result)
    lo, hi = fig.axes[0].get_xlim()
    assert lo <= marks.natural <= hi
    assert hi >= marks.top_harmonic * marks.mesh > marks.natural
    text = _texts(fig)
    assert f"f_n = {marks.natural:.0f} Hz" in text
    assert f"1f_m\n{marks.mesh:.0f} Hz" in text
    assert "Hann window" in fig.axes[0].get_title()
    assert all(ax.get_xlabel() or ax.get_ylabel() for ax in fig.axes)


def test_eccentric_spectrum_labels_shafts_and_sidebands() -> None:
    res = gd.run_scene(gd.load_scene("eccentric_helical"), periods=PERIODS)
    marks = spectrum_marks(res)
    assert [n for n, _ in marks.shafts] == ["f1", "f2"]
    assert marks.shafts[0][1] == pytest.approx(25.0) and marks.shafts[1][1] == pytest.approx(
        1500 / 60 * 18 / 70)
    fig = plot_spectrum(res)
    assert len(fig.axes) == 2
    text = _texts(fig)
    for label in ("f1 = 25 Hz", "f_m-f1\n425.0 Hz", "f_m+f1\n475.0 Hz", "f_m+f2\n456.4 Hz"):
        assert label in text
    fig = plot_time_history(res, periods=None)
    labels = [t.get_text() for ax in fig.axes for t in ax.get_legend().get_texts()]
    assert "kinematic part -e_ecc (eccentricity)" in labels
    assert "elastic part delta (mesh deflection)" in labels
    # the parts add up to the DTE (no transmission error in this scene)
    o = res.outputs
    np.testing.assert_allclose(-o["e_ecc"] + o["delta"], o["dte"], rtol=0, atol=1e-15)


def test_noise_floor_is_the_stated_error(result: gd.Result) -> None:
    est = result.extra["estimated_error"]["max_rel"]
    k_m = float(np.mean(result.outputs["stiffness"][result.steady]))
    assert noise_floor(result) == pytest.approx(est * result.static_load / k_m, rel=1e-12)


def test_linear_scale_and_own_axes() -> None:
    res = gd.run_scene(gd.load_scene("helicopter_tail"), periods=PERIODS)
    fig = Figure()
    ax = fig.subplots()
    assert plot_spectrum(res, ax=ax, scale="linear") is fig
    assert ax.get_yscale() == "linear" and ax.get_ylim()[0] == 0
    with pytest.raises(InputError, match="scale"):
        plot_spectrum(res, scale="dB")
