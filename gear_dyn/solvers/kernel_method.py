"""The ``kernel`` method: the native FMU's compiled stepper over the whole output grid.

The model goes to the compiled kernel as its tables in the mesh phase (the ones the native FMU
is built from, :mod:`gear_dyn.solvers.kernel.tables`; the eccentric torsional model with
polynomials on every piece, :func:`~gear_dyn.solvers.kernel.tables_torsional.torsional_table`
with ``lines=False``) and the kernel advances it over the grid in one call
(:func:`gear_dyn.solvers.kernel.run.run`): pieces with constant coefficients in closed form,
the others by the Dormand-Prince 5(4) pair (Dormand & Prince 1980), backlash contact changes
located on the closed form or the dense output; the torsional model's steps end at its
table's piece edges only, its states at the output times from the steps' dense output (of
order 4; Hairer, Norsett & Wanner 1993, II.6).

Where it applies (:func:`kernel_applies`): the single-DOF mesh equation (with or without
backlash and a mesh-periodic transmission error) and the eccentric torsional model without
backlash and transmission error, when the compiled library is present. The kernel form is
built once per model (kept for the model's lifetime, at most :data:`CACHE_SIZE` models); the
torsional model's table, which does not depend on the speed (the eccentric kinematics are
functions of the pinion angle, so every quantity of the table is one of the mesh phase,
de/dt = f_m de/dp), once per :func:`table_key`: the same pair at another speed, such as the
quasi-static reference of the dynamic factor or the next point of a sweep, reuses it.

Error control: the kernel weighs each state's error by ``tol (scale + |y|)``, so a state far
from zero (the gear angle of an eccentric pair holds the eccentric offset, tens of static
deflections) gets a looser control than the solvers' ``rtol`` (relative to the state scale)
means; the kernel runs at ``rtol / (1 + max |e| / x_s)`` (:func:`kernel_tolerance`, ``e`` the
table's transmission error or eccentric offset). The stated error (:func:`check_run`,
:func:`table_bound`, composed in :func:`gear_dyn.analysis.accuracy.estimate_error`) is twice the
difference from a check run with every step halved (:func:`check_run`: the fixed times the
steps end at halved, and a :data:`CHECK_TIGHTEN` = 2^5 times tighter tolerance: where those
times set the steps a tighter tolerance alone changes nothing, where the tolerance does it
halves them) from a start moved
by :data:`CHECK_NUDGE` of the state scale (closed-form pieces do not depend on the tolerance:
the nudge shows rounding that an unstable response amplifies), plus a bound on the table's
interpolation error carried to the DTE.
"""

from __future__ import annotations

import math
import threading
import weakref
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import GearDynError, InputError
from gear_dyn.models.base import Model
from gear_dyn.solvers import kernel
from gear_dyn.solvers.kernel.run import TOL_RANGE, KernelModel, kernel_model, run
from gear_dyn.solvers.kernel.tables_torsional import (
    TorsionalTable,
    split_table,
    torsional_table,
)
from gear_dyn.solvers.settings import SolverSettings

FloatArray = NDArray[np.float64]

#: the check run's tolerance is this many times tighter than the run's: 2^5, one halving of
#: the step of the fifth-order pair (its step goes as tol^(1/5), its error as h^5)
CHECK_TIGHTEN = 2.0**5
#: ... from a start moved by this share of the state scale
CHECK_NUDGE = 1e-12
#: safety factor of the table part of the stated error
TABLE_SAFETY = 2.0
#: models whose kernel form is kept
CACHE_SIZE = 4

_CACHE: dict[tuple[int, bool], tuple[weakref.ref[Any], KernelModel]] = {}
#: the torsional tables by :func:`table_key` and split (at most 2 CACHE_SIZE)
_TABLES: dict[Any, TorsionalTable] = {}
_LOCK = threading.RLock()  # re-entrant: a weakref callback may run inside a locked block


#: largest table error (relative, ``max_error``) for which ``auto`` picks the kernel
AUTO_TABLE_ERROR = 1e-9


