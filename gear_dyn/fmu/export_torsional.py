"""The torsional model as data for the native FMU: piecewise polynomials in the mesh phase.

The kernel (``solvers/kernel/gd_torsional.c``) steps the four states ``[q1, q2, q1', q2']``
of :class:`~gear_dyn.models.torsional.TorsionalModel` (eccentricity and friction; no backlash,
no transmission error) from a table of its state-free coefficients in the mesh phase
``p = z1 th1 / (2 pi)`` (cycles): :data:`QUANTITIES` on pieces between the model's switching
instants, over the hunting period with eccentricity (one mesh cycle without), each interpolated
at Chebyshev points with the lowest degree (<= :data:`MAX_DEGREE`) that meets
:data:`TABLE_ERROR` (``TorsionalTable.max_error``). Why tables in phase, and the figures:
docs/native_fmu.md, "The torsional model".
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError
from gear_dyn.fmu.export import CHECK_POINTS, RK_ERROR, NotNativeError, piecewise_values
from gear_dyn.geometry import GearPair
from gear_dyn.models.torsional_table import node_matrix

FloatArray = NDArray[np.float64]

#: the quantities of the table, in the kernel's order
QUANTITIES = ("e_ecc", "de_dp", "stiffness", "phi1", "phi2")
#: table error allowed, relative to each quantity's scale (far below the stated RK_ERROR)
TABLE_ERROR = 1e-9
#: lowest and highest polynomial degree tried
MIN_DEGREE, MAX_DEGREE = 3, 10


@dataclass(frozen=True)
class TorsionalTable:
    """Piecewise polynomials of :data:`QUANTITIES` over one table period in the mesh phase.

    Attributes
    ----------
    breaks : ndarray (n + 1,)
        Piece edges in cycles, from 0 to ``period``.
    degree : int
        Polynomial degree on every piece.
    coef : ndarray (n, 5, degree + 1)
        Coefficients in ``s = (2 p - a - b) / (b - a)`` on the piece ``[a, b]``, highest power
        first, of ``e_ecc`` (m), ``de_ecc/dp`` (m/cycle), ``k`` (N/m), ``phi1``, ``phi2`` (m).
    period : int
        Mesh cycles in the table (the hunting period, or 1).
    max_error : dict
        Largest error on the check points of each quantity, relative to its scale (``e`` and
        ``de/dp`` to the static deflection, ``k`` to the mean stiffness, ``phi`` to r_b).
    """

    breaks: FloatArray
    degree: int
    coef: FloatArray
    period: int
    max_error: dict[str, float]

    #: fitted, not exact (the single-DOF PhaseTable's attribute, for code that shows both)
    exact = False

    def evaluate(self, phase: FloatArray) -> FloatArray:
        """The five quantities at phases (cycles, any real), vectorised: array (5, n)."""
        return piecewise_values(self.breaks, self.coef, phase, float(self.period))


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


def _period_cycles(model: Any) -> int:
    """Mesh cycles in the table: the hunting period with eccentricity, else one."""
    if not model.eccentric:
        return 1
    n = model.mesh.hunting_period * model.mesh_frequency
    if abs(n - round(n)) > 1e-9 * n:
        raise InputError(f"native FMU: the hunting period is {n!r} mesh cycles, not a whole "
                         "number")
    return int(round(n))


def torsional_table(model: Any) -> TorsionalTable:
    """Tabulate the torsional model's state-free coefficients in the mesh phase.

    Raises
    ------
    InputError
        No degree up to :data:`MAX_DEGREE` meets :data:`TABLE_ERROR`.
    """
    fm = model.mesh_frequency
    period = _period_cycles(model)
    sw = np.asarray(model.switching_times(0.0, period / fm), dtype=float) * fm
    br = np.concatenate([[0.0], sw, [float(period)]])
    br = br[np.concatenate([[True], np.diff(br) > 1e-12])]
    br[-1] = float(period)
    a, b = br[:-1], br[1:]
    mid, half = 0.5 * (a + b), 0.5 * (b - a)
    names = ("e_ecc", "e_ecc_rate", "stiffness", "phi1", "phi2")

    def direct(ph: FloatArray) -> FloatArray:
        ex = model.excitations(ph / fm)
        vals = np.array([ex[n] for n in names])
        vals[1] /= fm  # de/dt -> de/dp
        return vals

    x_s = max(model.static_load / model.mean_stiffness, 1e-12)
    scale = np.array([x_s, x_s, model.mean_stiffness, model.pair.rb1, model.pair.rb2])
    u = np.linspace(-0.98, 0.98, CHECK_POINTS)
    chk = (mid[:, None] + half[:, None] * u[None, :]).ravel()
    exact = direct(chk)
    for degree in range(MIN_DEGREE, MAX_DEGREE + 1):
        s, to_mono = node_matrix(degree)
        vals = direct((mid[:, None] + half[:, None] * s[None, :]).ravel())
        coef = np.einsum("ij,qpj->pqi", to_mono, vals.reshape(5, a.size, s.size))
        table = TorsionalTable(br, degree, coef, period, {})
        err = np.max(np.abs(table.evaluate(chk) - exact), axis=1) / scale
        if np.all(err <= TABLE_ERROR):
            return TorsionalTable(br, degree, coef, period,
                                  {n: float(e) for n, e in zip(QUANTITIES, err, strict=True)})
    raise InputError(f"native FMU table: no polynomial degree up to {MAX_DEGREE} reaches the "
                     f"table error {TABLE_ERROR:g} (reached {float(np.max(err)):.3g})")


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

