"""Single-DOF mesh model (Jiang et al. 2018, eqs. 13-16).

    m_e x'' + c_m (x' - e') + k(t) f(x - e) = W

x is the dynamic transmission error along the line of action (x = r_b1 th1 - r_b2 th2, m),
m_e = I1 I2 / (r_b1^2 I2 + r_b2^2 I1) (kg), c_m = 2 xi sqrt(m_e k_m) (N s/m), W = T1 / r_b1 (N).
Options, each off by default and then absent from the right-hand side (no zero terms evaluated):

- backlash with half gap b_g: f(u) = u - b_g for u > b_g, 0 inside the gap, u + b_g below -b_g
- static transmission error e(t) = e(p(t)), p = f_m t + p0 the mesh phase

With both off the equation is exactly that of Jiang et al. (2018).
"""

from __future__ import annotations

import bisect
import copy
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError, check_range
from gear_dyn.excitation import HarmonicSignal, SampledSignal, SumSignal
from gear_dyn.geometry import GearPair, check_speed, check_torque, mesh_frequency
from gear_dyn.stiffness.periodic import FourierStiffness, PeriodicStiffness

FloatArray = NDArray[np.float64]
Signal = HarmonicSignal | SampledSignal | SumSignal


def effective_mass(i1: float, i2: float, rb1: float, rb2: float) -> float:
    """Equivalent mass on the line of action, m_e = I1 I2 / (rb1^2 I2 + rb2^2 I1), in kg.

    Parameters
    ----------
    i1, i2 : float
        Polar moments of inertia of pinion and gear in kg m^2 (> 0).
    rb1, rb2 : float
        Base radii in m (> 0).
    """
    check_range("inertia_pinion", i1, "kg*m^2", low=0.0, low_open=True)
    check_range("inertia_gear", i2, "kg*m^2", low=0.0, low_open=True)
    return i1 * i2 / (rb1**2 * i2 + rb2**2 * i1)


def dead_zone(u: FloatArray | float, half_gap: float) -> FloatArray:
    """Backlash function f(u): u - b for u > b, 0 for ``|u| <= b``, u + b for u < -b (m)."""
    u = np.asarray(u, dtype=float)
    return np.where(u > half_gap, u - half_gap, np.where(u < -half_gap, u + half_gap, 0.0))


def scalar_stiffness(k: PeriodicStiffness) -> Callable[[float], float]:
    """A fast scalar ``k(p)`` for the solver's right-hand side (same values as ``k``).

    A Fourier series is summed with ``math.cos``/``math.sin`` (no array set-up per call: about
    20x cheaper than the vectorised ``__call__`` for one phase), a piecewise-constant stiffness
    is a bisection of its segments; other kinds use their own scalar path where they have one.
    """
    if isinstance(k, FourierStiffness):
        k0 = float(k.k0)
        terms = [(2 * math.pi * (n + 1), float(an), float(bn))
                 for n, (an, bn) in enumerate(zip(k.a, k.b, strict=True)) if an or bn]
        cos, sin = math.cos, math.sin

        def k_fourier(p: float) -> float:
            s = k0
            for om, an, bn in terms:
                s += an * cos(om * p) + bn * sin(om * p)
            return s
        return k_fourier
    seg = k.segments()
    if seg is not None:
        edges, values = seg[0].tolist(), seg[1].tolist()
        last = len(values) - 1
        return lambda p: values[min(bisect.bisect_right(edges, p % 1.0) - 1, last)]
    fast = getattr(k, "_scalar", None)  # PiecewiseStiffness's scalar path (skips dispatch)
    if callable(fast):
        return fast
    return lambda p: float(k(p))


