"""The native FMU's stepper as a solver: the kernel model built in memory, run over a grid.

The compiled kernel (``gd_kernel.c``, ``gd_torsional.c``) steps the single-DOF and the
torsional model from their tables in the mesh phase (:mod:`.tables`, :mod:`.tables_torsional`,
the ones the native FMU writes into its ``model_data.c``): closed form on pieces with constant
coefficients, elsewhere the Dormand-Prince 5(4) pair with error control (Dormand & Prince 1980;
Hairer, Norsett & Wanner 1993), backlash contact changes located on the closed form or the dense
output. Here the same ``gd_model`` is built as ctypes structures from those arrays
(:func:`kernel_model`) and advanced over a whole output grid in one call (``gd_run`` in
``gd_run.c``, :func:`run`), without the Python interpreter in the loop.
"""

from __future__ import annotations

import ctypes
import functools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import SolverError
from gear_dyn.solvers import kernel
from gear_dyn.solvers.kernel.tables import PhaseTable, phase_table
from gear_dyn.solvers.kernel.tables_torsional import TorsionalTable, torsional_table

FloatArray = NDArray[np.float64]

#: parameters and inputs of the kernel (GD_SPEED .. GD_TOL in gd_kernel.h)
NPAR = 5
#: the kernel's tolerance range (solver.tolerance of the native FMU)
TOL_RANGE = (1e-14, 1e-3)
_P = ctypes.POINTER


class GdParam(ctypes.Structure):
    """``gd_param`` (gd_kernel.h)."""

    _fields_ = [("name", ctypes.c_char_p), ("unit", ctypes.c_char_p), ("low", ctypes.c_double),
                ("high", ctypes.c_double), ("low_open", ctypes.c_int)]


class GdLines(ctypes.Structure):
    """``gd_lines``: the contact-line form of an eccentric pair."""

    _fields_ = [("n_terms", ctypes.c_int), ("period", ctypes.c_double),
                ("term_k", _P(ctypes.c_ushort)), ("term_q", _P(ctypes.c_ubyte)),
                ("term_ab", _P(ctypes.c_double)), ("pitch", ctypes.c_double),
                ("width", ctypes.c_double), ("sin_bb", ctypes.c_double),
                ("face_width", ctypes.c_double), ("l_ac0", ctypes.c_double),
                ("index0", ctypes.c_int), ("n_index", ctypes.c_int),
                ("per_length", ctypes.c_double), ("mu", ctypes.c_double)]


class GdTors(ctypes.Structure):
    """``gd_tors``: the torsional model's constants."""

    _fields_ = [("inertia", ctypes.c_double * 2), ("z2", ctypes.c_double),
                ("arm", ctypes.c_double * 2), ("load_fixed", ctypes.c_double),
                ("q_scale", ctypes.c_double * 4), ("lines", _P(GdLines))]


class GdModel(ctypes.Structure):
    """``gd_model``: the table and the constants."""

    _fields_ = [("format", ctypes.c_int), ("n_pieces", ctypes.c_int), ("degree", ctypes.c_int),
                ("has_te", ctypes.c_int), ("has_backlash", ctypes.c_int),
                ("breaks", _P(ctypes.c_double)), ("coef", _P(ctypes.c_double)),
                ("flat", _P(ctypes.c_ubyte)), ("params", _P(GdParam)),
                ("start", ctypes.c_double * NPAR), ("mass", ctypes.c_double),
                ("k_mean", ctypes.c_double), ("rb1", ctypes.c_double), ("rb2", ctypes.c_double),
                ("z1", ctypes.c_double), ("phase0", ctypes.c_double),
                ("x_scale", ctypes.c_double), ("tors", _P(GdTors))]


class GdState(ctypes.Structure):
    """``gd_state``: parameters, time, states, mesh phase, step size and contact regime."""

    _fields_ = [("par", ctypes.c_double * NPAR), ("t", ctypes.c_double), ("x", ctypes.c_double),
                ("v", ctypes.c_double), ("frac", ctypes.c_double), ("h", ctypes.c_double),
                ("q", ctypes.c_double * 4), ("piece", ctypes.c_int), ("regime", ctypes.c_int),
                ("n_events", ctypes.c_long)]


