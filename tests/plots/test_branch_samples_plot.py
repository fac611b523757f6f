"""The continuation's bifurcation diagram: the orbits' stroboscopic samples
(gear_dyn.analysis.continuation.strobe) and their figure (gear_dyn.plots.bifurcation.
plot_branch_samples), checked on the artists, not the pixels.

The test model is tests/analysis/test_continuation.py's: m = 1 kg, rectangular mesh stiffness
(contact ratio 1.6, 0.8e6 / 1.2e6 N/m), half gap 1 mm, 0.3 mm static deflection, 20 teeth; over
f_m / f_n = 1.8..2.0 its period-1 orbit doubles its period in full contact and the period-2
branch is switched to there.
"""

from __future__ import annotations

import math

import matplotlib
import numpy as np
import pytest
from matplotlib.figure import Figure

from gear_dyn import InputError, SDOFModel, rectangular_stiffness
from gear_dyn.analysis.continuation import (
    ContinuationSettings,
    branch_samples,
    continue_orbits,
    sdof_family,
)
from gear_dyn.analysis.motion import DiagramOptions, bifurcation_diagram
from gear_dyn.plots.bifurcation import plot_branch_samples
from gear_dyn.solvers.contact_exact import flow_with_sensitivity

matplotlib.use("Agg")

K = rectangular_stiffness(1.6, 8e5, 1.2e6)
WN = math.sqrt(K.mean)
RPM = 2 * math.pi / 60
FAMILY = sdof_family(SDOFModel(1.0, K, 0.05, 300.0, 100.0, backlash=1e-3), "speed", teeth=20)


@pytest.fixture(scope="module")
def samples():
    br = continue_orbits(FAMILY, 1.8 * WN / 20, 2.0 * WN / 20, doublings=1,
                         settings=ContinuationSettings(max_points=60))
    return branch_samples(br, FAMILY)


def _lines(fig: Figure, label: str) -> list:
    """Lines of the figure's axes whose legend entry (first of a group) starts ``label``,
    with the unlabelled lines drawn after it in the same colour and style."""
    ax = fig.axes[0]
    out, on = [], False
    for line in ax.lines:
        text = line.get_label()
        if text.startswith(label):
            out.append(line)
            on = True
        elif on and text.startswith("_"):
            out.append(line)
        else:
            on = False
    return out


def test_a_period1_stable_sample_is_the_orbits_start_state(samples) -> None:
    """Period 1: one sample per point, the orbit's own start state, no run needed; the
    stable stretch is drawn solid at exactly those states (um against rpm)."""
    c0 = samples.curves[0]
    assert c0.branch.periods == 1
    assert c0.samples.shape == (len(c0.branch.points), 1, 2)
    for p, s in zip(c0.branch.points, c0.samples, strict=True):
        assert np.array_equal(s[0], p.state)  # the stored state itself
    fig = samples.plot()
    (line,) = _lines(fig, "period-1 stable")
    assert line.get_linestyle() == "-"
    # the stable stretch: the stable points in branch order, then the located period
    # doubling where it ends; the same numbers, scaled for display only
    (pd,) = c0.branch.of_kind("period_doubling")
    stable = [p for p in c0.branch.points if p.stable]
    assert all(p.arclength < pd.point.arclength for p in stable)
    want = [*stable, pd.point]
    np.testing.assert_allclose(line.get_xdata(), [p.parameter / RPM for p in want],
                               rtol=1e-15)
    np.testing.assert_allclose(line.get_ydata(), [p.state[0] * 1e6 for p in want],
                               rtol=1e-15)
    # the unstable stretch starts at the doubling: the two meet there, not at a point
    (dashed,) = _lines(fig, "period-1 unstable")
    assert dashed.get_linestyle() == "--"
    assert np.asarray(dashed.get_xdata())[0] == np.asarray(line.get_xdata())[-1]


