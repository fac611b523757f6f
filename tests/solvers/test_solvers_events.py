"""The one event locator (gear_dyn.solvers.events.RestartingSolver) on a problem with a closed
form.

x'' = -x from x = 1: the crossings of x = +-0.5 are at t = arccos(+-0.5) + k pi, i.e.
pi/3, 2 pi/3, 4 pi/3, 5 pi/3, ... Every crossing must be found exactly once (no re-detection at
the restart instant), and the restarts must not spoil the solution (cos t to 1e-9: DOP853 at
rtol 1e-11, global error ~1e-10 over three periods).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from gear_dyn.errors import SolverError
from gear_dyn.solvers.events import MAX_EVENTS_PER_PIECE, RestartingSolver


def rhs(t: float, y: np.ndarray) -> np.ndarray:
    return np.array([y[1], -y[0]])


def _solver(events: list, method: str, rtol: float, atol: float, tb: float) -> RestartingSolver:
    """From x = 1 at t = 0, one piece ending at ``tb`` (no switching instant inside)."""
    return RestartingSolver(method, lambda ta, tb: (rhs, None), events, 2,
                            lambda t: tb if t < tb else math.inf, 0.0, np.array([1.0, 0.0]),
                            rtol, np.array([atol, atol]), math.inf, span=tb)


def test_every_crossing_found_once_and_solution_intact() -> None:
    tb = 3 * 2 * math.pi
    t_eval = np.linspace(0.0, tb, 301)
    events = [lambda t, y: y[0] - 0.5, lambda t, y: y[0] + 0.5]
    run = _solver(events, "DOP853", 1e-11, 1e-13, tb)
    y_eval = run.advance(t_eval)
    assert run.n_events == 4 * 3  # four crossings per period, three periods
    assert np.max(np.abs(y_eval[0] - np.cos(t_eval))) < 1e-9
    assert y_eval[0, -1] == pytest.approx(1.0, abs=1e-9)


def test_points_one_by_one_are_the_grid_at_once() -> None:
    """The states read point by point (the FMU's communication steps) are those of the whole
    grid read at once, bit for bit: reading never disturbs the integration or the locator."""
    tb = 2 * math.pi
    t_eval = np.linspace(0.0, tb, 97)[1:]
    events = [lambda t, y: y[0] - 0.5, lambda t, y: y[0] + 0.5]
    whole = _solver(events, "RK45", 1e-9, 1e-12, tb)
    one = _solver(events, "RK45", 1e-9, 1e-12, tb)
    y = np.hstack([one.advance(np.array([t])) for t in t_eval])
    np.testing.assert_array_equal(y, whole.advance(t_eval))
    assert one.n_events == whole.n_events == 4
    assert one.counts() == whole.counts()


def test_chattering_is_an_error_not_a_hang(monkeypatch: pytest.MonkeyPatch) -> None:
    """A cap on contact changes per piece turns runaway restarts into a SolverError."""
    import gear_dyn.solvers.events as ev

    monkeypatch.setattr(ev, "MAX_EVENTS_PER_PIECE", 3)
    assert MAX_EVENTS_PER_PIECE > 3
    t_eval = np.linspace(0.0, 4 * math.pi, 50)
    with pytest.raises(SolverError, match="chattering"):
        _solver([lambda t, y: y[0] - 0.5], "RK45", 1e-8, 1e-10, 4 * math.pi).advance(t_eval)