@dataclass(frozen=True, eq=False)
class SDOFModel:
    """Single-DOF gear mesh model.

    Parameters
    ----------
    mass : float
        Equivalent mass m_e in kg (> 0).
    stiffness : PeriodicStiffness
        Mesh stiffness k(p) in N/m, p in mesh cycles.
    damping_ratio : float
        Mesh damping ratio xi (0..10); c_m = 2 xi sqrt(m_e k_m).
    static_load : float
        Transmitted static load W in N (>= 0).
    mesh_frequency : float
        Mesh frequency f_m in Hz (> 0).
    backlash : float or None
        Half gap b_g in m (> 0), or None for no backlash.
    transmission_error : HarmonicSignal, SampledSignal, SumSignal or None
        Static transmission error e(p) in m, or None. One whose period is longer than the mesh
        period (manufacturing deviations: shaft orders) makes the model not ``mesh_periodic``.
    phase0 : float
        Mesh phase at t = 0 in cycles.

    Raises
    ------
    InputError
        Any parameter outside its valid range.

    Attributes
    ----------
    mean_stiffness : float
        k_m in N/m.
    natural_frequency : float
        sqrt(k_m / m_e) / (2 pi) in Hz.
    static_deflection : float
        W / k_m in m (plus the half gap with backlash).
    is_linear : bool
        True without backlash.

    See Also
    --------
    :func:`~gear_dyn.models.sdof.sdof_from_pair` : The model of a gear pair at an operating point.
    :func:`~gear_dyn.analysis.study.simulate` : Integrate it.
    :func:`~gear_dyn.analysis.continuation.family.sdof_family`
        The model as a function of one parameter.

    Examples
    --------
    >>> from gear_dyn import rectangular_stiffness
    >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
    >>> round(m.natural_frequency, 1)  # sqrt(1.3e8 / 0.5) / (2 pi) in Hz
    2566.3
    >>> m.static_deflection  # W / k_m in m
    7.692307692307692e-06
    """

    mass: float
    stiffness: PeriodicStiffness
    damping_ratio: float
    static_load: float
    mesh_frequency: float
    backlash: float | None = None
    transmission_error: Signal | None = None
    phase0: float = 0.0
    state_labels: tuple[str, ...] = field(default=("x", "v"), init=False)
    output_names: tuple[str, ...] = field(default=("dte", "mesh_force", "stiffness"), init=False)
    damping: float = field(init=False)
    #: the right-hand side and its Jacobian, built at their first call (the exact contact
    #: walk never calls them; a continuation builds a model at every iterate's speed)
    _rhs: Callable[[float, FloatArray], FloatArray] | None = field(default=None, init=False,
                                                                   repr=False)
    _jac: Callable[[float, FloatArray], FloatArray] | None = field(default=None, init=False,
                                                                   repr=False)

    def __post_init__(self) -> None:
        check_range("mass", self.mass, "kg", low=0.0, low_open=True)
        check_range("damping_ratio", self.damping_ratio, "", low=0.0, high=10.0)
        check_range("static_load", self.static_load, "N", low=0.0)
        check_range("mesh_frequency", self.mesh_frequency, "Hz", low=0.0, high=1e7, low_open=True)
        check_range("phase0", self.phase0, "cycles")
        if self.backlash is not None:
            check_range("backlash", self.backlash, "m", low=0.0, high=0.1, low_open=True)
        k_m = self.stiffness.mean
        if not (math.isfinite(k_m) and k_m > 0):
            raise InputError(f"mean mesh stiffness = {k_m:.6g} N/m: valid range > 0 N/m")
        object.__setattr__(self, "damping", 2 * self.damping_ratio * math.sqrt(self.mass * k_m))
        object.__setattr__(self, "_rhs", None)
        object.__setattr__(self, "_jac", None)

    # ---------------------------------------------------------------- derived constants
    @property
    def mean_stiffness(self) -> float:
        """Mean mesh stiffness k_m in N/m."""
        return self.stiffness.mean

    @property
    def natural_frequency(self) -> float:
        """Natural frequency sqrt(k_m / m_e) / (2 pi) in Hz."""
        return math.sqrt(self.mean_stiffness / self.mass) / (2 * math.pi)

    @property
    def mesh_periodic(self) -> bool:
        """True unless the transmission error has a period longer than the mesh period.

        With shaft-order content (``transmission_error.period`` > 1 mesh cycles) the forced
        response repeats only over that period: the one-mesh-period steady state, the periodic
        step maps and the steady sweep do not apply, and the model says so here (the Floquet
        multipliers, a property of k(t) alone, are unchanged).
        """
        return self.transmission_error is None or self.transmission_error.period == 1

    @property
    def excitation_period(self) -> int:
        """Period of the excitation in mesh cycles (1, or the transmission error's)."""
        return 1 if self.transmission_error is None else int(self.transmission_error.period)

    @property
    def is_linear(self) -> bool:
        """True without backlash: the right-hand side is then affine in the state."""
        return self.backlash is None

    def at_mesh_frequency(self, mesh_frequency: float) -> SDOFModel:
        """The same model at another mesh frequency (only f_m depends on speed here).

        Parameters
        ----------
        mesh_frequency : float
            The new f_m in Hz (> 0).

        Returns
        -------
        SDOFModel
            A copy with that mesh frequency.

        See Also
        --------
        :func:`~gear_dyn.analysis.continuation.family.sdof_family` : The model over a speed range.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, rectangular_stiffness
        >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
        >>> m.at_mesh_frequency(100.0).mesh_frequency  # Hz
        100.0
        """
        check_range("mesh_frequency", mesh_frequency, "Hz", low=0.0, high=1e7, low_open=True)
        # only f_m changes: the other fields were checked when this model was built, so the
        # copy skips their checks and drops only what captures f_m (the right-hand side and
        # its Jacobian, rebuilt at their first call); continuation evaluates the map at a new
        # speed every iterate
        out = copy.copy(self)
        object.__setattr__(out, "mesh_frequency", float(mesh_frequency))
        object.__setattr__(out, "_rhs", None)
        object.__setattr__(out, "_jac", None)
        return out

    def contact_events(self) -> list[Callable[[float, FloatArray], float]]:
        """With backlash: ``x - e - b`` and ``x - e + b`` (drive and back flank); else none.

        Returns
        -------
        list of callable
            Event functions ``g(t, y)`` in m (zero where a flank makes or loses contact).

        See Also
        --------
        :meth:`~gear_dyn.models.sdof.SDOFModel.switching_times`
            The stiffness jumps, known in advance.

        Examples
        --------
        >>> import numpy as np
        >>> from gear_dyn import SDOFModel, rectangular_stiffness
        >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0,
        ...               backlash=1e-5)
        >>> drive, back = m.contact_events()
        >>> float(drive(0.0, np.array([2e-5, 0.0])))  # x - e - b in m
        1e-05
        """
        if self.backlash is None:
            return []
        te, fm, p0, bb = self.transmission_error, self.mesh_frequency, self.phase0, self.backlash

        def u(t: float, y: FloatArray) -> float:  # x - e
            return float(y[0]) - (0.0 if te is None else float(te.value(fm * t + p0)))
        return [lambda t, y: u(t, y) - bb, lambda t, y: u(t, y) + bb]

    @property
    def static_deflection(self) -> float:
        """Static deflection W / k_m in m (plus the half gap with backlash)."""
        return self.static_load / self.mean_stiffness + (self.backlash or 0.0)

    @property
    def state_scale(self) -> FloatArray:
        """Typical state magnitudes [m, m/s] for tolerances and relative errors."""
        x = max(self.static_load / self.mean_stiffness, self.backlash or 0.0, 1e-9)
        return np.array([x, x * 2 * math.pi * self.natural_frequency])

    def phase(self, t: FloatArray | float) -> FloatArray:
        """Mesh phase p = f_m t + p0 in cycles.

        Parameters
        ----------
        t : float or ndarray
            Time in s.

        Returns
        -------
        float or ndarray
            Mesh phase in cycles.

        See Also
        --------
        :meth:`~gear_dyn.models.sdof.SDOFModel.switching_times`
            Times at which the stiffness jumps.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, rectangular_stiffness
        >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
        >>> float(m.phase(1e-3))  # 500 Hz for 1 ms
        0.5
        """
        return self.mesh_frequency * np.asarray(t, dtype=float) + self.phase0

    def initial_state(self) -> FloatArray:
        """Static deflection under the mean stiffness, at rest relative to e(t).

        Returns
        -------
        ndarray
            [x, v] in m and m/s at t = 0.

        See Also
        --------
        :func:`~gear_dyn.analysis.study.simulate` : Starts from it.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, rectangular_stiffness
        >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
        >>> m.initial_state()
        array([7.69230769e-06, 0.00000000e+00])
        """
        x0 = self.static_deflection
        v0 = 0.0
        if self.transmission_error is not None:
            p0 = self.phase(0.0)
            x0 += float(self.transmission_error.value(p0))
            v0 = float(self.transmission_error.slope(p0)) * self.mesh_frequency
        return np.array([x0, v0])

    # ---------------------------------------------------------------- right-hand side
    def _build_rhs(self) -> Callable[[float, FloatArray], FloatArray]:
        m, c, w = self.mass, self.damping, self.static_load
        fm, p0 = self.mesh_frequency, self.phase0
        k = scalar_stiffness(self.stiffness)
        b = self.backlash
        te = self.transmission_error

        def rhs(t: float, y: FloatArray) -> FloatArray:
            x, v = y.tolist()  # Python floats: cheaper arithmetic
            p = fm * t + p0
            kt = float(k(p))
            u, ud = x, v
            if te is not None:
                u = x - float(te.value(p))
                ud = v - fm * float(te.slope(p))
            if b is not None:
                u = u - b if u > b else (u + b if u < -b else 0.0)
            return np.array([v, (w - c * ud - kt * u) / m])
        return rhs

    def _build_jac(self) -> Callable[[float, FloatArray], FloatArray]:
        m, c, fm, p0 = self.mass, self.damping, self.mesh_frequency, self.phase0
        k = scalar_stiffness(self.stiffness)  # same values, no array set-up per call
        b = self.backlash
        te = self.transmission_error

        def jac(t: float, y: FloatArray) -> FloatArray:
            p = fm * t + p0
            kt = float(k(p))
            if b is not None:
                u = y[0] - (float(te.value(p)) if te is not None else 0.0)
                if abs(u) <= b:
                    kt = 0.0
            return np.array([[0.0, 1.0], [-kt / m, -c / m]])
        return jac

    def rhs(self, t: float, y: FloatArray) -> FloatArray:
        """Time derivative [x', v'] of the state y = [x, v] at time t (s).

        Parameters
        ----------
        t : float
            Time in s.
        y : ndarray
            State [x, v] in m and m/s.

        Returns
        -------
        ndarray
            [x', v'] in m/s and m/s^2.

        See Also
        --------
        :meth:`~gear_dyn.models.sdof.SDOFModel.jac` : Its Jacobian.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, rectangular_stiffness
        >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
        >>> m.rhs(0.0, m.initial_state())  # k(0) = 1.5e8 N/m > k_m: pushed back (m/s^2)
        array([   0.        , -307.69230769])
        """
        f = self._rhs
        if f is None:
            f = self._build_rhs()
            object.__setattr__(self, "_rhs", f)
        return f(t, y)

    def jac(self, t: float, y: FloatArray) -> FloatArray:
        """Jacobian d rhs / d y (2 x 2).

        Parameters
        ----------
        t : float
            Time in s.
        y : ndarray
            State [x, v] in m and m/s.

        Returns
        -------
        ndarray
            [[0, 1], [-k(t)/m_e, -c_m/m_e]] in 1/s^2 and 1/s.

        See Also
        --------
        :meth:`~gear_dyn.models.sdof.SDOFModel.rhs` : The right-hand side.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, rectangular_stiffness
        >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
        >>> float(m.jac(0.0, m.initial_state())[1, 0])  # -k(0) / m_e in 1/s^2
        -300000000.0
        """
        f = self._jac
        if f is None:
            f = self._build_jac()
            object.__setattr__(self, "_jac", f)
        return f(t, y)

    def switching_times(self, t0: float, t1: float) -> FloatArray:
        """Instants in (t0, t1) where k(t) jumps.

        Parameters
        ----------
        t0, t1 : float
            The open interval in s.

        Returns
        -------
        ndarray
            Sorted times in s.

        See Also
        --------
        :meth:`~gear_dyn.stiffness.periodic.PeriodicStiffness.switching_times`
            The same for a stiffness.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, rectangular_stiffness
        >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
        >>> m.switching_times(0.0, 0.004)  # phases 0.6, 1, 1.6 at 500 Hz (s)
        array([0.0012, 0.002 , 0.0032])
        """
        return self.stiffness.switching_times(t0, t1, self.mesh_frequency, self.phase0)

    def linear_segments(self, t0: float, t1: float) -> list[tuple[float, float, FloatArray,
                                                                   FloatArray]] | None:
        """Pieces ``(ta, tb, A, g)`` with y' = A y + g, or None if not piecewise-constant linear.

        Parameters
        ----------
        t0, t1 : float
            The interval in s.

        Returns
        -------
        list of (float, float, ndarray, ndarray) or None
            Start and end in s, the 2 x 2 matrix A and the vector g of each piece; None with
            backlash or a smooth stiffness.

        See Also
        --------
        :meth:`~gear_dyn.models.sdof.SDOFModel.switching_times` : The piece boundaries.
        :class:`~gear_dyn.solvers.settings.SolverSettings` : Method ``exact`` uses these pieces.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, rectangular_stiffness
        >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
        >>> [(round(ta, 6), round(tb, 6)) for ta, tb, A, g in m.linear_segments(0.0, 0.002)]
        [(0.0, 0.0012), (0.0012, 0.002)]
        """
        seg = self.stiffness.segments()
        if seg is None or self.backlash is not None or self.transmission_error is not None:
            return None
        cuts = np.concatenate([[t0], self.switching_times(t0, t1), [t1]])
        g = np.array([0.0, self.static_load / self.mass])
        # one vectorised stiffness lookup at the piece midpoints; equal values share one A
        kts = self.stiffness(self.phase(0.5 * (cuts[:-1] + cuts[1:])))
        mats: dict[float, FloatArray] = {}
        out = []
        for ta, tb, kt in zip(cuts[:-1].tolist(), cuts[1:].tolist(), kts.tolist(), strict=True):
            a = mats.get(kt)
            if a is None:
                a = mats[kt] = np.array([[0.0, 1.0], [-kt / self.mass, -self.damping / self.mass]])
            out.append((ta, tb, a, g))
        return out

    def summary_info(self) -> dict[str, float | str]:
        """Model constants for run summaries (SI units in the key names).

        Returns
        -------
        dict
            Mean stiffness, static transmission error, f_n, m_e, c_m and the stiffness name.

        See Also
        --------
        :func:`~gear_dyn.analysis.report.summarize` : The run summary that includes them.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, rectangular_stiffness
        >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
        >>> m.summary_info()["mean_mesh_stiffness_n_per_m"]
        130000000.0
        """
        return {
            "mean_mesh_stiffness_n_per_m": self.mean_stiffness,
            "static_transmission_error_m": self.static_load / self.mean_stiffness,
            "natural_frequency_hz": self.natural_frequency,
            "equivalent_mass_kg": self.mass,
            "mesh_damping_n_s_per_m": self.damping,
            "stiffness_name": self.stiffness.name,
        }

    # ---------------------------------------------------------------- outputs
    def outputs(self, t: FloatArray, y: FloatArray) -> dict[str, FloatArray]:
        """Derived series: ``dte`` (m), ``mesh_force`` (N), ``stiffness`` (N/m).

        Parameters
        ----------
        t : ndarray
            Times in s, shape (n,).
        y : ndarray
            States [x, v] in m and m/s, shape (2, n).

        Returns
        -------
        dict of ndarray
            Each series of shape (n,).

        See Also
        --------
        :class:`~gear_dyn.solvers.result.Result` : Keeps them in ``outputs``.

        Examples
        --------
        >>> import numpy as np
        >>> from gear_dyn import SDOFModel, rectangular_stiffness
        >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
        >>> out = m.outputs(np.array([0.0]), m.initial_state()[:, None])
        >>> out["mesh_force"]  # k(0) x at the static deflection (N)
        array([1153.84615385])
        """
        t = np.asarray(t, dtype=float)
        x, v = np.asarray(y[0], dtype=float), np.asarray(y[1], dtype=float)
        p = self.phase(t)
        kt = self.stiffness(p)
        u, ud = x, v
        if self.transmission_error is not None:
            u = x - self.transmission_error.value(p)
            ud = v - self.mesh_frequency * self.transmission_error.slope(p)
        if self.backlash is not None:
            u = dead_zone(u, self.backlash)
        force = kt * u + self.damping * ud
        return {"dte": x, "mesh_force": force, "stiffness": kt}