def _available() -> bool:
    """The compiled library loads (a copy of gear_dyn without it, the pythonfmu FMU's, has none)."""
    try:
        kernel.library()
    except (GearDynError, OSError, TypeError, AttributeError):
        return False
    return True


def kernel_applies(model: Model) -> bool:
    """True for the single-DOF mesh equation with mesh-periodic coefficients (``mesh_periodic``:
    its table spans one mesh cycle) and for the eccentric torsional model (two inertias,
    ``force_form``, ``eccentric``) without backlash and transmission error, with the compiled
    kernel present."""
    n = len(model.state_labels)
    if n == 2:
        ok = bool(model.mesh_periodic)
    elif n == 4:
        ok = (bool(getattr(model, "eccentric", False)) and model.backlash is None
              and callable(getattr(model, "force_form", None))
              and getattr(model, "transmission_error", None) is None)
    else:
        ok = False
    return ok and _available()


def kernel_auto(model: Model, t_grid: FloatArray | None = None) -> bool:
    """True where ``auto`` picks the kernel (:func:`kernel_applies`): an eccentric torsional
    model whose table meets :data:`AUTO_TABLE_ERROR`, on any grid of two or more times and
    whatever tables the process holds, so a run's method depends on the model alone, not on
    what ran before it. The table spans the hunting period whatever the run's span (it is
    built once per :func:`table_key` and kept), so a short run of a pair without one pays for
    it (docs/solvers.md has the measurement); ``gauss`` stays available by name. Where no
    table fits (:class:`~gear_dyn.errors.InputError`) or the library is not built, ``auto``
    goes on to its next method.

    Single-DOF models never take it under ``auto``: the linear ones keep their exact and
    periodic routes, and the one with backlash and piecewise-constant stiffness takes
    ``exact_contact``, the compiled contact walk, which runs as fast as the kernel on the
    packaged backlash scene at its mesh resonance (``benchmarks/bench_kernel_method.py``) and
    brackets every contact change by a bound on the closed form, where the kernel samples a
    closed-form piece 32 times per natural period. The kernel stays available by name for
    every single-DOF model with mesh-periodic coefficients."""
    if not kernel_applies(model) or len(model.state_labels) == 2:
        return False
    if t_grid is None or len(t_grid) < 2:
        return False
    try:
        km = kernel_form(model)
    except InputError:  # no table fits
        return False
    return km.table_error <= AUTO_TABLE_ERROR


def kernel_form(model: Model, split: bool = False) -> KernelModel:
    """The model's kernel form, built on first use and kept while the model lives (threads of a
    sweep share the cache under a lock; a model is built once per thread at most). ``split``:
    the torsional model's form on its table with every piece split at its middle (the check
    run's, :func:`check_run`)."""
    key = (id(model), split)
    with _LOCK:
        hit = _CACHE.get(key)
    if hit is not None and hit[0]() is model:
        return hit[1]
    table = shared_table(model, split) if len(model.state_labels) == 4 else None
    km = kernel_model(model, table)

    def forget(_ref: weakref.ref[Any], k: tuple[int, bool] = key) -> None:
        with _LOCK:
            _CACHE.pop(k, None)

    with _LOCK:
        while len(_CACHE) >= 2 * CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = (weakref.ref(model, forget), km)
    return km


def table_key(model: Model) -> tuple[Any, ...]:
    """What the torsional model's table depends on: the pair, the stiffness, the eccentricity,
    the friction and the torque (the static deflection is the unit of its error), not the
    speed, the inertias or the damping."""
    tm: Any = model
    return (tm.pair, tm.stiffness, tm.eccentricity, tm.friction, float(tm.torque))