def test_a_period2_branch_has_two_samples_the_map_sends_to_each_other(samples) -> None:
    """Period 2: two samples per speed, y(0) and y(T_m); one mesh period of the exact flow
    (flow_with_sensitivity, not the sampler's propagator) sends each to the other, to the
    shooting tolerance (1e-10 scaled, times the map's amplification: 1e-7 of the state
    scale is far outside it), and away from the doubling they are two distinct states."""
    (c2,) = [c for c in samples.curves if c.branch.periods == 2]
    assert c2.samples.shape == (len(c2.branch.points), 2, 2)
    apart = 0
    for p, s in zip(c2.branch.points, c2.samples, strict=True):
        model = FAMILY(p.parameter)
        scale = model.state_scale
        a, _ = flow_with_sensitivity(model, s[0], 1.0 / model.mesh_frequency)
        b, _ = flow_with_sensitivity(model, s[1], 1.0 / model.mesh_frequency)
        assert np.all(np.abs(a - s[1]) <= 1e-7 * scale)
        assert np.all(np.abs(b - s[0]) <= 1e-7 * scale)
        apart += bool(np.max(np.abs(s[1] - s[0]) / scale) > 1e-4)
    assert apart >= len(c2.branch.points) - 1  # all but the point at the doubling itself
    assert samples.n_maps == len(c2.branch.points) + len(c2.marks)  # one run per orbit

    fig = samples.plot()
    red = [ln for ln in fig.axes[0].lines if ln.get_color() == "tab:red"]
    # every stretch of the period-2 branch draws two curves over the same speeds
    groups: dict[tuple[float, ...], list[np.ndarray]] = {}
    for ln in red:
        groups.setdefault(tuple(np.asarray(ln.get_xdata())), []).append(
            np.asarray(ln.get_ydata()))
    assert groups and all(len(ys) == 2 for ys in groups.values())
    allx = np.concatenate([np.asarray(k) for k in groups])
    assert set(np.round(allx, 9)) == set(np.round(c2.parameter / RPM, 9))


def test_period_doubling_marked_on_its_sample_and_labelled(samples) -> None:
    (pd,) = samples.curves[0].branch.of_kind("period_doubling")
    fig = samples.plot()
    ax = fig.axes[0]
    (mark,) = [ln for ln in ax.lines if ln.get_marker() == "s"]
    assert mark.get_label() == "period doubling"
    assert np.asarray(mark.get_xdata())[0] == pytest.approx(pd.parameter / RPM, rel=1e-15)
    assert np.asarray(mark.get_ydata())[0] == pytest.approx(pd.point.state[0] * 1e6,
                                                             rel=1e-15)
    assert f"PD {pd.parameter / RPM:.6g} rpm" in [t.get_text() for t in ax.texts]
    assert {ln.get_linestyle() for ln in ax.lines if len(ln.get_xdata()) > 1} == {"-", "--"}
    assert ax.get_xlabel() == "pinion speed (rpm)"
    assert ax.get_ylabel() == "x at t = k T_m (µm)"


def test_brute_force_diagram_behind_the_branch_agrees_with_a_stable_orbit(samples) -> None:
    """The brute-force diagram is drawn in small grey dots, every sample of both directions;
    at the speed of a stable period-1 point the diagram settles on that same orbit (its
    samples confirmed by shooting), to 1e-8 of the state scale."""
    c0 = samples.curves[0]
    p = next(q for q in c0.branch.points if q.stable)
    speeds = [p.parameter, 1.9 * WN / 20, 1.95 * WN / 20]
    diag = bifurcation_diagram(FAMILY, speeds, options=DiagramOptions(settle=50, samples=32))
    fig = Figure()
    ax = fig.subplots()
    assert plot_branch_samples(samples, ax=ax, diagram=diag, state="v") is fig
    (dots,) = [ln for ln in ax.lines if ln.get_label().startswith("brute force")]
    assert dots.get_color() == "0.6" and dots.get_linestyle() == "None"
    assert len(dots.get_xdata()) == 2 * 3 * 32  # two directions, three speeds, 32 samples
    assert ax.get_ylabel() == "v at t = k T_m (m/s)"
    scale = FAMILY(p.parameter).state_scale
    for c in diag.curves:
        i = int(np.argmin(np.abs(c.speed - p.parameter)))
        assert c.period[i] == 1
        assert np.all(np.abs(c.samples[i] - p.state) <= 1e-8 * scale)


