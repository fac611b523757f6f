"""The contact walk's derivative with respect to the mesh frequency
(:meth:`gear_dyn.solvers.contact_exact.Walk.mesh_rate`) against central differences of the
n-period map over ``f_m +- h`` (a second method: the map alone, at neighbouring speeds).

The central difference's own error is estimated from two steps, ``h`` and ``h / 2``: its
truncation is ``O(h^2)``, so ``|D(h) - D(h/2)|`` is three times that of ``D(h/2)``; its rounding
is ``eps_map |P| / h`` with the map rounded to ``eps_map = 1e-13`` relative (a few hundred ulps
over a few dozen closed-form pieces, :func:`gear_dyn.solvers.contact_exact.rounding_bound`).
The walk's derivative must lie within that error of ``D(h/2)`` (with a factor 2 of slack, for
the estimate), and the estimate must itself be small, so the check can fail.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from gear_dyn.errors import InputError
from gear_dyn.excitation import HarmonicSignal
from gear_dyn.models.sdof import SDOFModel
from gear_dyn.solvers.contact_exact import walk
from gear_dyn.stiffness.periodic import rectangular_stiffness

M_E, K1, W, B = 3.045616654145314, 1.0e9, 5782.170507648933, 1e-5
FN = math.sqrt(K1 / M_E) / (2 * math.pi)
TE = HarmonicSignal(2e-6, np.array([8e-6, 1.5e-6]), np.array([3e-6, -2e-6]))
#: relative rounding of the map (see the module)
EPS_MAP = 1e-13


def model(ratio: float, te: HarmonicSignal | None, phase0: float = 0.0) -> SDOFModel:
    """A rectangular-stiffness backlash pair at f_m / f_n = ``ratio``."""
    return SDOFModel(mass=M_E, stiffness=rectangular_stiffness(1.41, K1, 1.6 * K1),
                     damping_ratio=0.06, static_load=W, mesh_frequency=ratio * FN, backlash=B,
                     transmission_error=te, phase0=phase0)


def settled(m: SDOFModel, periods: int) -> np.ndarray:
    """A state near the attracting orbit (80 mesh periods from the static deflection)."""
    y = m.initial_state()
    for _ in range(80):
        y = walk(m, y, 1 / m.mesh_frequency).end
    return np.asarray(y)


@pytest.mark.parametrize(("ratio", "te", "phase0", "periods", "events"), [
    (0.7, None, 0.0, 1, 0),   # in contact throughout: the stiffness switches and the end only
    (1.0, None, 0.3, 1, 2),   # at the resonance: the teeth part, a phase offset
    (1.1, None, 0.0, 2, 4),   # two periods
    (0.9, TE, 0.137, 1, 4),   # a two-harmonic transmission error (particular solutions' rates)
    (1.3, TE, 0.0, 2, 6),
])
def test_mesh_rate_matches_central_differences(ratio: float, te: HarmonicSignal | None,
                                               phase0: float, periods: int, events: int
                                               ) -> None:
    m = model(ratio, te, phase0)
    fm = m.mesh_frequency
    y0 = settled(m, periods)
    walked = walk(m, y0, periods / fm, mesh_rate=True)
    assert len(walked.event_times) >= events  # contact changes inside: saltation on the way
    rate = walked.mesh_rate()

    def central(h: float) -> np.ndarray:
        plus, minus = (walk(m.at_mesh_frequency(fm + d), y0, periods / (fm + d)).end
                       for d in (h, -h))
        return (plus - minus) / (2 * h)

    h = 1e-5 * fm
    d1, d2 = central(h), central(h / 2)
    scale = np.abs(y0) + np.abs(walked.end)
    err = 2 * np.abs(d1 - d2) / 3 + EPS_MAP * scale / (h / 2)
    size = np.abs(d2)
    assert np.all(err < 1e-4 * size)  # the difference is itself accurate: a real check
    assert np.all(np.abs(rate - d2) <= 2 * err), (rate, d2, err)


def test_mesh_rate_of_a_walk_without_it_is_refused() -> None:
    m = model(0.8, None)
    with pytest.raises(InputError, match="mesh_rate=True"):
        walk(m, m.initial_state(), 1 / m.mesh_frequency).mesh_rate()


def test_shooting_column_is_the_speed_derivative() -> None:
    """The continuation's exact parameter column (speed family): ``dP/dw = dP/df_m f_m / w``
    against the central difference over the speed, with the same error estimate."""
    from gear_dyn.analysis.continuation.family import sdof_family
    from gear_dyn.analysis.continuation.shooting import Shooting

    fam = sdof_family(model(1.0, None), "speed", teeth=23)
    w = 0.95 * FN * 2 * math.pi / 23
    m = fam(w)
    sh = Shooting(fam, 1, "exact", m.state_scale, w, 1e-10, 1e-5)
    assert sh.exact_column
    y0 = settled(m, 1)
    ev = sh.evaluate(sh.scaled(y0, w))

    def central(h: float) -> np.ndarray:
        plus, minus = (walk(fam(w + d), y0, 1 / fam(w + d).mesh_frequency).end for d in (h, -h))
        return (plus - minus) / (2 * h) * w / sh.scale

    d1, d2 = central(1e-5 * w), central(5e-6 * w)
    err = 2 * np.abs(d1 - d2) / 3 + EPS_MAP * (np.abs(y0) / sh.scale + 1) / 5e-6
    assert np.all(np.abs(ev.jac[:, 2] - d2) <= 2 * err)
    assert ev.dp_error < 1e-10  # stated: rounding