@dataclass(frozen=True, eq=False)
class KernelModel:
    """A model as the kernel steps it: the ctypes ``gd_model`` and what it points to.

    Attributes
    ----------
    c_model : GdModel
        The structure passed to the kernel.
    keep : tuple
        The arrays and structures it points to (alive as long as this object).
    table : PhaseTable or TorsionalTable
        The table in the mesh phase.
    par : tuple of float
        Speed (rad/s), torque (N m), damping ratio, half gap (m), tolerance (replaced per run).
    period : float
        Mesh cycles the table spans.
    mesh_frequency : float
        f_m in Hz (the phase advances by f_m t cycles).
    phase0 : float
        Mesh phase at t = 0 (cycles).
    n_states : int
        2 (x, v) or 4 (q1, q2, q1', q2').
    """

    c_model: GdModel
    keep: tuple[Any, ...]
    table: PhaseTable | TorsionalTable
    par: tuple[float, ...]
    period: float
    mesh_frequency: float
    phase0: float
    n_states: int

    @property
    def table_error(self) -> float:
        """The table's largest interpolation error on its check points, relative to each
        quantity's scale (``max_error``; 0 for an exact piecewise-linear table)."""
        return float(max(self.table.max_error.values(), default=0.0))


def _arr(a: Any, dtype: Any, ctype: Any) -> tuple[NDArray[Any], Any]:
    """A contiguous copy of ``a`` (at least one element: C has no empty arrays) and its pointer."""
    arr = np.ascontiguousarray(np.ravel(a), dtype=dtype)
    if arr.size == 0:
        arr = np.zeros(1, dtype=dtype)
    return arr, arr.ctypes.data_as(_P(ctype))


def _params() -> tuple[Any, Any]:
    """The kernel's parameter descriptions (names only matter to the FMU glue's messages)."""
    p = (GdParam * NPAR)()
    for i, name in enumerate((b"speed", b"torque", b"damping.ratio", b"half_gap", b"tol")):
        p[i] = GdParam(name, b"1", 0.0, math.inf, 0)
    return p, ctypes.cast(p, _P(GdParam))


@functools.cache
def _table_format() -> int:
    """GD_TABLE_FORMAT of gd_kernel.h (read once)."""
    import re

    text = (kernel.SOURCE_DIR / "gd_kernel.h").read_text("utf-8")
    return int(re.search(r"#define GD_TABLE_FORMAT (\d+)", text)[1])  # type: ignore[index]


def kernel_model(model: Any, table: TorsionalTable | None = None) -> KernelModel:
    """The kernel's form of a single-DOF model (``SDOFModel``: two states) or of an eccentric
    torsional model (``TorsionalModel`` without backlash and transmission error), whose table
    (``torsional_table(model, lines=False)``) may be given: it is the same for the pair at any
    speed (:func:`gear_dyn.solvers.kernel_method.table_key`).

    The single-DOF model goes in with ``r_b1 = 1``, ``z1 = 1`` and its mesh frequency as the
    speed: the kernel's ``W = T1 / r_b1`` and ``f_m = z1 w1 / (2 pi)`` are then the model's
    static load and mesh frequency.

    Raises
    ------
    InputError
        A stiffness or transmission error no table represents (from the table builders).
    """
    keep: list[Any] = []
    params, p_params = _params()
    keep.append(params)
    fm = float(model.mesh_frequency)
    if len(model.state_labels) == 2:
        sd = phase_table(model)
        br, p_br = _arr(sd.breaks, np.float64, ctypes.c_double)
        cf, p_cf = _arr(sd.coef, np.float64, ctypes.c_double)
        fl, p_fl = _arr(sd.flat, np.uint8, ctypes.c_ubyte)
        keep += [br, cf, fl]
        gap = 0.0 if model.backlash is None else float(model.backlash)
        par = (2 * math.pi * fm, float(model.static_load), float(model.damping_ratio),
               gap or 1e-5, 1e-8)
        c_model = GdModel(_table_format(), br.size - 1, sd.degree,
                          int(model.transmission_error is not None),
                          int(model.backlash is not None), p_br, p_cf, p_fl, p_params,
                          (ctypes.c_double * NPAR)(*par), float(model.mass),
                          float(model.mean_stiffness), 1.0, 1.0, 1.0, 0.0,
                          float(model.state_scale[0]), None)
        return KernelModel(c_model, tuple(keep), sd, par, 1.0, fm, float(model.phase0), 2)
    # polynomials: cheaper to step
    tab = torsional_table(model, lines=False) if table is None else table
    br, p_br = _arr(tab.breaks, np.float64, ctypes.c_double)
    cf, p_cf = _arr(tab.coef, np.float64, ctypes.c_double)
    fl, p_fl = _arr(np.zeros(br.size - 1), np.uint8, ctypes.c_ubyte)
    keep += [br, cf, fl]
    p_lines = None  # polynomials: no contact-line form (GdLines, the FMU's)
    pair = model.pair
    arms = model.mean_friction_arms
    tors = GdTors((ctypes.c_double * 2)(*model.inertias), float(pair.z2),
                  (ctypes.c_double * 2)(*arms),
                  -1.0 if model.load_torque is None else float(model.load_torque),
                  (ctypes.c_double * 4)(*(float(v) for v in model.state_scale)), p_lines)
    keep.append(tors)
    par = (float(model.speed), float(model.torque), float(model.damping_ratio), 1e-5, 1e-8)
    c_model = GdModel(_table_format(), br.size - 1, tab.degree, 0, 0, p_br, p_cf, p_fl,
                      p_params, (ctypes.c_double * NPAR)(*par), float(model.effective_mass),
                      float(model.mean_stiffness), pair.rb1, pair.rb2, float(pair.z1), 0.0,
                      float(model.state_scale[0]) * pair.rb1, ctypes.pointer(tors))
    return KernelModel(c_model, tuple(keep), tab, par, float(tab.period), fm, 0.0, 4)


