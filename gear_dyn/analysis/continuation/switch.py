"""Branch switching at a period-doubling point onto the period-2n branch (Seydel 2010,
sec. 7.6; Kuznetsov 2004, sec. 10.3.2).

At a period doubling of a period-n orbit the n-period map has the multiplier -1 with the
eigenvector ``v``; seen as a 2n-period orbit, the same orbit is a branch point of the 2n-period
shooting equations (``M^2`` has the multiplier +1), where the period-2n branch leaves in the
direction ``(v, 0)``. The predictor is the located point plus ``eps`` times that direction made
orthogonal to the period-n branch's tangent; the corrector holds the component along it fixed
(so it cannot fall back onto the period-n branch), and the new branch is followed away from the
period-doubling point.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from gear_dyn.analysis.continuation.branch import Bifurcation, Branch
from gear_dyn.analysis.continuation.family import PARAMETERS
from gear_dyn.analysis.continuation.settings import ContinuationSettings
from gear_dyn.analysis.continuation.shooting import Shooting, tangent
from gear_dyn.errors import SolverError

#: scaled predictor offsets tried in turn
OFFSETS = (1e-2, 3e-3, 3e-2, 1e-1)
#: a switched point must miss closing after n periods by at least this (scaled)
MIN_SPLIT = 1e-6


def switch_at_period_doubling(sh: Shooting, bif: Bifurcation, window: tuple[float, float],
                              settings: ContinuationSettings, parameter: str, doublings: int,
                              follow: Callable[..., Branch]) -> Branch:
    """The period-2n branch born at the period doubling ``bif`` of the period-n problem
    ``sh``, followed inside ``window`` by ``follow`` (the continuation loop,
    :func:`.arclength.follow`); a branch without points and a ``stop_reason`` saying why,
    when no period-2n orbit is found next to it."""
    p_star = bif.point.parameter
    z_star = sh.scaled(bif.point.state, p_star)

    def failed(reason: str) -> Branch:
        return Branch(parameter, PARAMETERS.get(parameter, ""), (), (), (), sh.route, reason, 0)

    try:
        ev = sh.evaluate(z_star)
        t1 = tangent(ev.jac)
    except (SolverError, ValueError) as exc:
        return failed(f"switching at {p_star:.10g} failed: {exc}")
    w, vecs = np.linalg.eig(ev.monodromy)
    v = np.real(vecs[:, int(np.argmin(np.abs(w + 1.0)))]) / sh.scale
    phi = np.append(v, 0.0)
    phi = phi - (phi @ t1) * t1
    phi /= np.linalg.norm(phi)
    sh2 = sh.with_periods(2 * sh.periods)
    for eps in OFFSETS:
        z0 = ev.z + eps * phi
        out = sh2.correct(z0, phi, float(phi @ z0), settings.newton)
        if out is None:
            continue
        ev2 = out[0]
        if float(np.max(np.abs(sh.residual_only(ev2.z)))) < MIN_SPLIT:
            continue  # fell back onto the period-n orbit
        try:
            t2 = tangent(ev2.jac)
        except SolverError:
            continue
        if float(t2 @ (ev2.z - ev.z)) < 0.0:
            t2 = -t2
        return follow(sh2, ev2, t2, window, settings, parameter, doublings, parent=sh)
    return failed(f"no period-{2 * sh.periods} orbit converged next to the period doubling "
                  f"at {parameter} = {p_star:.10g}")
