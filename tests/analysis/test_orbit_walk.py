"""The exact walk kept from a shooting evaluation (gear_dyn.solvers.contact_exact.walk, the
third item of gear_dyn.analysis.continuation.orbit.period_map) gives the same orbit shape as a
fresh propagation, bit for bit, and the same map and monodromy matrix as
flow_with_sensitivity.

Second method: fresh runs of propagate_contact_exact from the same start state, on the sample
grid and, for spells shorter than a sample step, on the spells' midpoints (the way orbit_shape
read them before it kept the walk). Equality is exact: the same closed form of the same pieces
evaluated at the same times. Cases: the packaged backlash scene settled on its upper branch at
6400 rpm (teeth apart for part of each period) and a start kicked onto the back flank at
3319 rpm; with the default samples and with two samples per period (every spell then shorter
than a sample step, so every state comes from the midpoints).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from gear_dyn.analysis.continuation import orbit
from gear_dyn.analysis.stability import CONTACT_LETTERS
from gear_dyn.errors import InputError
from gear_dyn.models.sdof import SDOFModel
from gear_dyn.scene import build_plan, load_scene
from gear_dyn.solvers.contact_exact import flow_with_sensitivity, propagate_contact_exact

BACKLASH = Path(__file__).resolve().parents[2] / "gear_dyn" / "scenes" / \
    "helicopter_tail_backlash.toml"


def at_rpm(model: SDOFModel, rpm: float) -> SDOFModel:
    return dataclasses.replace(model, mesh_frequency=23 * rpm / 60)


@pytest.fixture(scope="module")
def cases() -> dict[str, tuple[SDOFModel, np.ndarray, int]]:
    base = build_plan(load_scene(BACKLASH)).model
    assert isinstance(base, SDOFModel)
    hi = at_rpm(base, 6400.0)
    settled = propagate_contact_exact(hi, np.linspace(0.0, 300 / hi.mesh_frequency, 301)
                                      )[0][:, -1]
    low = at_rpm(base, 3319.0)
    kick = low.initial_state() + np.array([0.0, -4 * low.state_scale[1]])
    return {"upper": (hi, settled, 1), "kick": (low, kick, 2)}


def fresh_pattern(model: SDOFModel, y0: np.ndarray, periods: int, samples: int
                  ) -> tuple[str, float, float, float]:
    """Pattern, gap share, back-flank share and RMS of x by fresh propagations."""
    t1 = periods / model.mesh_frequency
    t = np.linspace(0.0, t1, periods * samples + 1)
    y, st = propagate_contact_exact(model, t, y0=y0)
    ev = st["event_times"][(st["event_times"] > 0.0) & (st["event_times"] < t1)]
    edges = np.concatenate([[0.0], ev, [t1]])
    mids = 0.5 * (edges[:-1] + edges[1:])
    ym, _ = propagate_contact_exact(model, np.concatenate([[0.0], mids]), y0=y0)
    b = float(model.backlash)
    states = np.where(ym[0, 1:] > b, 1, np.where(ym[0, 1:] < -b, -1, 0))
    dur = np.diff(edges)
    keep = np.concatenate([[True], states[1:] != states[:-1]])
    letters = "".join(CONTACT_LETTERS[int(s)] for s in states[keep])
    return (letters, float(np.sum(dur[states == 0]) / t1), float(np.sum(dur[states == -1]) / t1),
            float(np.std(y[0, :-1])))


@pytest.mark.parametrize("samples", [orbit.SAMPLES_PER_PERIOD, 2])
@pytest.mark.parametrize("name", ["upper", "kick"])
def test_kept_walk_gives_the_fresh_shape(cases: dict[str, tuple[SDOFModel, np.ndarray, int]],
                                         name: str, samples: int,
                                         monkeypatch: pytest.MonkeyPatch) -> None:
    model, y0, periods = cases[name]
    monkeypatch.setattr(orbit, "SAMPLES_PER_PERIOD", samples)
    yt, mono, walked = orbit.period_map(model, y0, periods, "exact", 1e-10)
    assert walked is not None
    y_ref, mono_ref = flow_with_sensitivity(model, y0, periods / model.mesh_frequency)
    assert np.array_equal(yt, y_ref) and np.array_equal(mono, mono_ref)
    kept = orbit.orbit_shape(model, y0, periods, "exact", 1e-10, walked)
    assert kept == orbit.orbit_shape(model, y0, periods, "exact", 1e-10)
    pattern, sep, back, rms = fresh_pattern(model, y0, periods, samples)
    assert kept.pattern == pattern
    # the same spells summed in another order, the RMS by another formula: rounding apart
    assert (kept.separation, kept.back, kept.dte_rms) == pytest.approx((sep, back, rms),
                                                                       rel=1e-12, abs=1e-15)
    assert len(pattern) > 1  # the case has contact changes


def test_walk_of_another_orbit_is_refused(
        cases: dict[str, tuple[SDOFModel, np.ndarray, int]]) -> None:
    model, y0, periods = cases["upper"]
    _yt, _mono, walked = orbit.period_map(model, y0, periods, "exact", 1e-10)
    with pytest.raises(InputError, match="walked is not the walk of this orbit"):
        orbit.orbit_shape(model, 1.01 * y0, periods, "exact", 1e-10, walked)
    with pytest.raises(InputError, match="walked is not the walk of this orbit"):
        orbit.orbit_shape(model, y0, periods + 1, "exact", 1e-10, walked)
