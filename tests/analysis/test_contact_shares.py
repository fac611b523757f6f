"""Contact shares (teeth apart, back flank) have one home,
gear_dyn.analysis.stability.contact_states / contact_shares, used by the sweep's rows, the
continuation's orbit shapes and the run report.

Second method: the exact orbit sampled densely (DENSE samples per mesh period; the closed-form
propagator for the pair with backlash, the exact piece maps for the linear pair), the flank
separation's (or the mesh force's) sign changes located by linear interpolation between
samples, and the shares summed from those crossing times. Linear interpolation misplaces a
crossing by at most dt^2 max|u''| / (8 min|u'|) at the crossing; with dt = T / DENSE that is
below 1e-9 T here, so the reference is good to far better than the tolerances below.

Tolerances, from how each figure is measured:
- the continuation's exact route sums the spells between the located contact changes (event
  times found to rounding): ``EXACT_TOL``, the reference's own error with margin;
- sampled figures (the sweep: ``samples_per_period`` per period; the continuation's variational
  route: SAMPLES_PER_PERIOD) count samples, so each crossing can move one sample from one state
  to the other: at most ``crossings / samples`` of the period.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gear_dyn.analysis.continuation import orbit as corbit
from gear_dyn.analysis.stability import (
    contact_shares,
    contact_states,
    periodic_steady_state,
    shoot,
)
from gear_dyn.analysis.sweep import SweepOptions
from gear_dyn.analysis.sweep.batch import linear_block
from gear_dyn.analysis.sweep.points import steady_point
from gear_dyn.models.sdof import SDOFModel
from gear_dyn.scene import load_scene
from gear_dyn.scene.sweep import model_at_speed
from gear_dyn.solvers import SolverSettings
from gear_dyn.solvers.contact_exact import propagate_contact_exact
from gear_dyn.solvers.exact import propagate_pieces

SCENES = Path(__file__).resolve().parents[2] / "gear_dyn" / "scenes"
DENSE = 100_000
EXACT_TOL = 1e-7
RPM = 2 * np.pi / 60
#: the constant-stiffness pair with backlash at this speed: a period-1 orbit with a gap and a
#: back-flank contact in every mesh period
BACKLASH_RPM = 5500.0


def at_rpm(name: str, rpm: float) -> SDOFModel:
    model = model_at_speed(load_scene(SCENES / f"{name}.toml"), rpm * RPM)
    assert isinstance(model, SDOFModel)
    return model


def crossings(t: np.ndarray, g: np.ndarray) -> np.ndarray:
    """Times where ``g`` changes sign, by linear interpolation between samples."""
    i = np.flatnonzero(np.signbit(g[1:]) != np.signbit(g[:-1]))
    return t[i] - g[i] * (t[i + 1] - t[i]) / (g[i + 1] - g[i])


def share_below(t: np.ndarray, g: np.ndarray) -> tuple[float, int]:
    """Share of [t0, t1] where ``g < 0`` from its located sign changes, and their number."""
    tc = crossings(t, g)
    edges = np.concatenate([[t[0]], tc, [t[-1]]])
    mids = 0.5 * (edges[:-1] + edges[1:])
    below = np.interp(mids, t, g) < 0
    return float(np.sum(np.diff(edges)[below]) / (t[-1] - t[0])), tc.size


@pytest.fixture(scope="module")
def backlash_orbit() -> tuple[SDOFModel, np.ndarray]:
    """The constant-stiffness pair with backlash at BACKLASH_RPM, its orbit by shooting from
    a settled state."""
    model = at_rpm("backlash_constant_stiffness", BACKLASH_RPM)
    settled = propagate_contact_exact(model, np.linspace(0.0, 300 / model.mesh_frequency,
                                                         301))[0][:, -1]
    sol = shoot(model, settled, 1e-11)
    assert sol.converged and sol.stable
    return model, sol.y0


def dense_backlash_shares(model: SDOFModel, y0: np.ndarray) -> tuple[float, float, int]:
    """Gap and back-flank shares of the orbit from the sign changes of u - b and u + b."""
    t1 = 1.0 / model.mesh_frequency
    t = np.linspace(0.0, t1, DENSE + 1)
    x = propagate_contact_exact(model, t, y0=y0)[0][0]
    u = x if model.transmission_error is None else x - model.transmission_error.value(
        model.phase(t))
    b = float(model.backlash)
    not_drive, n1 = share_below(t, u - b)    # u <= b: gap or back flank
    back, n2 = share_below(t, u + b)          # u < -b: back flank
    return not_drive - back, back, n1 + n2


def test_backlash_shares_agree_with_the_dense_orbit(
        backlash_orbit: tuple[SDOFModel, np.ndarray]) -> None:
    model, y0 = backlash_orbit
    sep_ref, back_ref, n_cross = dense_backlash_shares(model, y0)
    assert sep_ref > 0.05 and back_ref > 0.05 and n_cross >= 4  # gap and back flank

    exact = corbit.orbit_shape(model, y0, 1, "exact", 1e-10)
    assert abs(exact.separation - sep_ref) <= EXACT_TOL
    assert abs(exact.back - back_ref) <= EXACT_TOL

    variational = corbit.orbit_shape(model, y0, 1, "variational", 1e-10)
    tol = n_cross / corbit.SAMPLES_PER_PERIOD
    assert abs(variational.separation - sep_ref) <= tol
    assert abs(variational.back - back_ref) <= tol

    settings = SolverSettings(rtol=1e-10)
    point, _ = steady_point(model, BACKLASH_RPM * RPM, settings, SweepOptions(), y0)
    assert point.orbit is not None and point.orbit_periods == 1
    tol = n_cross / settings.samples_per_period
    assert abs(point.separation - sep_ref) <= tol
    assert abs(point.backside - back_ref) <= tol
    # the row reads the shares of its orbit: one place
    assert point.separation == point.orbit.separation and point.backside == point.orbit.back


def test_sampled_shares_are_the_sample_counts(
        backlash_orbit: tuple[SDOFModel, np.ndarray]) -> None:
    """On samples, the shares are the counts of ``|u| <= b`` and ``u < -b`` (the sweep's and
    the run report's rule before it had one home), bit for bit."""
    model, y0 = backlash_orbit
    t = np.linspace(0.0, 1.0 / model.mesh_frequency, 513)[:-1]
    y = propagate_contact_exact(model, t, y0=y0)[0]
    u = y[0] if model.transmission_error is None else y[0] - model.transmission_error.value(
        model.phase(t))
    b = float(model.backlash)
    assert contact_shares(contact_states(model, t, y)) == (
        float(np.mean(np.abs(u) <= b)), float(np.mean(u < -b)))


def test_linear_shares_are_the_negative_force_share() -> None:
    """Without backlash the teeth "part" where the linear model's mesh force is negative: the
    sweep row (per-speed and block paths) and the continuation's shape give that share."""
    rpm = 7000.0
    model = at_rpm("helicopter_tail", rpm)
    assert model.backlash is None
    sol = periodic_steady_state(model, rtol=1e-12)
    t1 = 1.0 / model.mesh_frequency
    t = np.linspace(0.0, t1, DENSE + 1)
    segments = model.linear_segments(0.0, t1)
    assert segments is not None  # piecewise-constant stiffness: exact piece maps
    y = propagate_pieces(segments, t, sol.y0)[0]
    ref, n_cross = share_below(t, model.outputs(t, y)["mesh_force"])
    assert ref > 0.01 and n_cross >= 2  # the force goes negative here

    settings = SolverSettings(rtol=1e-10)
    tol = n_cross / settings.samples_per_period
    point, _ = steady_point(model, rpm * RPM, settings, SweepOptions(), None)
    (block,) = linear_block([model], [rpm * RPM], settings, SweepOptions()) or [None]
    assert block is not None
    for p in (point, block):
        assert abs(p.separation - ref) <= tol and p.backside == 0.0
        assert p.orbit is not None and p.separation == p.orbit.separation
    shape = corbit.orbit_shape(model, sol.y0, 1, "variational", 1e-10)
    assert abs(shape.separation - ref) <= n_cross / corbit.SAMPLES_PER_PERIOD
    assert shape.pattern == "DGD"
