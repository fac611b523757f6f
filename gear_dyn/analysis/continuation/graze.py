"""The grazing test function: how far the orbit's extremum that touches a contact boundary lies
from it (di Bernardo et al. 2008, sec. 2.3 and ch. 7).

A contact spell appears or vanishes on a branch where a local extremum of the relative
displacement ``x(t)`` touches a contact boundary ``x = +-b`` (a grazing orbit: ``x = +-b`` and
``x' = 0`` at one instant). The signed distance ``x_e - level`` of that extremum is continuous
along the branch and changes sign there, so a root finder brackets on it as on the fold and
period-doubling tests (:mod:`.detect`); the contact pattern still decides on which side of
the graze a point lies.

The extremum is found on the orbit sampled at :data:`~.orbit.SAMPLES_PER_PERIOD` points per
mesh period (a sign change of ``x'``) and refined by Newton's method on ``x'(t) = 0`` with the
acceleration from the model's right-hand side, each iterate's state propagated from the sample
before it (closed form on the exact route, DOP853 to ``rtol`` on the variational one); its
value is then exact to rounding on the exact route, to ``rtol`` on the variational one. On the
exact route the states come from the orbit's own walk where it is at hand (the shooting map's,
:meth:`gear_dyn.solvers.contact_exact.Walk.on_grid`: the same closed-form pieces, no second
propagation).
Models with a transmission error (where the contact coordinate is ``x - e(t)``) have no test
function here: the caller bisects on the contact pattern.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.continuation.orbit import SAMPLES_PER_PERIOD
from gear_dyn.analysis.stability import flow_on_grid
from gear_dyn.errors import SolverError
from gear_dyn.models.base import MeshModel
from gear_dyn.solvers.contact_exact import Walk, propagate_contact_exact

FloatArray = NDArray[np.float64]
#: Newton iterations on x'(t) = 0 (quadratic convergence from a sample step's secant guess)
NEWTON_ITERATIONS = 6
#: Newton stops when its time step is below this share of the sample step: the Taylor step to
#: the stationary point then errs by x''' dt^3 / 6, ~1e-20 of the amplitude at 256 samples per
#: mesh period
NEWTON_STOP = 1e-4
#: sample steps either side of the extremum's last time searched first for it
WINDOW = 4


@dataclass(frozen=True)
class Extremum:
    """A local extremum of ``x(t)`` on an orbit.

    Attributes
    ----------
    t : float
        Time from the orbit's start (s).
    x : float
        Value (m).
    kind : int
        +1 a maximum, -1 a minimum.
    """

    t: float
    x: float
    kind: int


def _advance(model: MeshModel, y: FloatArray, t0: float, t1: float, route: str, rtol: float,
             walked: Walk | None = None) -> FloatArray:
    """State at ``t1`` from ``y`` at ``t0`` (``t1 >= t0``; ``walked``: the walk of the orbit
    that ``y`` at ``t0`` lies on)."""
    if t1 <= t0:
        return np.asarray(y, dtype=float)
    if walked is not None:
        return walked.on_grid(np.array([t1]))[:, 0]
    return _on(model, y, np.array([t0, t1]), route, rtol)[:, -1]


def _on(model: MeshModel, y0: FloatArray, t: FloatArray, route: str, rtol: float,
        walked: Walk | None = None) -> FloatArray:
    """States on the increasing grid ``t`` from ``y0`` at ``t[0]``; from ``walked`` where it
    is the walk from ``y0`` at ``t[0]`` over the grid (else a new propagation)."""
    if walked is not None and _serves(walked, model, y0, t):
        return walked.on_grid(t)
    if route == "exact":
        y, _stats = propagate_contact_exact(model, t, y0=y0)
    else:
        y = flow_on_grid(model, y0, t, rtol=rtol)
    return np.asarray(y, dtype=float)


def _serves(walked: Walk, model: MeshModel, y0: FloatArray, t: FloatArray) -> bool:
    """True when ``walked`` is the walk of ``model`` from ``y0`` at ``t[0]`` covering ``t``."""
    return (walked.model is model and walked.t0 == float(t[0]) and float(t[-1]) <= walked.t1
            and np.array_equal(walked.start, np.asarray(y0, dtype=float)))


def _samples(model: MeshModel, y0: FloatArray, periods: int, route: str, rtol: float,
             walked: Walk | None = None) -> tuple[FloatArray, FloatArray]:
    t = np.linspace(0.0, periods / model.mesh_frequency, periods * SAMPLES_PER_PERIOD + 1)
    return t, _on(model, y0, t, route, rtol, walked)


def _refine(model: MeshModel, t: FloatArray, y: FloatArray, j: int, route: str, rtol: float,
            walked: Walk | None = None) -> Extremum:
    """The extremum between samples ``j`` and ``j + 1`` (where ``x'`` changes sign)."""
    ta, tb = float(t[j]), float(t[j + 1])
    va, vb = float(y[1, j]), float(y[1, j + 1])
    kind = 1 if va > 0.0 else -1
    tt = ta + (tb - ta) * va / (va - vb)  # secant on x'
    ya = y[:, j]
    x_e = float("nan")
    for _ in range(NEWTON_ITERATIONS):
        yt = _advance(model, ya, ta, tt, route, rtol, walked)
        acc = float(model.rhs(tt, yt)[1])
        if acc == 0.0:
            x_e = float(yt[0])
            break
        dt = -float(yt[1]) / acc
        x_e = float(yt[0] + yt[1] * dt + 0.5 * acc * dt * dt)  # Taylor to the stationary point
        if abs(dt) <= NEWTON_STOP * (tb - ta):
            break
        tt = min(max(tt + dt, ta), tb)
    return Extremum(tt, x_e, kind)


def _turns(v: FloatArray) -> NDArray[np.int64]:
    """Sample indices ``j`` where ``x'`` changes sign between ``j`` and ``j + 1``."""
    return np.flatnonzero(((v[:-1] > 0.0) & (v[1:] <= 0.0)) | ((v[:-1] < 0.0) & (v[1:] >= 0.0)))


def extrema(model: MeshModel, y0: FloatArray, periods: int, route: str, rtol: float,
            near: tuple[float, int] | None = None, walked: Walk | None = None
            ) -> list[Extremum]:
    """Local extrema of ``x(t)`` over the n-period orbit through ``y0``.

    Parameters
    ----------
    model : MeshModel
    y0 : ndarray
        Orbit state at t = 0 [m, m/s].
    periods : int
        Mesh periods n.
    route : str
        ``exact`` or ``variational``.
    rtol : float
        Variational tolerance.
    near : (float, int) or None
        ``(time, kind)``: only the extremum of that kind nearest that time (s); None: all.
    walked : Walk or None
        The exact route's walk of this orbit from ``y0`` (the shooting map's): its states,
        no new propagation; None: propagated here.

    Returns
    -------
    list of Extremum
        In time order (empty where there is none of the kind asked for).

    Raises
    ------
    SolverError
        The propagation failed.
    """
    t, y = _samples(model, y0, periods, route, rtol, walked)
    if walked is not None and not _serves(walked, model, y0, t):
        walked = None
    idx = _turns(y[1])
    if near is not None:
        t_near, kind = near
        idx = idx[(y[1, idx] > 0.0) == (kind > 0)]
        if idx.size == 0:
            return []
        idx = idx[[int(np.argmin(np.abs(t[idx] - t_near)))]]
    return [_refine(model, t, y, int(j), route, rtol, walked) for j in idx]


@dataclass(frozen=True)
class GrazeTest:
    """The extremum tracked across a graze: its kind, the boundary it crosses and where it was
    last seen.

    Attributes
    ----------
    kind : int
        +1 a maximum, -1 a minimum.
    level : float
        The contact boundary (+b or -b, m).
    t : float
        Time of the extremum on the orbit last seen (s).
    """

    kind: int
    level: float
    t: float

    def margin(self, model: MeshModel, y0: FloatArray, periods: int, route: str, rtol: float,
               walked: Walk | None = None) -> tuple[float, GrazeTest] | None:
        """``x_e - level`` on the orbit through ``y0`` (m), and the test moved to where the
        extremum is now; None where the orbit has no extremum of the kind. ``walked``: the
        exact route's walk of the orbit from ``y0`` (its states, no new propagation)."""
        h = 1.0 / (model.mesh_frequency * SAMPLES_PER_PERIOD)
        t1 = periods / model.mesh_frequency
        try:
            # first the samples next to where it was (the orbit moved little), else all
            near = self.t + h * np.arange(-WINDOW, WINDOW + 1)
            t: FloatArray = np.concatenate([[0.0], near[(near > 0.0) & (near < t1)]])
            if walked is not None and not _serves(walked, model, y0, t):
                walked = None
            y = _on(model, y0, t, route, rtol, walked)
            idx = _turns(y[1])
            idx = idx[idx >= 1]  # not the interval from t = 0 to the window
            idx = idx[(y[1, idx] > 0.0) == (self.kind > 0)]
            if idx.size:
                j = int(idx[np.argmin(np.abs(t[idx] - self.t))])
                found = [_refine(model, t, y, j, route, rtol, walked)]
            else:
                found = extrema(model, y0, periods, route, rtol, near=(self.t, self.kind),
                                walked=walked)
        except SolverError:
            return None
        if not found:
            return None
        e = found[0]
        return e.x - self.level, GrazeTest(self.kind, self.level, e.t)


def graze_test(model_a: MeshModel, y_a: FloatArray, model_b: MeshModel, y_b: FloatArray,
               periods: int, route: str, rtol: float, walked_a: Walk | None = None,
               walked_b: Walk | None = None) -> tuple[GrazeTest, float, float] | None:
    """The grazing test between the orbits through ``y_a`` and ``y_b`` (either end of a step
    where the contact pattern changes), with its values at both ends.

    An extremum of ``a`` and the extremum of the same kind of ``b`` nearest it in time form a
    pair when one contact boundary lies between their values (the sampled values pick the
    pair, the refined values confirm it); the test follows the one pair found. None when there
    is no such pair, more than one, or the model has a transmission error. ``walked_a``,
    ``walked_b``: the exact route's walks of the two orbits (their states, no new propagation).
    """
    if model_a.transmission_error is not None or model_a.backlash is None:
        return None
    b = float(model_a.backlash)
    try:
        ta, ya = _samples(model_a, y_a, periods, route, rtol, walked_a)
        tb, yb = _samples(model_b, y_b, periods, route, rtol, walked_b)
        if walked_a is not None and not _serves(walked_a, model_a, y_a, ta):
            walked_a = None
        if walked_b is not None and not _serves(walked_b, model_b, y_b, tb):
            walked_b = None
    except SolverError:
        return None
    ia, ib = _turns(ya[1]), _turns(yb[1])
    pairs: list[tuple[int, int, float]] = []
    for j in ia:
        same = ib[(yb[1, ib] > 0.0) == (ya[1, j] > 0.0)]
        if not same.size:
            continue
        k = int(same[np.argmin(np.abs(tb[same] - ta[j]))])
        xa, xb = 0.5 * (ya[0, j] + ya[0, j + 1]), 0.5 * (yb[0, k] + yb[0, k + 1])
        pairs.extend((int(j), k, level) for level in (b, -b) if (xa - level) * (xb - level) < 0)
    if len(pairs) != 1:
        return None
    j, k, level = pairs[0]
    try:
        ea = _refine(model_a, ta, ya, j, route, rtol, walked_a)
        eb = _refine(model_b, tb, yb, k, route, rtol, walked_b)
    except SolverError:
        return None
    if (ea.x - level) * (eb.x - level) >= 0.0:
        return None
    return GrazeTest(ea.kind, level, ea.t), ea.x - level, eb.x - level
