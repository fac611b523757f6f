"""Exact one-period map and sensitivity of the backlash model, and shooting on it
(gear_dyn.solvers.sensitivity.integrate_with_sensitivity / shoot, route ``exact``).

Second methods: the variational equations integrated with DOP853 (route ``variational``, the
route shooting used before), and central differences of the exact flow. The cases are the
packaged backlash scene at 3319 rpm (teeth in contact), on the upper branch at 5400 rpm (teeth
apart for half the period) and at 5000 rpm (back-flank contact), and a start kicked onto the
back flank. Tolerances:

- against the variational route at rtol 1e-12: its error is proportional to rtol (DOP853's
  tolerance proportionality), so its run at rtol 1e-13 gives its error at 1e-12, ``e_12 =
  |V(1e-12) - V(1e-13)|``; tolerance ``10 e_12`` plus the exact flow's stated rounding error
  (:func:`gear_dyn.solvers.contact_exact.rounding_bound`). With contact changes ``e_12`` is
  ~50 rtol (DOP853 restarts at each one), without ~1 rtol. The difference must also fall
  with rtol (1e-10 to 1e-12): the exact map is the variational route's limit;
- against central differences with step ``h`` (relative to the state scale): the exact flow's
  stated rounding error divided by ``h`` plus twice the Richardson estimate of the truncation
  error ``|D(h) - D(2h)|``;
- orbits of the two routes: the closing errors and the routes' difference of the map through
  ``(I - Phi)^-1`` for the start state, Bauer-Fike for the multipliers, times 10.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from gear_dyn.analysis.stability import shoot
from gear_dyn.errors import InputError
from gear_dyn.models.sdof import SDOFModel
from gear_dyn.scene import build_plan, load_scene
from gear_dyn.solvers.contact_exact import propagate_contact_exact, rounding_bound
from gear_dyn.solvers.sensitivity import integrate_with_sensitivity

SCENES = Path(__file__).resolve().parents[2] / "gear_dyn" / "scenes"
BACKLASH = SCENES / "helicopter_tail_backlash.toml"
RTOL_VAR = 1e-12  #: the variational route's tolerance in the comparison


@pytest.fixture(scope="module")
def base() -> SDOFModel:
    model = build_plan(load_scene(BACKLASH)).model
    assert isinstance(model, SDOFModel)
    return model


def at_rpm(model: SDOFModel, rpm: float) -> SDOFModel:
    return dataclasses.replace(model, mesh_frequency=23 * rpm / 60)


@pytest.fixture(scope="module")
def cases(base: SDOFModel) -> dict[str, tuple[SDOFModel, np.ndarray]]:
    """Start states: the static state at 3319 rpm, the upper-branch orbits at 5400 and 5000 rpm
    (settled at 6400 rpm, then continued down as a slow sweep), a back-flank kick."""
    hi = at_rpm(base, 6400.0)
    t = np.linspace(0.0, 300 / hi.mesh_frequency, 301)
    guess = propagate_contact_exact(hi, t)[0][:, -1]  # rho^300 < 1e-50: settled
    orbits = {}
    for rpm in (6400.0, 6200.0, 6000.0, 5800.0, 5600.0, 5400.0, 5000.0):
        sol = shoot(at_rpm(base, rpm), guess, 1e-10)
        assert sol.converged
        guess = sol.y0
        orbits[rpm] = sol.y0
    low = at_rpm(base, 3319.0)
    kick = low.initial_state() + np.array([0.0, -4 * low.state_scale[1]])
    return {"contact": (low, low.initial_state()),
            "separation": (at_rpm(base, 5400.0), orbits[5400.0]),
            "back_flank": (at_rpm(base, 5000.0), orbits[5000.0]),
            "kick": (low, kick)}


def contact_facts(model: SDOFModel, y0: np.ndarray) -> tuple[int, float, float]:
    """Contact changes in one period, min x / b, and the stated rounding error of the exact
    flow over it (relative to the state scale)."""
    t = np.linspace(0.0, 1 / model.mesh_frequency, 4001)
    y, st = propagate_contact_exact(model, t, y0=y0)
    rounding = rounding_bound(y, model.state_scale, int(st["n_segments"]))
    return int(st["n_contact_events"]), float(np.min(y[0])) / float(model.backlash or 1.0), \
        rounding


def scaled(model: SDOFModel, phi: np.ndarray) -> np.ndarray:
    """``D^-1 phi D``, D = diag(state scale): dimensionless, the same eigenvalues."""
    s = np.asarray(model.state_scale, dtype=float)
    return np.asarray(phi / s[:, None] * s[None, :])


@pytest.mark.parametrize("case", ["contact", "separation", "back_flank", "kick"])
def test_exact_map_equals_variational(cases, case: str) -> None:
    model, y0 = cases[case]
    n_ev, x_min, rounding = contact_facts(model, y0)
    if case == "contact":
        assert n_ev == 0
    else:
        assert n_ev >= 2, "the case must separate the teeth"
    if case in ("back_flank", "kick"):
        assert x_min < -1.0, "the case must reach the back flank"
    period = 1 / model.mesh_frequency
    scale = np.asarray(model.state_scale, dtype=float)
    y_ex, phi_ex = integrate_with_sensitivity(model, y0, period, route="exact")

    def diff(rtol_a: float, rtol_b: float | None = None) -> float:
        """Largest scaled difference of state and sensitivity: V(rtol_a) against V(rtol_b),
        or against the exact route."""
        ya, pa = integrate_with_sensitivity(model, y0, period, rtol_a, route="variational")
        yb, pb = (y_ex, phi_ex) if rtol_b is None else integrate_with_sensitivity(
            model, y0, period, rtol_b, route="variational")
        return max(float(np.max(np.abs(ya - yb) / scale)),
                   float(np.max(np.abs(scaled(model, pa - pb)))))

    own = diff(RTOL_VAR, RTOL_VAR / 10)
    err = diff(RTOL_VAR)
    assert err <= 10 * own + rounding
    assert err < diff(100 * RTOL_VAR) / 10  # converges to the exact map as rtol falls
    # 'auto' takes the exact route for this model
    y_auto, phi_auto = integrate_with_sensitivity(model, y0, period)
    assert np.array_equal(y_auto, y_ex) and np.array_equal(phi_auto, phi_ex)


@pytest.mark.parametrize("case", ["contact", "separation", "back_flank", "kick"])
def test_exact_sensitivity_equals_central_differences(cases, case: str) -> None:
    model, y0 = cases[case]
    period = 1 / model.mesh_frequency
    scale = np.asarray(model.state_scale, dtype=float)
    _y, phi = integrate_with_sensitivity(model, y0, period, route="exact")
    n_ev, _x, rounding = contact_facts(model, y0)
    h_rel = 1e-4

    def central(h: float) -> np.ndarray:
        d = np.empty((2, 2))
        for j in range(2):
            e = np.zeros(2)
            e[j] = h * scale[j]
            yp, _ = integrate_with_sensitivity(model, y0 + e, period, route="exact")
            ym, _ = integrate_with_sensitivity(model, y0 - e, period, route="exact")
            d[:, j] = (yp - ym) / (2 * e[j])
        return d

    d1, d2 = central(h_rel), central(2 * h_rel)
    # each flow is off by <= rounding (of the state scale): the difference quotient by
    # rounding / h_rel; the truncation error of D(h) is (D(2h) - D(h)) / 3 (error ~ h^2)
    tol = rounding / h_rel + 2 * np.abs(scaled(model, d1 - d2))
    err = np.abs(scaled(model, phi - d1))
    assert np.all(err <= tol), (err, tol, n_ev)


@pytest.mark.parametrize("case", ["contact", "separation", "back_flank"])
def test_orbit_equal_between_routes(cases, case: str) -> None:
    model, y_orbit = cases[case]
    rtol = 1e-10
    guess = 1.01 * y_orbit
    ex = shoot(model, guess, rtol, route="exact")
    var = shoot(model, guess, rtol, route="variational")
    assert ex.converged and var.converged and ex.how == var.how == "shooting"
    scale = np.asarray(model.state_scale, dtype=float)
    ref = np.maximum(scale, np.abs(ex.y0))
    # the routes' difference of the map at one state (the variational one's error at rtol)
    y_v, phi_v = integrate_with_sensitivity(model, var.y0, var.period, rtol, route="variational")
    y_e, phi_e = integrate_with_sensitivity(model, var.y0, ex.period, route="exact")
    delta_y = float(np.max(np.abs(y_v - y_e) / ref))
    phi = ex.monodromy / ref[:, None] * ref[None, :]
    kappa = float(np.linalg.norm(np.linalg.inv(np.eye(2) - phi), np.inf))
    tol_y = 10 * kappa * (ex.residual + var.residual + delta_y)
    assert np.max(np.abs(ex.y0 - var.y0) / ref) <= tol_y
    # Bauer-Fike: |d mu| <= cond(V) ||d Phi||_2, d Phi = the routes' difference at one state
    # + the exact monodromy's change between the two start states
    d_phi = float(np.linalg.norm(scaled(model, phi_v - phi_e), 2)) + float(
        np.linalg.norm(scaled(model, phi_e - ex.monodromy), 2))
    vecs = np.linalg.eig(scaled(model, ex.monodromy))[1]
    tol_mu = 10 * float(np.linalg.cond(vecs)) * d_phi
    for mu in var.multipliers:
        assert float(np.min(np.abs(ex.multipliers - mu))) <= tol_mu
    assert ex.stable and var.stable


def test_fallback_and_errors(base: SDOFModel) -> None:
    """A smooth (Fourier) stiffness is not covered: ``auto`` integrates the variational
    equations; asking for ``exact`` or an unknown route is an input error."""
    fourier = dataclasses.replace(base, stiffness=base.stiffness.truncated(5))
    y0 = fourier.initial_state()
    period = 1 / fourier.mesh_frequency
    y_auto, phi_auto = integrate_with_sensitivity(fourier, y0, period, 1e-10)
    y_var, phi_var = integrate_with_sensitivity(fourier, y0, period, 1e-10, route="variational")
    assert np.array_equal(y_auto, y_var) and np.array_equal(phi_auto, phi_var)
    with pytest.raises(InputError, match="exact_contact"):
        integrate_with_sensitivity(fourier, y0, period, route="exact")
    with pytest.raises(InputError, match="route"):
        integrate_with_sensitivity(base, y0, period, route="euler")
