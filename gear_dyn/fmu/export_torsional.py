"""The torsional model as data for the native FMU: its table in the mesh phase and constants.

The kernel (``solvers/kernel/gd_torsional.c``) steps the four states ``[q1, q2, q1', q2']``
of :class:`~gear_dyn.models.torsional.TorsionalModel` (eccentricity and friction; no backlash,
no transmission error) from a table of its state-free coefficients in the mesh phase, computed
where the solvers' ``kernel`` method computes it too,
:func:`gear_dyn.solvers.kernel.tables_torsional.torsional_table` (re-exported here with its
types). Why tables in phase, and the figures: docs/native_fmu.md, "The torsional model".
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.fmu.export import RK_ERROR, NotNativeError
from gear_dyn.geometry import GearPair
from gear_dyn.solvers.kernel.tables_torsional import FOURIER_CUTS as FOURIER_CUTS
from gear_dyn.solvers.kernel.tables_torsional import FOURIER_SAMPLES as FOURIER_SAMPLES
from gear_dyn.solvers.kernel.tables_torsional import KINEMATICS as KINEMATICS
from gear_dyn.solvers.kernel.tables_torsional import MAX_DEGREE as MAX_DEGREE
from gear_dyn.solvers.kernel.tables_torsional import MIN_DEGREE as MIN_DEGREE
from gear_dyn.solvers.kernel.tables_torsional import QUANTITIES as QUANTITIES
from gear_dyn.solvers.kernel.tables_torsional import TABLE_ERROR as TABLE_ERROR
from gear_dyn.solvers.kernel.tables_torsional import LineKinematics as LineKinematics
from gear_dyn.solvers.kernel.tables_torsional import TorsionalTable, torsional_table

FloatArray = NDArray[np.float64]

@dataclass(frozen=True)
class TorsionalNative:
    """What the native FMU needs for the torsional model.

    Attributes
    ----------
    table : TorsionalTable
    inertias : (float, float)
        I1, I2 in kg m^2.
    mass : float
        Effective mass m_e in kg (damping c = 2 xi sqrt(m_e k_m)).
    mean_stiffness : float
        k_m in N/m.
    rb1, rb2 : float
        Base radii in m.
    z1, z2 : int
        Teeth (f_m = z1 w1 / 2 pi; nominal w2 = w1 z1 / z2).
    mean_arms : (float, float)
        Mean friction arms (m): W = T1 / (r_b1 - phi1), T2 = W (r_b2 + phi2).
    load_torque : float or None
        A fixed T2 in N m, None to balance T1 as above.
    friction : bool
        Friction torques modelled.
    q_scale : (float, float, float, float)
        State scales of the error control (rad, rad, rad/s, rad/s): the model's
        ``state_scale``.
    x_scale : float
        Displacement scale along the line of action, m.
    speed, torque, damping_ratio, tolerance : float
        Start values: rad/s, N m, -, - (relative solver tolerance).
    """

    table: TorsionalTable
    inertias: tuple[float, float]
    mass: float
    mean_stiffness: float
    rb1: float
    rb2: float
    z1: int
    z2: int
    mean_arms: tuple[float, float]
    load_torque: float | None
    friction: bool
    q_scale: tuple[float, float, float, float]
    x_scale: float
    speed: float
    torque: float
    damping_ratio: float
    tolerance: float
    #: no backlash, no TE in the torsional kernel (the names the FMU code shares with NativeModel)
    half_gap: None = None
    transmission_error: bool = False
    load_tables: bool = False

    @property
    def static_deflection(self) -> float:
        """W / k_m at the start torque, m."""
        return self.torque / (self.rb1 - self.mean_arms[0]) / self.mean_stiffness

    @property
    def stated_error(self) -> float:
        """Stated error of the DTE relative to :attr:`static_deflection`: :data:`.RK_ERROR`."""
        return RK_ERROR


def torsional_native(model: Any, pair: GearPair, tolerance: float = 1e-10) -> TorsionalNative:
    """The native FMU's data for a :class:`~gear_dyn.models.torsional.TorsionalModel`.

    Raises
    ------
    NotNativeError
        Backlash or a transmission error (not in the torsional kernel).
    InputError
        A table no polynomial degree fits.
    """
    missing = [n for n in ("backlash", "transmission_error") if getattr(model, n) is not None]
    if missing:
        raise NotNativeError(f"the torsional kernel has no {' and no '.join(missing)}")
    sc = [float(v) for v in model.state_scale]
    return TorsionalNative(
        table=torsional_table(model), inertias=(float(model.inertias[0]),
                                                 float(model.inertias[1])),
        mass=float(model.effective_mass), mean_stiffness=float(model.mean_stiffness),
        rb1=pair.rb1, rb2=pair.rb2, z1=int(pair.z1), z2=int(pair.z2),
        mean_arms=(float(model.mean_friction_arms[0]), float(model.mean_friction_arms[1])),
        load_torque=None if model.load_torque is None else float(model.load_torque),
        friction=model.friction is not None, q_scale=(sc[0], sc[1], sc[2], sc[3]),
        x_scale=sc[0] * pair.rb1, speed=float(model.speed),
        torque=float(model.torque), damping_ratio=float(model.damping_ratio),
        tolerance=float(tolerance))

