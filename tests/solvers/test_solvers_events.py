"""Contact-change events (gear_dyn/events.py) on a problem with a closed form.

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
from gear_dyn.solvers.events import MAX_EVENTS_PER_PIECE, solve_piece_with_events


def rhs(t: float, y: np.ndarray) -> np.ndarray:
    return np.array([y[1], -y[0]])


def test_every_crossing_found_once_and_solution_intact() -> None:
    tb = 3 * 2 * math.pi
    t_eval = np.linspace(0.0, tb, 301)
    events = [lambda t, y: y[0] - 0.5, lambda t, y: y[0] + 0.5]
    y_eval, y_end, st = solve_piece_with_events(
        rhs, 0.0, tb, np.array([1.0, 0.0]), t_eval, events, "DOP853", 1e-11,
        np.array([1e-13, 1e-13]), math.inf, {})
    assert st["n_events"] == 4 * 3  # four crossings per period, three periods
    assert np.max(np.abs(y_eval[0] - np.cos(t_eval))) < 1e-9
    assert y_end[0] == pytest.approx(1.0, abs=1e-9)


def test_chattering_is_an_error_not_a_hang(monkeypatch: pytest.MonkeyPatch) -> None:
    """A cap on contact changes per piece turns runaway restarts into a SolverError."""
    import gear_dyn.solvers.events as ev

    monkeypatch.setattr(ev, "MAX_EVENTS_PER_PIECE", 3)
    assert MAX_EVENTS_PER_PIECE > 3
    t_eval = np.linspace(0.0, 4 * math.pi, 50)
    with pytest.raises(SolverError, match="chattering"):
        ev.solve_piece_with_events(rhs, 0.0, 4 * math.pi, np.array([1.0, 0.0]), t_eval,
                                   [lambda t, y: y[0] - 0.5], "RK45", 1e-8,
                                   np.array([1e-10, 1e-10]), math.inf, {})
