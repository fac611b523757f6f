"""The event-locating DOP853 reference of the backlash oscillator, written independently of
gear_dyn's solvers (tests/solvers/test_contact_exact.py and test_contact_exact_te.py)."""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from gear_dyn.models.sdof import SDOFModel


def dop853_events(model: SDOFModel, t: np.ndarray, rtol: float, y0: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray]:
    """States on ``t`` and the located contact changes ``u = x - e(t) = +-b`` (``e = 0``
    without a transmission error): ``solve_ivp(DOP853)`` on ``model.rhs`` at ``rtol`` and
    ``atol = rtol * model.state_scale``, restarted at every stiffness switch and at every
    event its own event finder locates (the crossed surface may only be crossed back)."""
    b = float(model.backlash or 0.0)
    te, fm = model.transmission_error, model.mesh_frequency

    def u(t_: float, y: np.ndarray) -> float:
        return float(y[0]) - (0.0 if te is None else float(te.value(model.phase(t_))))

    def u_dot(t_: float, y: np.ndarray) -> float:
        return float(y[1]) - (0.0 if te is None else fm * float(te.slope(model.phase(t_))))

    atol = rtol * model.state_scale
    cuts = np.concatenate([[t[0]], model.switching_times(t[0], t[-1]), [t[-1]]])
    y = np.array(y0, dtype=float)
    out = np.empty((2, t.size))
    out[:, 0] = y
    events: list[float] = []
    skip: dict[int, float] = {}  # event just located: only the opposite crossing next
    for ta, tb in zip(cuts[:-1], cuts[1:], strict=True):
        t_now = float(ta)
        while t_now < tb:
            fns: list[Any] = []
            for i, lev in enumerate((b, -b)):
                def ev(t_: float, yy: np.ndarray, lev: float = lev) -> float:
                    return u(t_, yy) - lev
                ev.terminal = True  # type: ignore[attr-defined]
                ev.direction = -skip[i] if i in skip else 0.0  # type: ignore[attr-defined]
                fns.append(ev)
            sel = (t > t_now) & (t <= tb)
            sol = solve_ivp(model.rhs, (t_now, float(tb)), y, method="DOP853", rtol=rtol,
                            atol=atol, events=fns, dense_output=True)
            assert sol.status >= 0, sol.message
            t_stop = float(sol.t[-1])
            grid = t[sel & (t <= t_stop)]
            if grid.size:
                out[:, np.searchsorted(t, grid)] = sol.sol(grid)
            y = sol.y[:, -1]
            skip = {}
            if sol.status == 1:
                for i, t_ev in enumerate(sol.t_events):
                    if t_ev.size:
                        events.append(float(t_ev[0]))
                        skip[i] = float(np.sign(u_dot(float(t_ev[0]), sol.y_events[i][0])))
            t_now = t_stop
    return out, np.array(events)
