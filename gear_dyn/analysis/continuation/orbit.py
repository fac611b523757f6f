"""One periodic orbit of a single-DOF mesh model: its n-period map, monodromy matrix, Floquet
multipliers, Liouville check, contact pattern and response measures.

The n-period map ``P(y0) = y(n T)`` and its derivative ``M = dP/dy0`` (the monodromy matrix of
a period-n orbit) come from :func:`gear_dyn.solvers.sensitivity.integrate_with_sensitivity`:
the closed-form pieces and saltation matrices of the backlash propagator where the stiffness
is piecewise constant and the transmission error, if any, harmonic (route ``exact``,
:func:`gear_dyn.solvers.contact_exact.contact_exact_applies`), else the variational equations
integrated with located contact events (route ``variational``).

Liouville's formula: for ``y' = f(t, y)`` the determinant of the fundamental matrix is
``exp(int tr(df/dy) dt)``; here ``tr(df/dy) = -c / m_e`` in every contact state, so on any
orbit ``det M = exp(-c n T / m_e)`` exactly (saltation matrices of the continuous dead zone are
the identity). The relative mismatch checks the monodromy matrix of every point.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.stability import (
    OrbitShape,
    contact_pattern,
    contact_shares,
    contact_states,
    flow_on_grid,
)
from gear_dyn.errors import InputError, SolverError
from gear_dyn.models.base import MeshModel
from gear_dyn.solvers.contact_exact import (
    Walk,
    contact_exact_applies,
    walk,
)
from gear_dyn.solvers.sensitivity import integrate_with_sensitivity

FloatArray = NDArray[np.float64]

#: routes to the n-period map and its sensitivity
ROUTES = ("auto", "exact", "variational")
#: samples per mesh period for the response measures and the sampled contact pattern
SAMPLES_PER_PERIOD = 256


def resolve_route(model: MeshModel, route: str) -> str:
    """``exact`` or ``variational`` for ``route`` in :data:`ROUTES` and this model.

    Raises
    ------
    InputError
        An unknown route, or ``exact`` for a model it does not cover.
    """
    if route not in ROUTES:
        raise InputError(f"route = {route!r}: valid choices are {', '.join(ROUTES)}")
    applies = contact_exact_applies(model)
    if route == "exact" and not applies:
        raise InputError("route = 'exact' needs backlash, piecewise-constant stiffness and no or "
                         "a damped harmonic transmission error; use route = 'variational'")
    if route == "auto":
        return "exact" if applies else "variational"
    return route


def period_map(model: MeshModel, y0: FloatArray, periods: int, route: str, rtol: float,
               mesh_rate: bool = False) -> tuple[FloatArray, FloatArray, Walk | None]:
    """``(P(y0), M, walked)``: the state after ``periods`` mesh periods, ``d P / d y0`` and,
    on the exact route, the walk they come from (:func:`~gear_dyn.solvers.contact_exact.walk`,
    for :func:`orbit_shape` of the same orbit; None on the variational route).

    ``route`` is ``exact`` or ``variational`` (:func:`resolve_route`); ``rtol`` is the
    variational integration's relative tolerance. ``mesh_rate`` (exact route only): the walk
    also carries ``d P / d f_m`` (:meth:`~gear_dyn.solvers.contact_exact.Walk.mesh_rate`).

    Raises
    ------
    SolverError
        Integration failure, a chattering contact or a diverging response.
    """
    t1 = periods / model.mesh_frequency
    if route == "exact":
        walked = walk(model, y0, t1, mesh_rate=mesh_rate)
        return walked.end, walked.sensitivity(), walked
    if mesh_rate:
        raise InputError("period_map: mesh_rate needs route = 'exact'")
    y, mono = integrate_with_sensitivity(model, y0, t1, rtol, route)
    return y, mono, None


def map_only(model: MeshModel, y0: FloatArray, periods: int, route: str, rtol: float
             ) -> FloatArray:
    """``P(y0)`` without the sensitivity (the closed form, or DOP853 on the state alone). On
    the exact route the end state of the walk, as in :func:`period_map` (the same formula, so
    the parameter difference quotients of :mod:`.shooting` compare like with like).

    Raises
    ------
    SolverError
        Integration failure, a chattering contact or a diverging response.
    """
    t1 = periods / model.mesh_frequency
    if route == "exact":
        end = walk(model, y0, t1).end
        if not np.isfinite(end).all():
            raise SolverError("exact_contact produced non-finite states: the response diverges")
        return end
    return np.asarray(flow_on_grid(model, y0, np.array([0.0, t1]), rtol=rtol)[:, -1])


def liouville_residual(model: MeshModel, monodromy: FloatArray, periods: int) -> float:
    """``|det M / exp(-c n T / m_e) - 1|``: the monodromy matrix's Liouville mismatch (-)."""
    expected = math.exp(-model.damping * periods / (model.mass * model.mesh_frequency))
    (a, b), (c, d) = monodromy.tolist()
    return abs((a * d - b * c) / expected - 1.0)


def orbit_shape(model: MeshModel, y0: FloatArray, periods: int, route: str, rtol: float,
                walked: Walk | None = None) -> OrbitShape:
    """The contact pattern and response measures of the orbit through ``y0``
    (:class:`~gear_dyn.analysis.stability.OrbitShape`, the ``shape`` of its
    :class:`~gear_dyn.analysis.stability.PeriodicSolution`).

    On the exact route the pattern comes from the walk's own contact state of each piece
    (:meth:`~gear_dyn.solvers.contact_exact.Walk.spells`: every spell between located contact
    changes is seen, however short); on the variational route from
    :data:`SAMPLES_PER_PERIOD` samples per mesh period (a spell shorter than a sample step
    can be missed). The response measures
    use the samples.

    ``walked``: on the exact route, the walk of this orbit from ``y0`` over the n periods
    already made (the third item of :func:`period_map`); its pieces give the samples and the
    contact changes, with no second propagation. None walks here.

    Raises
    ------
    InputError
        ``walked`` is not the walk of this orbit (another start state or span).
    SolverError
        Integration failure.
    """
    t1 = periods / model.mesh_frequency
    t = np.linspace(0.0, t1, periods * SAMPLES_PER_PERIOD + 1)
    if route == "exact":
        if walked is None:
            walked = walk(model, y0, t1)
        elif not (walked.model is model and walked.t0 == 0.0 and walked.t1 == t1
                  and np.array_equal(walked.start, np.asarray(y0, dtype=float))):
            raise InputError("orbit_shape: walked is not the walk of this orbit (another "
                             "model, start state or span)")
        y = walked.on_grid(t)
        st, dur = walked.spells()  # the walk's own spells (backlash: the same rule as
        keep = dur > 0.0           # contact_states), however short
        st, dur = st[keep], dur[keep]
        sep, back = contact_shares(st, dur, span=t1)
        x = y[0, :-1]
        mean = float(x.mean())
        d = x - mean
        return OrbitShape(contact_pattern(st), sep, back, math.sqrt(float(d @ d) / x.size),
                          float(x.max() - x.min()), mean)
    y = flow_on_grid(model, y0, t, rtol=rtol)
    return OrbitShape.of_samples(contact_states(model, t[:-1], y[:, :-1]), y[0, :-1])
