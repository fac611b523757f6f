"""Design comparison from sweeps built by hand: ranking by peak force, deltas, flags, exports,
and the named peaks of a sweep."""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pytest

from gear_dyn.analysis.compare import COMPARED, FLAGS, compare_sweeps
from gear_dyn.analysis.sweep import RPM, SweepCurve, SweepOptions, SweepResult
from gear_dyn.errors import InputError
from gear_dyn.solvers import SolverSettings

RPM_GRID = np.array([1000.0, 2000.0, 3000.0, 4000.0, 5000.0])


def _curve(force: Sequence[float] | np.ndarray, separation: Sequence[float] | None = None,
           direction: str = "up", jump: float = 1.0, rms: Sequence[float] | None = None,
           rpm: np.ndarray = RPM_GRID) -> SweepCurve:
    """A curve of F_max / W ``force`` over ``rpm`` (in sweep order: reversed for ``down``)."""
    n = rpm.size
    speed = (rpm if direction == "up" else rpm[::-1]) * RPM
    f = np.asarray(force, dtype=float)
    return SweepCurve(
        direction=direction, speed=speed, mesh_frequency=speed * 23 / (2 * np.pi),
        dynamic_factor=f / jump, peak_force_ratio=f,
        rms_dte=np.asarray(rms if rms is not None else 1e-6 * f, dtype=float),
        ptp_dte=3e-6 * f, mean_dte=np.full(n, 1e-5), spectral_radius=np.full(n, 0.5),
        stable=np.ones(n, bool), periodic=np.ones(n, bool), status=("periodic",) * n,
        separation=np.asarray(separation if separation is not None else np.zeros(n), float),
        backside=np.zeros(n), iterations=np.ones(n, int), spectrum=np.zeros((n, 1)),
        state=np.zeros((n, 2)), orbit_periods=np.ones(n, int))


def _result(*curves: SweepCurve, jump: float = 1.0, nonlinear: bool = False,
            name: str = "d") -> SweepResult:
    return SweepResult(name, tuple(curves), np.array([1.0]), 1000.0, 1e4, nonlinear,
                       SweepOptions(), SolverSettings(), 0.0, "serial",
                       quasi_static={"peak_force_ratio": jump})


def test_ranking_follows_the_peak_force_not_k_dyn() -> None:
    # the case of six tip reliefs of one pair: no relief F/W 3.31 with a stiffness-jump
    # factor 1.68 (K_dyn 1.97), a relief F/W 2.55 with factor 1.2 (K_dyn 2.125): by K_dyn the
    # relief looks worse; by the force the teeth carry it is 23 % better
    plain = _result(_curve([1.2, 2.0, 3.31, 2.5, 1.8], jump=1.68), jump=1.68)
    relief = _result(_curve([1.1, 1.6, 2.55, 2.0, 1.5], jump=1.2), jump=1.2)
    cmp = compare_sweeps([plain, relief], ["plain", "relief"], [3000 * RPM, 3000 * RPM])
    assert cmp.ranking == ("relief", "plain")
    by = {r["scene"]: r for r in cmp.designs}
    assert by["relief"]["peak_dynamic_factor"] > by["plain"]["peak_dynamic_factor"]
    assert by["relief"]["rank"] == 1 and by["plain"]["rank"] == 2
    assert by["relief"]["peak_peak_force_ratio_delta_pct"] == pytest.approx(
        100 * (2.55 / 3.31 - 1), rel=1e-12)
    assert by["relief"]["peak_peak_force_ratio_speed_rpm"] == pytest.approx(3000.0)
    assert by["plain"]["dynamic_factor_at_peak_force"] == pytest.approx(3.31 / 1.68)


