"""An :class:`~.branch.OrbitPoint` from a converged evaluation of the shooting equations: its
orbit (:class:`~gear_dyn.analysis.stability.PeriodicSolution`, with the shape) and place on the
branch."""

from __future__ import annotations

import numpy as np

from gear_dyn.analysis.continuation.branch import OrbitPoint
from gear_dyn.analysis.continuation.orbit import OrbitShape, liouville_residual, orbit_shape
from gear_dyn.analysis.continuation.settings import ContinuationSettings
from gear_dyn.analysis.continuation.shooting import Evaluation, Shooting
from gear_dyn.analysis.stability import PeriodicSolution


def make_point(sh: Shooting, ev: Evaluation, settings: ContinuationSettings,
               arclength: float = 0.0, tangent_p: float = float("nan"), iterations: int = 0,
               shape: OrbitShape | None = None) -> OrbitPoint:
    """The orbit point of ``ev``: multipliers, stability, Liouville check, contact pattern
    and response measures (from the evaluation's walk on the exact route, else one more
    n-period map on a sample grid; unless its ``shape`` is given).

    Raises
    ------
    SolverError
        The sampling run failed.
    """
    y = sh.state(ev.z)
    mu = np.linalg.eigvals(ev.monodromy).astype(np.complex128)
    liou = liouville_residual(ev.model, ev.monodromy, sh.periods)
    if shape is None:
        shape = orbit_shape(ev.model, y, sh.periods, sh.route, sh.rtol, ev.walked)
    fm = float(ev.model.mesh_frequency)
    orbit = PeriodicSolution(y, sh.periods / fm, ev.monodromy, mu, True, int(iterations),
                             "continuation", float(np.max(np.abs(ev.g))), sh.periods, shape)
    return OrbitPoint(
        parameter=sh.param(ev.z), orbit=orbit, liouville=liou,
        liouville_ok=liou <= settings.liouville_tol, mesh_frequency=fm,
        arclength=float(arclength), tangent_p=float(tangent_p), dp_error=float(ev.dp_error))