def _regime(km: KernelModel, phase: float, y: FloatArray) -> int:
    """The contact regime of the single-DOF state ``y`` at ``phase``: 1 drive flank, 0 in the
    gap, -1 back flank (1 without backlash)."""
    if not km.c_model.has_backlash:
        return 1
    u = float(y[0]) - float(km.table.evaluate(np.array([phase]))[1, 0])
    b = km.par[3]
    return 1 if u > b else (-1 if u < -b else 0)


def run(km: KernelModel, t_grid: FloatArray, y0: FloatArray, tolerance: float,
        values: bool = False) -> tuple[FloatArray, dict[str, Any]]:
    """States on ``t_grid`` (non-decreasing, from the initial time) from ``y0``, in one call of
    the compiled kernel.

    Parameters
    ----------
    km : KernelModel
    t_grid : ndarray
        Output times in s; the run starts at ``t_grid[0]``.
    y0 : ndarray
        Initial state (``x`` in m, ``v`` in m/s; or ``q1, q2`` in rad, ``q1', q2'`` in rad/s).
    tolerance : float
        Relative tolerance of the Runge-Kutta pieces (clipped to the kernel's
        1e-14..1e-3), relative to the state scales.
    values : bool
        The torsional model: also its table's values on the grid (``stats["values"]``).

    Returns
    -------
    y : ndarray (n_states, n_t)
    stats : dict with n_events (contact changes located) and, with ``values``, ``values``:
        ndarray (5, n_t) of e_ecc (m), de_ecc/dp (m/cycle), k (N/m), phi1, phi2 (m)

    Raises
    ------
    SolverError
        A failed step (step size underflow, too many contact changes) or a non-finite state.
    """
    lib = kernel.library()
    t = np.ascontiguousarray(t_grid, dtype=np.float64)
    y0 = np.asarray(y0, dtype=float)
    out = np.empty((t.size, km.n_states))
    s = GdState()
    par = list(km.par)
    par[4] = min(max(float(tolerance), TOL_RANGE[0]), TOL_RANGE[1])
    s.par[:] = par
    lib.gd_start(ctypes.byref(s), ctypes.byref(km.c_model), float(t[0]))
    # the model's phase at the start, and its piece (gd_start assumes the table's own origin)
    phase = (km.phase0 + km.mesh_frequency * float(t[0])) % km.period
    br = km.table.breaks
    s.frac = phase
    s.piece = int(np.clip(np.searchsorted(br, phase, side="right") - 1, 0, br.size - 2))
    if km.n_states == 2:
        s.x, s.v = float(y0[0]), float(y0[1])
        s.regime = _regime(km, phase, y0)
    else:
        s.q[:] = [float(v) for v in y0]
    status = ctypes.c_int(0)
    coef = np.empty((t.size, 5)) if values and km.n_states == 4 else None
    done = lib.gd_run(ctypes.byref(s), ctypes.byref(km.c_model), t.size, t.ctypes.data,
                      out.ctypes.data, None if coef is None else coef.ctypes.data,
                      ctypes.byref(status))
    if status.value != 0 or done != t.size:
        at = float(t[min(int(done), t.size - 1)])
        raise SolverError(f"kernel: step failed at t = {at:.6g} s (step size underflow, too many "
                          "contact changes or a non-finite state); lower solver.rtol or use "
                          "another solver.method")
    stats: dict[str, Any] = {"n_events": int(s.n_events)}
    if coef is not None:
        stats["values"] = np.ascontiguousarray(coef.T)
    return np.ascontiguousarray(out.T), stats