def sdof_from_pair(
    pair: GearPair,
    speed: float,
    torque: float,
    stiffness: PeriodicStiffness,
    damping_ratio: float = 0.06,
    inertias: tuple[float, float] | None = None,
    backlash: float | None = None,
    transmission_error: Signal | None = None,
) -> SDOFModel:
    """Build the single-DOF model of a gear pair at an operating point.

    Parameters
    ----------
    pair : GearPair
        The gear pair (base radii, teeth, blank inertias).
    speed : float
        Pinion speed in rad/s (> 0).
    torque : float
        Pinion (input) torque T1 in N m (>= 0); W = T1 / r_b1.
    stiffness : PeriodicStiffness
        Mesh stiffness.
    damping_ratio : float
        xi, default 0.06 (Jiang et al. 2018 give the range 0.03-0.17).
    inertias : (float, float) or None
        (I1, I2) in kg m^2; None uses solid blanks at the pitch radii (GearPair.blank_inertias).
    backlash : float or None
        Half gap in m.
    transmission_error : signal or None
        Static transmission error e(p) in m.

    Returns
    -------
    SDOFModel
        m_e = I1 I2 / (I1 r_b2^2 + I2 r_b1^2) in kg, W = T1 / r_b1 in N, f_m in Hz.

    Raises
    ------
    InputError
        A speed or torque out of range, or any invalid model field.

    See Also
    --------
    :class:`~gear_dyn.models.sdof.SDOFModel` : The model.
    :class:`~gear_dyn.geometry.GearPair` : The pair.
    :func:`~gear_dyn.stiffness.select.build_stiffness` : Its mesh stiffness.

    Examples
    --------
    >>> import math
    >>> from gear_dyn import GearPair, rectangular_stiffness
    >>> pair = GearPair(19, 48, 3.2e-3, math.radians(20), 16e-3)
    >>> k = rectangular_stiffness(pair.total_contact_ratio, 2e8, 3e8)
    >>> m = sdof_from_pair(pair, 300.0, 100.0, k)  # 300 rad/s, 100 N m
    >>> round(m.static_load, 1)  # T1 / r_b1 in N
    3500.6
    >>> round(m.mesh_frequency, 2)  # 19 * 300 / (2 pi) in Hz
    907.18
    """
    check_speed(speed)
    check_torque(torque)
    i1, i2 = inertias if inertias is not None else pair.blank_inertias()
    m = effective_mass(i1, i2, pair.rb1, pair.rb2)
    return SDOFModel(
        mass=m,
        stiffness=stiffness,
        damping_ratio=damping_ratio,
        static_load=torque / pair.rb1,
        mesh_frequency=mesh_frequency(pair, speed),
        backlash=backlash,
        transmission_error=transmission_error,
    )