def test_deltas_are_the_arithmetic_of_the_values() -> None:
    sweeps = [_result(_curve(f, rms=r), jump=j)
              for f, r, j in (([1.2, 2.0, 3.0, 2.0, 1.5], [1, 2, 5, 3, 2], 1.5),
                              ([1.1, 1.8, 2.5, 2.2, 1.4], [1, 3, 4, 6, 2], 1.2),
                              ([1.3, 2.6, 4.1, 2.8, 1.6], [2, 2, 3, 2, 1], 1.7))]
    stress = [1.0e9, 0.9e9, 1.1e9]
    cmp = compare_sweeps(sweeps, ["a", "b", "c"], [2000 * RPM, 4000 * RPM, 3000 * RPM],
                         static_stress=stress)
    base = cmp.designs[0]
    for r in cmp.designs:
        for key in COMPARED:
            assert r[f"{key}_delta"] == pytest.approx(r[key] - base[key], rel=1e-14, abs=0)
            assert r[f"{key}_delta_pct"] == pytest.approx(100 * (r[key] / base[key] - 1),
                                                          rel=1e-12, abs=1e-12)
    assert all(base[f"{k}_delta"] == 0 for k in COMPARED)
    # the values at each design's own operating speed
    assert [r["operating_peak_force_ratio"] for r in cmp.designs] == [2.0, 2.2, 4.1]
    assert [r["operating_rms_dte_m"] for r in cmp.designs] == [2.0, 6.0, 3.0]
    # ranks by RMS DTE and by contact stress, each on its own figure
    assert [r["rank_rms_dte"] for r in cmp.designs] == [2, 3, 1]  # peaks 5, 6, 3 um
    # contact stress: the quasi-static peak times sqrt(K_dyn) (sigma_H ~ sqrt(F))
    for r, s, sw in zip(cmp.designs, stress, sweeps, strict=True):
        k = sw.peak().value
        assert r["peak_contact_stress_pa"] == pytest.approx(s * math.sqrt(k), rel=1e-14)
    order = sorted(range(3), key=lambda i: cmp.designs[i]["peak_contact_stress_pa"])
    assert [cmp.designs[i]["rank_contact_stress"] for i in order] == [1, 2, 3]


def test_flag_peak_at_an_end_of_the_range() -> None:
    rising = _result(_curve([1.0, 1.2, 1.5, 2.0, 2.8]))
    inside = _result(_curve([1.0, 1.5, 2.5, 1.5, 1.2]))
    # a backlash sweep whose larger peak is the down curve's first speed (the top of the range)
    down_top = _result(_curve([1.0, 1.5, 2.0, 1.5, 1.2]),
                       _curve([3.0, 1.4, 1.3, 1.1, 1.0], direction="down"), nonlinear=True)
    cmp = compare_sweeps([inside, rising, down_top], ["inside", "rising", "down_top"],
                         [3000 * RPM] * 3)
    flags = {r["scene"]: r["flags"] for r in cmp.designs}
    assert flags == {"inside": [], "rising": ["peak_at_range_end"],
                     "down_top": ["peak_at_range_end"]}
    assert any("rising: " + FLAGS["peak_at_range_end"] == w for w in cmp.warnings)


def test_flag_a_linear_model_invalid_at_its_peak() -> None:
    sep = [0.0, 0.0, 0.3, 0.0, 0.0]
    linear = _result(_curve([1.0, 1.5, 2.5, 1.5, 1.2], separation=sep))
    backlash = _result(_curve([1.0, 1.5, 2.5, 1.5, 1.2], separation=sep), nonlinear=True)
    elsewhere = _result(_curve([1.0, 1.5, 2.5, 1.5, 1.2], separation=[0, 0.1, 0, 0, 0]))
    cmp = compare_sweeps([linear, backlash, elsewhere], ["linear", "backlash", "elsewhere"],
                         [3000 * RPM] * 3)
    flags = {r["scene"]: r["flags"] for r in cmp.designs}
    assert flags == {"linear": ["linear_model_invalid_at_peak"],
                     "backlash": ["teeth_separate_at_peak"],
                     "elsewhere": ["linear_model_invalid_in_range"]}


def test_operating_speed_off_the_grid_is_read_from_its_own_sweep() -> None:
    main = _result(_curve([1.0, 1.5, 2.5, 1.5, 1.2]))
    one = _result(_curve([1.33], rpm=np.array([6500.0])))
    cmp = compare_sweeps([main], ["a"], [6500 * RPM], operating=[one])
    row = cmp.designs[0]
    assert row["operating_peak_force_ratio"] == 1.33
    assert row["flags"] == ["operating_speed_outside_range"]
    # without a sweep that holds it, the value is not known
    assert math.isnan(compare_sweeps([main], ["a"], [6500 * RPM]).designs[0][
        "operating_peak_force_ratio"])


