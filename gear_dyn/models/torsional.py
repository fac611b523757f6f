"""Two-DOF torsional model of a gear pair with eccentricity and friction.

States ``y = [q1, q2, q1', q2']`` (rad, rad/s): vibration angles about the nominal rotation,
``q1 = th1 - w1 t``, ``q2 = th2 - w1 t z1 / z2``, so a long run keeps full precision::

    I1 q1'' = T1 - r_b1 F_m + T_f1
    I2 q2'' = r_b2 F_m - T2 + T_f2
    F_m     = k(t) f(delta) + c_m delta'
    delta   = r_b1 q1 - r_b2 q2 + e_ecc(t) - e(t)            (mesh deflection, m)

with ``e_ecc`` and the friction torques ``T_f = max(F_m, 0) phi(t)`` of Liu et al. (2017),
``c_m = 2 xi sqrt(m_e k_m)``. The terms, the default load torque and the initial state are
derived in docs/eccentricity.md. Options left out (eccentricity, friction, backlash,
transmission error) are absent from the right-hand side: closures are chosen at construction.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.eccentricity.contact_lines import LineLayout, LinePlace, contact_lines
from gear_dyn.eccentricity.friction import friction_factors
from gear_dyn.eccentricity.kinematics import Eccentricity, EccentricMesh, Kinematics
from gear_dyn.errors import InputError, check_range
from gear_dyn.excitation import HarmonicSignal, SampledSignal
from gear_dyn.geometry import GearPair, check_speed, check_torque
from gear_dyn.models.sdof import dead_zone, effective_mass
from gear_dyn.models.torsional_parts import (
    ContactLineStiffness,
    Excite,
    _levels,
    excite_closure,
)
from gear_dyn.models.torsional_table import ExcitationTable, force_form, table_of
from gear_dyn.stiffness.periodic import PeriodicStiffness

FloatArray = NDArray[np.float64]
Signal = HarmonicSignal | SampledSignal

_MEAN_SAMPLES = 200_000  # cap on samples used for the mean friction factors
#: mean friction arms by the speed-free inputs they depend on (geometry, eccentricity, layout,
#: mu, samples): the mean over the hunting period is a mean over shaft angles, the same at every
#: speed, so the quasi-static model and the points of a sweep reuse it
_MEAN_ARMS: dict[tuple[Any, ...], tuple[float, float]] = {}
_MEAN_ARMS_KEPT = 32
#: times per block of :meth:`TorsionalModel.excitations`: the kinematics' and contact lines'
#: temporaries of one block stay in the CPU cache (about 2x faster on long grids than one pass)
_EXCITE_BLOCK = 8192


@dataclass(frozen=True, eq=False)
class TorsionalModel:
    """Two-DOF torsional gear model with optional eccentricity, friction, backlash and TE.

    Parameters
    ----------
    pair : GearPair
    speed : float
        Nominal pinion speed w1 in rad/s (> 0).
    torque : float
        Pinion torque T1 in N m (>= 0).
    stiffness : PeriodicStiffness or ContactLineStiffness
        Mesh stiffness.
    inertias : (float, float)
        I1, I2 in kg m^2 (> 0).
    damping_ratio : float
        xi (0..10).
    eccentricity : Eccentricity or None
        None (or zero eccentricity) builds no eccentric kinematics.
    friction : float or None
        Mean friction coefficient mu (0..1), or None for no friction machinery.
    backlash : float or None
        Half gap b_g in m (> 0), or None.
    transmission_error : HarmonicSignal, SampledSignal or None
        Static transmission error e(p) in m at the nominal mesh phase.
    load_torque : float or None
        T2 in N m; None balances T1 (see the module docstring).
    tabulate : bool
        True (default): the right-hand side takes the state-independent coefficients from
        piecewise polynomials between switching instants
        (:mod:`~gear_dyn.models.torsional_table`, interpolation error stated in
        ``coefficients.max_error``); False evaluates them directly at every call (reference).

    Raises
    ------
    InputError
        Any parameter out of range (message names field, value, unit and range).
    """

    pair: GearPair
    speed: float
    torque: float
    stiffness: PeriodicStiffness | ContactLineStiffness
    inertias: tuple[float, float]
    damping_ratio: float = 0.06
    eccentricity: Eccentricity | None = None
    friction: float | None = None
    backlash: float | None = None
    transmission_error: Signal | None = None
    load_torque: float | None = None
    tabulate: bool = True
    state_labels: tuple[str, ...] = field(default=("q1", "q2", "q1_dot", "q2_dot"), init=False)
    mesh_frequency: float = field(init=False)
    static_load: float = field(init=False)
    load: float = field(init=False)
    mean_stiffness: float = field(init=False)
    damping: float = field(init=False)
    mean_friction_arms: tuple[float, float] = field(init=False)
    #: the kinematic (rigid) eccentric mesh the excitations come from
    mesh: EccentricMesh = field(init=False, repr=False)
    _layout: LineLayout | None = field(init=False, repr=False)
    _place0: Kinematics = field(init=False, repr=False)
    _excite: Excite = field(init=False, repr=False)
    _table: ExcitationTable | None = field(init=False, repr=False)
    _rhs: Callable[[float, FloatArray], FloatArray] = field(init=False, repr=False)
    #: the last long grid of :meth:`outputs` and its excitations (a run's outputs and its error
    #: check ask for the same grid)
    _last: list[Any] = field(init=False, repr=False, default_factory=list, compare=False)

    def __post_init__(self) -> None:
        check_speed(self.speed)
        check_torque(self.torque)
        check_range("damping_ratio", self.damping_ratio, "", low=0.0, high=10.0)
        if len(self.inertias) != 2:
            raise InputError("inertias: expected (I1, I2) in kg*m^2")
        check_range("inertia_pinion", self.inertias[0], "kg*m^2", low=0.0, high=1e6, low_open=True)
        check_range("inertia_gear", self.inertias[1], "kg*m^2", low=0.0, high=1e6, low_open=True)
        if self.friction is not None:
            check_range("friction.coefficient", self.friction, "", low=0.0, high=1.0)
        if self.backlash is not None:
            check_range("backlash", self.backlash, "m", low=0.0, high=0.01, low_open=True)
        if self.load_torque is not None:
            check_range("load_torque", self.load_torque, "N*m", low=0.0, high=1e9)
        if not isinstance(self.stiffness, PeriodicStiffness | ContactLineStiffness):
            raise InputError("stiffness: expected a PeriodicStiffness or ContactLineStiffness")
        pair = self.pair
        ecc = self.eccentricity if self.eccentricity is not None else Eccentricity()
        mesh = EccentricMesh(pair, ecc, self.speed)
        need_lines = self.friction is not None or isinstance(self.stiffness, ContactLineStiffness)
        setf = object.__setattr__
        setf(self, "mesh", mesh)
        setf(self, "_layout", LineLayout.of(mesh) if need_lines else None)
        setf(self, "_place0", mesh.kinematics(0.0))
        setf(self, "mesh_frequency", mesh.mesh_frequency)
        if isinstance(self.stiffness, ContactLineStiffness):
            k_m = self.stiffness.per_length * pair.face_width * pair.contact_ratio / math.cos(
                pair.beta_b)
        else:
            k_m = self.stiffness.mean
        if not (math.isfinite(k_m) and k_m > 0):
            raise InputError(f"mean mesh stiffness = {k_m:.6g} N/m: valid range > 0 N/m")
        setf(self, "mean_stiffness", k_m)
        setf(self, "damping", 2 * self.damping_ratio * math.sqrt(self.effective_mass * k_m))
        # t -> (e_ecc, e_ecc', k, phi1, phi2), with only the enabled parts
        setf(self, "_excite", excite_closure(self.stiffness, self._layout, self.friction,
                                             self.eccentric, self._place_scalar,
                                             self.mesh_frequency, pair.base_pitch, mesh.l_ac0))
        phi = self._mean_friction_arms() if self.friction is not None else (0.0, 0.0)
        setf(self, "mean_friction_arms", phi)
        w = self.torque / (pair.rb1 - phi[0])
        setf(self, "static_load", w)
        setf(self, "load", self.load_torque if self.load_torque is not None
             else w * (pair.rb2 + phi[1]))
        setf(self, "_table", table_of(self) if self.tabulate else None)
        setf(self, "_rhs", self._build_rhs())

    # ---------------------------------------------------------------- properties
    @property
    def output_names(self) -> tuple[str, ...]:
        """Names of :meth:`outputs` (they depend on the parts modelled)."""
        return tuple(self.outputs(np.zeros(1), self.initial_state()[:, None]))

    @property
    def is_linear(self) -> bool:
        """True without backlash and friction (the friction force follows max(F, 0))."""
        return self.backlash is None and self.friction is None

    #: not the single-DOF mesh equation (two inertias, eccentric kinematics)
    mesh_periodic = False

    def at_mesh_frequency(self, mesh_frequency: float) -> None:
        """None: the kinematics depend on speed, so the model is rebuilt at a new speed."""
        del mesh_frequency
        return None

    @property
    def eccentric(self) -> bool:
        """True if an eccentricity is modelled."""
        return self.eccentricity is not None and self.eccentricity.active

    @property
    def effective_mass(self) -> float:
        """m_e in kg."""
        return effective_mass(self.inertias[0], self.inertias[1], self.pair.rb1, self.pair.rb2)

    @property
    def natural_frequency(self) -> float:
        """Mesh-mode natural frequency sqrt(k_m / m_e) / (2 pi) in Hz."""
        return math.sqrt(self.mean_stiffness / self.effective_mass) / (2 * math.pi)

    @property
    def static_deflection(self) -> float:
        """W / k_m (+ half gap) in m."""
        return self.static_load / self.mean_stiffness + (self.backlash or 0.0)

    @property
    def state_scale(self) -> FloatArray:
        """Typical magnitudes [rad, rad, rad/s, rad/s] for tolerances."""
        ecc = self.eccentricity
        x = max(self.static_load / self.mean_stiffness, self.backlash or 0.0, 1e-9,
                (ecc.e1 + ecc.e2) if ecc is not None else 0.0)
        om = 2 * math.pi * self.natural_frequency
        q1, q2 = x / self.pair.rb1, x / self.pair.rb2
        return np.array([q1, q2, q1 * om, q2 * om])

    def summary_info(self) -> dict[str, Any]:
        """Model facts for the run summary."""
        return {
            "model": "torsional",
            "load_torque_n_m": self.load,
            "mean_stiffness_n_per_m": self.mean_stiffness,
            "natural_frequency_hz": self.natural_frequency,
            "eccentric": self.eccentric,
            "friction_coefficient": self.friction,
            "mean_friction_arms_m": list(self.mean_friction_arms),
        }

    # ---------------------------------------------------------------- excitations
    def _place_scalar(self, t: float) -> Any:
        if self.eccentric:
            return self.mesh.kinematics(t)
        k0 = self._place0
        return LinePlace(travel=self.pair.rb1 * self.speed * t, l_ac=float(k0.l_ac),
                         l_cd=float(k0.l_cd), l_cp=float(k0.l_cp), foot1=float(k0.foot1),
                         foot2=float(k0.foot2))

    @property
    def coefficients(self) -> Excite:
        """``t -> (e_ecc, e_ecc', k, phi1, phi2)`` as the right-hand side uses it: the table of
        :mod:`~gear_dyn.models.torsional_table` when built, else the direct evaluation."""
        return self._table if self._table is not None else self._excite

    @property
    def force_form_needs_compression(self) -> bool:
        """True with friction: the friction torques follow F only while F > 0, so the affine
        form of :meth:`force_form` holds only there; without friction it holds everywhere."""
        return self.friction is not None

    def force_form(self, t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray,
                                                 FloatArray] | None:
        """``(u, f, f0, g_v)`` at many times: ``q' = v``, ``v' = u F + g_v``,
        ``F = f . y + f0`` while the mesh force is compressive
        (:func:`~gear_dyn.models.torsional_table.force_form`), from the table; None without a
        table or with backlash or transmission error (the gauss solver does not apply)."""
        if self._table is None or self.backlash is not None or \
                self.transmission_error is not None:
            return None
        return force_form(self._table.evaluate(t), (self.pair.rb1, self.pair.rb2),
                          self.inertias, (self.torque, self.load), self.damping)

    def excitations(self, t: FloatArray) -> dict[str, FloatArray]:
        """Explicit time functions on a grid: ``e_ecc``, ``e_ecc_rate`` (m, m/s), ``stiffness``
        (N/m), ``contact_length`` (m, when contact lines are modelled), ``phi1``, ``phi2``
        (friction torque per unit normal load, m), ``w2_kinematic`` (rad/s)."""
        t = np.asarray(t, dtype=float)
        if t.ndim == 1 and t.size > _EXCITE_BLOCK:
            parts = [self._excitations(t[i:i + _EXCITE_BLOCK])
                     for i in range(0, t.size, _EXCITE_BLOCK)]
            return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
        return self._excitations(t)

    def _kept_excitations(self, t: FloatArray) -> dict[str, FloatArray]:
        """:meth:`excitations`, kept for the last long grid (fresh copies each call)."""
        last = self._last
        if last and last[0].shape == t.shape and np.array_equal(last[0], t):
            return {k: v.copy() for k, v in last[1].items()}
        out = self.excitations(t)
        if t.ndim == 1 and t.size > _EXCITE_BLOCK:  # worth keeping
            last[:] = [t.copy(), {k: v.copy() for k, v in out.items()}]
        return out

    def _excitations(self, t: FloatArray) -> dict[str, FloatArray]:
        lay = self._layout
        # the kinematics, where eccentricity or contact lines need them
        kin = self.mesh.kinematics(t) if self.eccentric or lay is not None else None
        zero = np.zeros_like(t)
        out: dict[str, FloatArray]
        if self.eccentric and kin is not None:
            out = {"e_ecc": np.asarray(kin.e_ecc, dtype=float),
                   "e_ecc_rate": np.asarray(kin.e_ecc_rate, dtype=float),
                   "w2_kinematic": np.asarray(kin.w2, dtype=float)}
        else:
            out = {"e_ecc": zero, "e_ecc_rate": zero,
                   "w2_kinematic": np.full_like(t, self.speed * self.pair.z1 / self.pair.z2)}
        if lay is not None and kin is not None:
            out["contact_length"] = np.asarray(contact_lines(lay, kin).total, dtype=float)
        stiff = self.stiffness
        if isinstance(stiff, ContactLineStiffness):
            out["stiffness"] = stiff.per_length * out["contact_length"]
        elif self.eccentric and kin is not None:
            phase = (kin.travel + self.mesh.l_ac0 - kin.l_ac) / self.pair.base_pitch
            out["stiffness"] = np.asarray(stiff(phase), dtype=float)
        else:
            out["stiffness"] = np.asarray(stiff(self.mesh_frequency * t), dtype=float)
        if self.friction is not None and lay is not None and kin is not None:
            ff = friction_factors(lay, kin, self.friction)
            out["phi1"] = np.asarray(ff.torque_pinion, dtype=float)
            out["phi2"] = np.asarray(ff.torque_gear, dtype=float)
            out["friction_force_factor"] = np.asarray(ff.force, dtype=float)
        else:
            out["phi1"] = zero
            out["phi2"] = zero
        return out

    def _mean_friction_arms(self) -> tuple[float, float]:
        """Time means of phi1, phi2 over one hunting period (one mesh period if error-free):
        means over the shaft angles, independent of the speed (kept by their inputs)."""
        if self.eccentric:
            span = self.mesh.hunting_period
            n = int(min(_MEAN_SAMPLES, 64 * round(span * self.mesh_frequency)))
        else:
            span = 1.0 / self.mesh_frequency
            n = 4096
        lay = self._layout
        assert lay is not None  # friction models contact lines
        key = (self.mesh.angle_key, self.pair.z1, self.pair.z2, lay.pitch,
               lay.width, lay.sin_bb, lay.face_width, lay.l_ac0, tuple(lay.index.tolist()),
               self.friction, self.eccentric, n)
        got = _MEAN_ARMS.get(key)
        if got is None:
            t = np.arange(n, dtype=np.float64) * (span / n)
            ex = self.excitations(t)
            got = float(np.mean(ex["phi1"])), float(np.mean(ex["phi2"]))
            if len(_MEAN_ARMS) >= _MEAN_ARMS_KEPT:
                del _MEAN_ARMS[next(iter(_MEAN_ARMS))]
            _MEAN_ARMS[key] = got
        return got

    # ---------------------------------------------------------------- dynamics
    def _build_rhs(self) -> Callable[[float, FloatArray], FloatArray]:
        rb1, rb2 = self.pair.rb1, self.pair.rb2
        i1, i2 = self.inertias
        t1, t2 = self.torque, self.load
        c = self.damping
        fm = self.mesh_frequency
        excite = self.coefficients
        bg = self.backlash
        te = self.transmission_error
        friction = self.friction is not None

        def rhs(t: float, y: FloatArray) -> FloatArray:
            q1, q2, v1, v2 = y
            e, ed, k, p1, p2 = excite(t)
            d = rb1 * q1 - rb2 * q2 + e
            dd = rb1 * v1 - rb2 * v2 + ed
            if te is not None:
                p = fm * t
                d -= float(te.value(p))
                dd -= fm * float(te.slope(p))
            if bg is not None:
                d = d - bg if d > bg else (d + bg if d < -bg else 0.0)
            f = k * d + c * dd
            if friction:
                n = f if f > 0.0 else 0.0
                return np.array([v1, v2, (t1 - rb1 * f + n * p1) / i1,
                                 (rb2 * f - t2 + n * p2) / i2])
            return np.array([v1, v2, (t1 - rb1 * f) / i1, (rb2 * f - t2) / i2])
        return rhs

    def rhs(self, t: float, y: FloatArray) -> FloatArray:
        """Time derivative of ``y = [q1, q2, q1', q2']`` at time ``t`` (s)."""
        return self._rhs(t, y)

    def jac(self, t: float, y: FloatArray) -> FloatArray:
        """Jacobian d rhs / d y (4 x 4)."""
        rb1, rb2 = self.pair.rb1, self.pair.rb2
        e, ed, k, p1, p2 = self.coefficients(t)
        if self.backlash is not None or self.friction is not None:
            d = rb1 * y[0] - rb2 * y[1] + e
            dd = rb1 * y[2] - rb2 * y[3] + ed
            if self.transmission_error is not None:
                p = self.mesh_frequency * t
                d -= float(self.transmission_error.value(p))
                dd -= self.mesh_frequency * float(self.transmission_error.slope(p))
            if self.backlash is not None:
                if abs(d) <= self.backlash:
                    k, d = 0.0, 0.0
                else:
                    d -= math.copysign(self.backlash, d)
            if self.friction is not None and k * d + self.damping * dd <= 0.0:
                p1 = p2 = 0.0
        return self._matrix(k, p1, p2)

    def _matrix(self, k: float, p1: float, p2: float) -> FloatArray:
        """``d rhs / d y`` (4 x 4) at stiffness ``k`` (N/m) and friction arms ``p1``, ``p2`` (m)."""
        rb1, rb2 = self.pair.rb1, self.pair.rb2
        i1, i2 = self.inertias
        c = self.damping
        dfdy = np.array([k * rb1, -k * rb2, c * rb1, -c * rb2])
        a = np.zeros((4, 4))
        a[0, 2] = a[1, 3] = 1.0
        a[2] = (p1 - rb1) * dfdy / i1
        a[3] = (rb2 + p2) * dfdy / i2
        return a

    def initial_state(self) -> FloatArray:
        """Static deflection, delta' = 0 and zero rigid-body momentum (see module docstring)."""
        rb1, rb2 = self.pair.rb1, self.pair.rb2
        i1, i2 = self.inertias
        e, ed = 0.0, 0.0
        if self.eccentric:
            k0 = self.mesh.kinematics(0.0)
            e, ed = float(k0.e_ecc), float(k0.e_ecc_rate)
        if self.transmission_error is not None:
            e -= float(self.transmission_error.value(0.0))
            ed -= self.mesh_frequency * float(self.transmission_error.slope(0.0))
        q2 = (e - self.static_deflection) / rb2
        v1 = -ed * i2 * rb1 / (i2 * rb1**2 + i1 * rb2**2)
        v2 = -i1 * v1 * rb2 / (i2 * rb1)
        return np.array([0.0, q2, v1, v2])

    # ---------------------------------------------------------------- switching
    def switching_times(self, t0: float, t1: float) -> FloatArray:
        """Instants in (t0, t1) where k(t) or the friction torques jump or have a kink.

        Contact lines enter or leave the field (their ends cross C or D), and, with friction,
        cross the pitch line. All are levels of monotone functions of time (the contact travel
        ``tau`` and ``tau - L_AC``, ``tau - L_AP``), found by Newton iteration.
        """
        if t1 <= t0:
            return np.empty(0)
        stiff = self.stiffness
        if isinstance(stiff, PeriodicStiffness) and self.friction is None and not self.eccentric:
            return stiff.switching_times(t0, t1, self.mesh_frequency, 0.0)
        pitch = self.pair.base_pitch
        l_ac0 = self.mesh.l_ac0
        l_ad = self.pair.tip_reach1
        width = self.pair.face_width * math.tan(self.pair.beta_b)
        rate = self.pair.rb1 * self.speed
        found: list[FloatArray] = []
        mesh = self.mesh

        def entry(t: FloatArray) -> FloatArray:  # D_i of the line ends, up to a multiple of p_bt
            k = mesh.kinematics(t)
            return np.asarray(k.travel + l_ac0 - k.l_ac, dtype=float)

        def travel(t: FloatArray) -> FloatArray:
            return np.asarray(mesh.kinematics(t).travel, dtype=float)

        def pitch_line(t: FloatArray) -> FloatArray:
            k = mesh.kinematics(t)
            return np.asarray(k.travel - k.l_ap, dtype=float)

        if isinstance(stiff, PeriodicStiffness):
            found.append(_levels(entry, rate, t0, t1, stiff.switching_phases * pitch, pitch))
        if self._layout is not None:
            found.append(_levels(entry, rate, t0, t1, np.array([0.0, width]), pitch))
            found.append(_levels(travel, rate, t0, t1, np.array([l_ad - l_ac0,
                                                                 l_ad + width - l_ac0]), pitch))
        if self.friction is not None:
            found.append(_levels(pitch_line, rate, t0, t1, np.array([-l_ac0, width - l_ac0]),
                                 pitch))
        ts = np.sort(np.concatenate(found))  # never empty: a stiffness or contact lines
        tol = 1e-12 * max(abs(t1), 1.0 / self.mesh_frequency)
        ts = ts[(ts > t0 + tol) & (ts < t1 - tol)]
        return ts[np.concatenate([[True], np.diff(ts) > tol])] if ts.size else ts

    def contact_events(self) -> list[Callable[[float, FloatArray], float]]:
        """Functions g(t, y) whose zeros are contact changes through the backlash (none without).

        ``delta - b_g`` (drive flank) and ``delta + b_g`` (back flank), delta the mesh deflection
        of the module docstring; used by :mod:`gear_dyn.solvers.events` to restart the solver there.
        """
        bg = self.backlash
        if bg is None:
            return []
        rb1, rb2 = self.pair.rb1, self.pair.rb2
        fm = self.mesh_frequency
        excite = self.coefficients
        te = self.transmission_error
        ecc = self.eccentric

        def deflection(t: float, y: FloatArray) -> float:
            d = rb1 * float(y[0]) - rb2 * float(y[1])
            if ecc:
                d += excite(t)[0]
            if te is not None:
                d -= float(te.value(fm * t))
            return d
        return [lambda t, y: deflection(t, y) - bg, lambda t, y: deflection(t, y) + bg]

    def linear_segments(self, t0: float, t1: float) -> list[tuple[float, float, FloatArray,
                                                                   FloatArray]] | None:
        """Pieces ``(ta, tb, A, g)`` with y' = A y + g, or None.

        Only for the plain model: piecewise-constant periodic stiffness, no eccentricity, no
        friction, no backlash, no transmission error.
        """
        stiff = self.stiffness
        if (not isinstance(stiff, PeriodicStiffness) or stiff.segments() is None or self.eccentric
                or self.friction is not None or self.backlash is not None
                or self.transmission_error is not None):
            return None
        i1, i2 = self.inertias
        cuts = np.concatenate([[t0], self.switching_times(t0, t1), [t1]])
        g = np.array([0.0, 0.0, self.torque / i1, -self.load / i2])
        out = []
        for ta, tb in zip(cuts[:-1], cuts[1:], strict=True):
            k = float(stiff(self.mesh_frequency * 0.5 * (ta + tb)))
            out.append((float(ta), float(tb), self._matrix(k, 0.0, 0.0), g))
        return out

    # ---------------------------------------------------------------- outputs
    def outputs(self, t: FloatArray, y: FloatArray,
                excitations: dict[str, FloatArray] | None = None) -> dict[str, FloatArray]:
        """Derived series.

        ``dte`` r_b1 q1 - r_b2 q2 (m), ``delta`` mesh deflection (m), ``mesh_force`` (N),
        ``stiffness`` (N/m), ``w1``, ``w2`` speeds (rad/s), ``w2_kinematic`` (rad/s, rigid
        eccentric pair), and, when enabled, ``e_ecc`` (m), ``contact_length`` (m),
        ``friction_torque_pinion``, ``friction_torque_gear`` (N m).

        ``excitations``: ``e_ecc`` (m), ``e_ecc_rate`` (m/s), ``stiffness`` (N/m), ``phi1``,
        ``phi2`` (m) on ``t`` where the caller has them (the kernel method's table, within its
        stated error); the rest follows from them (``w2_kinematic = (e_ecc' + r_b1 w1) / r_b2``,
        ``contact_length = k / k_l`` with contact-line stiffness). None, or where the contact
        length does not follow (friction on another stiffness): evaluated here.
        """
        t = np.asarray(t, dtype=float)
        y = np.asarray(y, dtype=float)
        rb1, rb2 = self.pair.rb1, self.pair.rb2
        stiff = self.stiffness
        lines = isinstance(stiff, ContactLineStiffness)
        if excitations is not None and (lines or self._layout is None):
            ex = dict(excitations)
            ex["w2_kinematic"] = (ex["e_ecc_rate"] + rb1 * self.speed) / rb2
            if isinstance(stiff, ContactLineStiffness):
                ex["contact_length"] = ex["stiffness"] / stiff.per_length
        else:
            ex = self._kept_excitations(t)
        dte = rb1 * y[0] - rb2 * y[1]
        d = dte + ex["e_ecc"]
        dd = rb1 * y[2] - rb2 * y[3] + ex["e_ecc_rate"]
        if self.transmission_error is not None:
            p = self.mesh_frequency * t
            d = d - self.transmission_error.value(p)
            dd = dd - self.mesh_frequency * self.transmission_error.slope(p)
        fd = dead_zone(d, self.backlash) if self.backlash is not None else d
        force = ex["stiffness"] * fd + self.damping * dd
        out = {
            "dte": dte, "delta": d, "mesh_force": force, "stiffness": ex["stiffness"],
            "w1": self.speed + y[2], "w2": self.speed * self.pair.z1 / self.pair.z2 + y[3],
            "w2_kinematic": ex["w2_kinematic"],
        }
        if self.eccentric:
            out["e_ecc"] = ex["e_ecc"]
        if "contact_length" in ex:
            out["contact_length"] = ex["contact_length"]
        if self.friction is not None:
            n = np.maximum(force, 0.0)
            out["friction_torque_pinion"] = n * ex["phi1"]
            out["friction_torque_gear"] = n * ex["phi2"]
        return out


def torsional_from_pair(
    pair: GearPair,
    speed: float,
    torque: float,
    stiffness: PeriodicStiffness | ContactLineStiffness,
    damping_ratio: float = 0.06,
    inertias: tuple[float, float] | None = None,
    **options: Any,
) -> TorsionalModel:
    """Build the torsional model; ``inertias=None`` uses solid blanks (GearPair.blank_inertias).

    ``options`` are the optional parts of :class:`TorsionalModel` (eccentricity, friction,
    backlash, transmission_error, load_torque); unknown names raise InputError.
    """
    allowed = {"eccentricity", "friction", "backlash", "transmission_error", "load_torque"}
    bad = sorted(set(options) - allowed)
    if bad:
        raise InputError(f"torsional model: unknown option(s) {', '.join(bad)}; valid: "
                         f"{', '.join(sorted(allowed))}")
    i12 = inertias if inertias is not None else pair.blank_inertias()
    return TorsionalModel(pair=pair, speed=speed, torque=torque, stiffness=stiffness,
                          inertias=i12, damping_ratio=damping_ratio, **options)