def shared_table(model: Model, split: bool = False) -> TorsionalTable:
    """The torsional model's polynomial table (``torsional_table(model, lines=False)``), built
    once per :func:`table_key` (module docstring); ``split``: with every piece split at its
    middle (:func:`~gear_dyn.solvers.kernel.tables_torsional.split_table`, the check run's)."""
    key = (table_key(model), split)
    with _LOCK:
        tab = _TABLES.get(key)
    if tab is not None:
        return tab
    tab = split_table(shared_table(model)) if split else torsional_table(model, lines=False)
    with _LOCK:
        while len(_TABLES) >= 2 * CACHE_SIZE:
            _TABLES.pop(next(iter(_TABLES)))
        _TABLES[key] = tab
    return tab


def table_ready(model: Model) -> bool:
    """The torsional model's table is built (:func:`shared_table` costs nothing)."""
    with _LOCK:
        return (table_key(model), False) in _TABLES


def _x_scale(model: Model) -> float:
    """The static deflection W/k_m (m), the unit of the errors."""
    return max(float(model.static_load) / float(model.mean_stiffness or 1.0), 1e-300)


def kernel_tolerance(model: Model, km: KernelModel, rtol: float) -> float:
    """The kernel's tolerance for the solvers' ``rtol``: ``rtol / (1 + max |e| / x_s)``, within
    the kernel's range (module docstring)."""
    e_row = 1 if km.n_states == 2 else 0  # (k, e, de) or (e, de, k, phi1, phi2)
    coef = km.table.coef
    e_max = float(np.max(np.abs(coef[:, e_row, -1]))) if coef.size else 0.0
    tol = rtol / (1.0 + e_max / _x_scale(model))
    return min(max(tol, TOL_RANGE[0]), TOL_RANGE[1])


def propagate_kernel(model: Model, t_grid: FloatArray, settings: SolverSettings,
                     y0: FloatArray | None = None) -> tuple[FloatArray, dict[str, Any]]:
    """States on ``t_grid`` by the compiled kernel.

    Returns
    -------
    y : ndarray (n_states, n_t)
    stats : dict with n_events, kernel_tolerance, n_segments (table pieces crossed), nfev 0,
        and for the torsional model ``excitations``: its table's ``e_ecc``, ``e_ecc_rate``,
        ``stiffness``, ``phi1``, ``phi2`` on the grid (for ``TorsionalModel.outputs``)

    Raises
    ------
    SolverError
        A failed kernel step (its message says what to change).
    """
    km = kernel_form(model)
    tol = kernel_tolerance(model, km, settings.rtol)
    y_start = np.asarray(model.initial_state() if y0 is None else y0, dtype=float)
    y, st = run(km, t_grid, y_start, tol, values=True)
    pieces = km.table.breaks.size - 1
    span = (float(t_grid[-1]) - float(t_grid[0])) * km.mesh_frequency / km.period
    out = {"nfev": 0, "njev": 0, "nlu": 0, "n_segments": int(math.ceil(span * pieces)),
           "n_events": st["n_events"], "kernel_tolerance": tol}
    if "values" in st:  # the torsional model: its table on the grid, for the outputs
        out["excitations"] = _excitations(km, st["values"])
    return y, out


def _excitations(km: KernelModel, v: FloatArray) -> dict[str, FloatArray]:
    """The torsional table's values ``v`` (5, n) as ``TorsionalModel.outputs`` takes them."""
    return {"e_ecc": v[0], "e_ecc_rate": v[1] * km.mesh_frequency, "stiffness": v[2],
            "phi1": v[3], "phi2": v[4]}