def test_exports_hold_the_rows_in_rank_order(tmp_path: Path) -> None:
    a = _result(_curve([1.0, 1.5, 3.0, 1.5, 1.2]))
    b = _result(_curve([1.0, 1.4, 2.0, 1.5, 1.2], separation=[0, 0, 0.2, 0, 0]))
    cmp = compare_sweeps([a, b], ["a", "b"], [3000 * RPM] * 2)
    data = cmp.to_dict()
    assert data["baseline"] == "a" and data["ranking"] == ["b", "a"]
    assert data["flags"] == {"linear_model_invalid_at_peak":
                             FLAGS["linear_model_invalid_at_peak"]}
    assert "does not rank designs" in data["definitions"]["dynamic_factor"]
    with open(cmp.to_csv(tmp_path / "c.csv"), newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["scene"] for r in rows] == ["b", "a"]
    assert rows[0]["flags"] == "linear_model_invalid_at_peak"
    assert float(rows[0]["peak_peak_force_ratio_delta_pct"]) == pytest.approx(
        100 * (2.0 / 3.0 - 1))
    with pytest.raises(InputError, match="unique"):
        compare_sweeps([a, b], ["a", "a"], [1.0, 1.0])


def test_figure_of_six_designs_is_readable(tmp_path: Path) -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    rng = np.random.default_rng(1)
    sweeps = [_result(_curve(1 + 3 * rng.random(5)), _curve(1 + 3 * rng.random(5),
                                                            direction="down"),
                      nonlinear=True) for _ in range(7)]
    names = [f"a long design name number {i}" for i in range(7)]
    cmp = compare_sweeps(sweeps, names, [3000 * RPM] * 7)
    fig = cmp.plot()
    FigureCanvasAgg(fig)
    fig.canvas.draw()
    legend = fig.legends[0]
    assert len(legend.get_texts()) == 7  # one entry per design, up and down in one
    styles = {(line.get_color(), line.get_linestyle()) for line in legend.get_lines()}
    assert len(styles) == 7
    renderer = fig.canvas.get_renderer()
    box = fig.bbox
    for text in (fig._suptitle, *legend.get_texts()):
        b = text.get_window_extent(renderer)
        assert box.x0 <= b.x0 and b.x1 <= box.x1 and box.y0 <= b.y0 and b.y1 <= box.y1
    bars = fig.axes[2]
    assert len(bars.patches) == 7 and len(bars.get_yticklabels()) == 7


def test_peak_is_a_named_result_that_unpacks_as_before() -> None:
    res = _result(_curve([1.0, 1.5, 2.5, 1.5, 1.2], jump=1.25, rms=[1, 2, 3, 7, 1]),
                  jump=1.25)
    value, speed, direction = res.peak()
    assert (value, direction) == (2.0, "up") and speed == pytest.approx(3000 * RPM)
    p = res.peak("rms_dte")
    assert p.value == 7.0 and p.speed_rpm == pytest.approx(4000.0)
    assert p.row("rms_dte")["unit"] == "m"
    assert res.peak("peak_force_ratio").value == 2.5
    with pytest.raises(InputError, match="peak quantity"):
        res.peak("force")
    empty = _result(_curve([math.nan] * 5))
    assert math.isnan(empty.peak().value) and empty.peak().direction == ""


def test_plot_draws_into_the_callers_axes() -> None:
    from matplotlib.figure import Figure

    cmp = compare_sweeps([_result(_curve([1.0, 1.5, 2.5, 1.5, 1.2]))], ["a"], [3000 * RPM])
    fig = Figure()
    axes = fig.subplots(3, 1)
    assert cmp.plot(ax=axes) is fig
    assert len(axes[0].get_lines()) >= 1 and len(axes[2].patches) == 1
    with pytest.raises(ValueError, match="expected 3 matplotlib Axes"):
        cmp.plot(ax=axes[:2])
