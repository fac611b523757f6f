"""The single-DOF model as data for the native FMU: piecewise polynomials in the mesh phase.

The native FMU's C kernel (``gear_dyn/solvers/kernel/gd_kernel.c``) steps the single-DOF model
from a table over one mesh cycle, plus the constants here. The table is computed where the
solvers' ``kernel`` method computes it too, :func:`gear_dyn.solvers.kernel.tables.phase_table`
(re-exported here); which tables are exact and which fitted, and which pieces the kernel
propagates in closed form (*flat*): docs/native_fmu.md, "Tables".
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError
from gear_dyn.geometry import GearPair
from gear_dyn.solvers.kernel.tables import CHECK_POINTS as CHECK_POINTS
from gear_dyn.solvers.kernel.tables import MIN_WIDTH as MIN_WIDTH
from gear_dyn.solvers.kernel.tables import SMOOTH_DEGREE as SMOOTH_DEGREE
from gear_dyn.solvers.kernel.tables import SMOOTH_PIECES as SMOOTH_PIECES
from gear_dyn.solvers.kernel.tables import PhaseTable, phase_table
from gear_dyn.solvers.kernel.tables import piecewise_values as piecewise_values

FloatArray = NDArray[np.float64]

#: stated error of the native FMU's DTE, in units of the static deflection W/k_m: every piece
#: closed form on an exact table (rounding only) ...
EXACT_ERROR = 1e-9
#: ... and otherwise (Runge-Kutta pieces at solver.tolerance <= 1e-10, or a fitted table)
RK_ERROR = 1e-6


class NotNativeError(InputError):
    """The scene has no native FMU (a part the kernel lacks, or a table over a requested size):
    build the pythonfmu FMU instead.

    Attributes
    ----------
    reason : str
        Why, in a few words ("the torsional kernel has no backlash").
    """

    def __init__(self, reason: str) -> None:
        super().__init__(f"native FMU: {reason}; build with --backend python")
        self.reason = reason


@dataclass(frozen=True)
class NativeModel:
    """What the native FMU needs: the table, the constants and the parameters' start values.

    Attributes
    ----------
    table : PhaseTable
    mass : float
        Equivalent mass m_e in kg.
    mean_stiffness : float
        k_m in N/m (damping c = 2 xi sqrt(m_e k_m)).
    rb1, rb2 : float
        Base radii in m (W = T1 / r_b1; driven speed (r_b1 w1 - x') / r_b2).
    z1 : int
        Pinion teeth (f_m = z1 w1 / 2 pi).
    phase0 : float
        Mesh phase at the start, cycles.
    x_scale : float
        Displacement scale of the error control, m (the model's ``state_scale[0]``).
    speed, torque, damping_ratio, tolerance : float
        Start values: rad/s, N m, -, - (relative solver tolerance).
    half_gap : float or None
        Backlash half gap in m, None without backlash.
    transmission_error : bool
        The table carries a static transmission error.
    load_tables : bool
        The tables come from a loaded-contact analysis at the build torque (tip relief): the
        torque input then changes W only, the tables stay those of ``torque``.
    """

    table: PhaseTable
    mass: float
    mean_stiffness: float
    rb1: float
    rb2: float
    z1: int
    phase0: float
    x_scale: float
    speed: float
    torque: float
    damping_ratio: float
    tolerance: float
    half_gap: float | None
    transmission_error: bool
    load_tables: bool = False

    @property
    def static_deflection(self) -> float:
        """W / k_m at the start torque, m."""
        return self.torque / self.rb1 / self.mean_stiffness

    @property
    def stated_error(self) -> float:
        """Stated error of the DTE relative to :attr:`static_deflection`: :data:`EXACT_ERROR`
        when every piece is exact and flat (closed form), else :data:`RK_ERROR`."""
        t = self.table
        return EXACT_ERROR if t.exact and bool(np.all(t.flat)) else RK_ERROR


def native_model(model: Any, pair: GearPair, speed: float, torque: float,
                 tolerance: float = 1e-10, load_tables: bool = False) -> NativeModel:
    """The native FMU's data for a single-DOF model built at ``speed`` (rad/s), ``torque`` (N m).

    ``load_tables``: the model's stiffness and TE come from a loaded-contact analysis at
    ``torque`` (tip relief), see ``NativeModel.load_tables``.

    Raises
    ------
    NotNativeError
        Not a single-DOF mesh model (the torsional model: :mod:`gear_dyn.fmu.export_torsional`).
    InputError
        A stiffness the table cannot represent.
    """
    if np.size(getattr(model, "state_scale", ())) != 2:  # the single-DOF model's (x, x')
        raise NotNativeError(f"the {type(model).__name__} model is not a single-DOF model")
    return NativeModel(
        table=phase_table(model), mass=model.mass, mean_stiffness=model.mean_stiffness,
        rb1=pair.rb1, rb2=pair.rb2, z1=int(pair.z1), phase0=float(model.phase0),
        x_scale=float(model.state_scale[0]), speed=float(speed), torque=float(torque),
        damping_ratio=float(model.damping_ratio), tolerance=float(tolerance),
        half_gap=None if model.backlash is None else float(model.backlash),
        transmission_error=model.transmission_error is not None,
        load_tables=load_tables,
    )