def check_run(model: Model, t_grid: FloatArray, y0: FloatArray, rtol: float
              ) -> tuple[FloatArray, float, dict[str, FloatArray] | None]:
    """The check run of the error estimate of a run at ``rtol``, on ``t_grid``, its tolerance
    and, for the torsional model, its table on the grid (as :func:`propagate_kernel`'s
    ``excitations``; None for the single-DOF model).

    Every step of the run is halved. The run's steps end where its tolerance puts them or at
    fixed times: the output times for the single-DOF model (the check adds the grid's
    midpoints), the table's piece edges for the torsional model (whose outputs come from the
    steps' dense output; the check steps the table with every piece split at its middle,
    :func:`~gear_dyn.solvers.kernel.tables_torsional.split_table`); and its tolerance is
    :data:`CHECK_TIGHTEN` = 2^5 times the run's kernel tolerance (down to the kernel's 1e-14),
    which halves a step the tolerance set (the Dormand-Prince 5(4) step goes as tol^(1/5)). Its
    error is then about 1/32 of the run's, and twice the difference (the estimate's
    ``SAFETY``) bounds the run's error. A tighter tolerance alone does not: where the fixed
    times, not the tolerance, set the steps, two runs take the same steps and agree. The start
    is moved by :data:`CHECK_NUDGE` of the state scale: the closed-form pieces do not depend on
    the tolerance, and the nudge shows where rounding grows (an unstable or chaotic response),
    as ``exact_contact``'s check does."""
    km = kernel_form(model)
    tol = max(kernel_tolerance(model, km, rtol) / CHECK_TIGHTEN, TOL_RANGE[0])
    start = np.asarray(y0, dtype=float) + CHECK_NUDGE * np.asarray(model.state_scale, float)
    t = np.asarray(t_grid, dtype=float)
    if km.n_states == 4:
        y, st = run(kernel_form(model, split=True), t, start, tol, values=True)
        return y, tol, _excitations(km, st["values"])
    both = np.empty(2 * t.size - 1)
    both[0::2] = t
    both[1::2] = 0.5 * (t[1:] + t[:-1])
    return np.ascontiguousarray(run(km, both, start, tol)[0][:, 0::2]), tol, None


def table_bound(model: Model, t_grid: FloatArray, y: FloatArray) -> float:
    """A bound on the DTE error (over W/k_m) from the table's interpolation error.

    A force error ``dF`` moves the DTE by at most the dynamic amplification ``1 + 1/(2 xi)``
    times ``dF / k_m``; the table's errors give ``dF / W <= err_k D + err_e K + err_de
    2 xi f_m / omega_n`` with ``D`` the largest mesh deflection over ``x_s`` on the run and
    ``K = k_max / k_m`` (errors ``max_error`` relative to ``k_m`` and ``x_s``), times
    :data:`TABLE_SAFETY`; ``D`` and ``K`` from bounds (the run's largest DTE plus the table's
    largest ``|e|``, the table's largest ``k``, each piece's bounded by the sum of its
    coefficients' magnitudes), not from the table evaluated on the grid. 0 for an exact table;
    inf without damping for a fitted one."""
    km = kernel_form(model)
    errs = km.table.max_error
    if not any(v > 0 for v in errs.values()):
        return 0.0
    xi = float(getattr(model, "damping_ratio", 0.0))
    if xi <= 0.0:
        return math.inf
    x_s = _x_scale(model)
    # bounds, not samples: on a piece |sum_j c_j s^j| <= sum_j |c_j| (|s| <= 1)
    top = np.max(np.sum(np.abs(km.table.coef), axis=2), axis=0)  # per quantity
    if km.n_states == 2:
        k_max, e_max = top[0], top[1]
        u_max = float(np.max(np.abs(y[0]))) + e_max
        err_k, err_e, err_de = errs.get("k", 0.0), errs.get("e", 0.0), errs.get("de", 0.0)
    else:
        e_max, k_max = top[0], top[2]
        pair: Any = model.pair  # type: ignore[attr-defined]
        u_max = float(np.max(np.abs(pair.rb1 * y[0] - pair.rb2 * y[1]))) + e_max
        err_k, err_e, err_de = errs["stiffness"], errs["e_ecc"], errs["de_dp"]
        err_k = max(err_k, errs["phi1"], errs["phi2"])  # friction arms: relative to r_b
    d = u_max / x_s
    kk = float(k_max) / float(model.mean_stiffness or 1.0)
    fn = float(model.natural_frequency or km.mesh_frequency)
    force = err_k * d + err_e * kk + err_de * 2 * xi * km.mesh_frequency / (2 * math.pi * fn)
    return TABLE_SAFETY * (1.0 + 1.0 / (2.0 * xi)) * force