def test_bad_state_and_a_diagram_over_another_parameter_are_refused(samples) -> None:
    with pytest.raises(InputError, match="state = 'a'"):
        plot_branch_samples(samples, state="a")
    by_torque = sdof_family(FAMILY(1.85 * WN / 20), "torque", base_radius=0.05)
    tb = continue_orbits(by_torque, 15.0, 16.0, parameter="torque",
                         settings=ContinuationSettings(max_points=3))
    torque = branch_samples(tb, by_torque)
    assert torque.curves[0].samples.shape[1] == 1
    diag = bifurcation_diagram(FAMILY, [1.85 * WN / 20], options=DiagramOptions(settle=1,
                                                                                 samples=32))
    with pytest.raises(InputError, match="diagram: a brute-force diagram is over speed"):
        plot_branch_samples(torque, diagram=diag)
    with pytest.raises(InputError, match="rtol"):
        branch_samples(tb, FAMILY, rtol=1.0)


@pytest.mark.slow
def test_period2_samples_on_the_variational_route() -> None:
    """(Slow: about 15 s.) The constant-stiffness scene of issue 25 (1e9 N/m, 10 um
    transmission error) at f_m / f_n = 1.24, where a stable period-2 orbit exists
    (docs/motion.md), continued on the variational route (asked for: the exact flow applies
    too); its samples come from the exact flow; DOP853 at rtol 1e-12 takes the second back to
    the first over one
    mesh period, to 1e-6 of the state scale (the orbit closes to 1e-10 scaled; 1e-6 leaves
    1e4 times the integration tolerance for the error carried along the period), and the
    two samples are distinct states."""
    import tomllib

    import gear_dyn as gd
    from gear_dyn.analysis.stability import flow_on_grid
    from gear_dyn.scene.packaged import scene_path
    from gear_dyn.scene.sweep import SceneModels

    data = tomllib.loads(scene_path("helicopter_tail_backlash").read_text())
    data["stiffness"] = {"method": "rectangular", "single": "1e9 N/m", "double": "1e9 N/m"}
    data["transmission_error"] = {"cos": ["10 um"]}
    fam = SceneModels.of(gd.parse_scene(data, "const_te.toml"))
    probe = fam(1000.0)
    speed = 1.24 * probe.natural_frequency * 1000.0 / probe.mesh_frequency  # f_m ~ speed
    model = fam(speed)
    motion = gd.classify_motion(model, model.initial_state(), settle=60, samples=32)
    assert motion.period == 2
    br = continue_orbits(fam, speed, 1.005 * speed, periods=2, y_guess=motion.state,
                         doublings=0, settings=ContinuationSettings(max_points=2),
                         route="variational")
    assert br.route == "variational"
    c = branch_samples(br, fam).curves[0]
    for p, s in zip(br.points, c.samples, strict=True):
        m = fam(p.parameter)
        back = flow_on_grid(m, s[1], np.array([0.0, 1.0 / m.mesh_frequency]), rtol=1e-12)
        assert np.all(np.abs(back[:, -1] - s[0]) <= 1e-6 * m.state_scale)
        assert np.max(np.abs(s[1] - s[0]) / m.state_scale) > 0.1


def test_samples_habit_json_rows_csv(samples, tmp_path) -> None:
    """to_dict survives json.dumps with every branch's period and marks; rows() carry every
    sample (the period-2 child two per point) and are the rows of to_csv's file."""
    import csv
    import json

    d = json.loads(json.dumps(samples.to_dict()))
    assert [b["periods"] for b in d["branches"]] == [c.branch.periods for c in samples.curves]
    rows = samples.rows()
    assert len(rows) == sum(c.samples.shape[0] * c.samples.shape[1] for c in samples.curves)
    assert [r["state_0"] for r in rows if r["branch"] == 1] == (
        samples.curves[1].samples[:, :, 0].ravel().tolist())
    back = list(csv.DictReader(samples.to_csv(tmp_path / "s.csv").read_text().splitlines()))
    assert [float(b["state_1"]) for b in back] == [r["state_1"] for r in rows]
