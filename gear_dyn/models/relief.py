"""Tip relief in the single-DOF model: load-dependent stiffness plus the relief's TE.

The loaded-contact analysis (:mod:`gear_dyn.modification.contact`) at the operating load gives,
over one mesh cycle, the tangent stiffness ``k_t(p)`` (sum of the loaded pairs) and the
transmission error the relief adds, ``e(p)``; the single-DOF model
``m x'' + c (x' - e') + k_t(p) (x - e) = W`` then has the loaded static transmission error
``delta(p)`` as its quasi-static solution. Alternatively
(``linearisation="secant"``) the model gets the ``K_TPM = F / delta`` of Wang et al. (2024) and
no ``e``: the same static solution, with the secant instead of the incremental stiffness (for
comparison only).
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError
from gear_dyn.geometry import GearPair
from gear_dyn.models.base import ModelDefaults
from gear_dyn.models.sdof import SDOFModel, sdof_from_pair
from gear_dyn.modification.contact import LoadedContact, PiecewiseSignal, loaded_contact
from gear_dyn.modification.lead import FlankModification
from gear_dyn.modification.relief import ProfileModification
from gear_dyn.modification.slice_contact import SliceContact, SliceOptions, slice_contact
from gear_dyn.stiffness.periodic import PeriodicStiffness, PiecewiseStiffness
from gear_dyn.stiffness.select import (  # re-exported: the function's first home
    pair_stiffness_function as pair_stiffness_function,
)

FloatArray = NDArray[np.float64]

LINEARISATIONS: tuple[str, ...] = ("tangent", "secant")


def relief_sdof(
    pair: GearPair,
    speed: float,
    torque: float,
    modification: ProfileModification | None,
    pair_stiffness: Callable[[FloatArray], FloatArray],
    damping_ratio: float = 0.06,
    inertias: tuple[float, float] | None = None,
    linearisation: str = "tangent",
    samples_per_segment: int = 48,
) -> tuple[ReliefSDOFModel, LoadedContact]:
    """Single-DOF model of a spur pair with tip relief at its operating load.

    Parameters
    ----------
    pair : GearPair
        Spur pair.
    speed : float
        Pinion speed in rad/s (> 0).
    torque : float
        Pinion torque in N m (> 0).
    modification : ProfileModification or None
        Tip reliefs (None: the unmodified pair through the same machinery).
    pair_stiffness : callable
        Unmodified single-pair stiffness ``K(s)`` in N/m.
    damping_ratio : float
        Mesh damping ratio xi.
    inertias : (float, float) or None
        (I1, I2) in kg m^2; None uses solid blanks.
    linearisation : str
        ``"tangent"`` (default: k_t and e) or ``"secant"`` (K_TPM, no e).
    samples_per_segment : int
        Loaded-contact samples per segment between switching phases.

    Returns
    -------
    (ReliefSDOFModel, LoadedContact)

    Raises
    ------
    InputError
        Bad parameters (see :func:`~gear_dyn.modification.contact.loaded_contact` and
        :func:`~gear_dyn.models.sdof.sdof_from_pair`).
    """
    if linearisation not in LINEARISATIONS:
        raise InputError(f"linearisation = {linearisation!r}: valid values are "
                         f"{', '.join(LINEARISATIONS)}")
    lc = loaded_contact(pair, pair_stiffness, torque, modification, samples_per_segment)
    relieved = modification is not None and not modification.is_zero
    if linearisation == "secant":
        k: PeriodicStiffness = lc.mesh_stiffness()
        te = None
    else:
        k = lc.tangent_stiffness()
        te = lc.transmission_error() if relieved else None
    base = sdof_from_pair(pair, speed, torque, k, damping_ratio, inertias,
                          transmission_error=te)
    info = {
        "stiffness_method": f"loaded contact ({linearisation})",
        "tip_relief": relief_info(modification),
        "static_ptp_transmission_error_m": lc.peak_to_peak_error,
        "mean_loaded_stiffness_n_per_m": lc.mesh_stiffness().mean,
    }
    model = ReliefSDOFModel(
        mass=base.mass, stiffness=k, damping_ratio=damping_ratio, static_load=base.static_load,
        mesh_frequency=base.mesh_frequency, transmission_error=te, info=info,
    )
    return model, lc


def slice_sdof(
    pair: GearPair,
    speed: float,
    torque: float,
    modification: FlankModification | None,
    pair_stiffness: Callable[[FloatArray], FloatArray] | None = None,
    damping_ratio: float = 0.06,
    inertias: tuple[float, float] | None = None,
    options: SliceOptions | None = None,
) -> tuple[ReliefSDOFModel, SliceContact]:
    """Single-DOF model of a spur or helical pair on its slice-method loaded contact.

    The tangent stiffness ``k_t(p)`` and the transmission error of the modifications
    ``e(p) = delta(p) - F_t / k_t(p)`` at the operating torque
    (:func:`~gear_dyn.modification.slice_contact`), linear between the mesh
    positions, feed ``m x'' + c (x' - e') + k_t (x - e) = W`` (the ``"tangent"`` form of
    :func:`relief_sdof`): its static solution is the loaded static TE.

    Parameters
    ----------
    pair : GearPair
    speed, torque : float
        Pinion speed (rad/s, > 0) and torque (N m, > 0).
    modification : FlankModification or None
        Tip reliefs, lead modifications, misalignment.
    pair_stiffness : callable or None
        Unmodified single-pair stiffness ``K(s)`` in N/m (None: potential energy).
    damping_ratio : float
    inertias : (float, float) or None
    options : SliceOptions or None

    Returns
    -------
    (ReliefSDOFModel, SliceContact)

    Raises
    ------
    InputError
        As :func:`~gear_dyn.modification.slice_contact` and
        :func:`~gear_dyn.models.sdof.sdof_from_pair`.
    """
    sc = slice_contact(pair, torque, modification, pair_stiffness, options)
    ph = np.append(sc.phase, 1.0)
    kt = np.append(sc.tangent_stiffness[0], sc.tangent_stiffness[0, 0])
    k = PiecewiseStiffness(np.array([0.0, 1.0]), ((ph, kt),), name="slice LTCA (tangent)")
    e = sc.relief_error[0]
    te = None if not np.any(e) else PiecewiseSignal.from_segments(
        np.array([0.0, 1.0]), np.zeros(ph.size, dtype=int), ph, np.append(e, e[0]))
    base = sdof_from_pair(pair, speed, torque, k, damping_ratio, inertias, transmission_error=te)
    mod = sc.modification
    info = {
        "stiffness_method": "slice LTCA (tangent)",
        "tip_relief": relief_info(mod.profile),
        "static_ptp_transmission_error_m": float(sc.peak_to_peak_te[0]),
        "mean_loaded_stiffness_n_per_m": float(sc.mean_secant_stiffness[0]),
        "slices": sc.options.slices, "mesh_positions": int(sc.phase.size),
    }
    model = ReliefSDOFModel(
        mass=base.mass, stiffness=k, damping_ratio=damping_ratio, static_load=base.static_load,
        mesh_frequency=base.mesh_frequency, transmission_error=te, info=info,
    )
    return model, sc


def relief_info(modification: ProfileModification | None) -> dict[str, Any]:
    """Plain-dict description of the reliefs (SI units in the key names) for summaries."""
    out: dict[str, Any] = {}
    for name in ("pinion", "gear"):
        r = None if modification is None else getattr(modification, name)
        out[name] = None if r is None else {"amount_m": r.amount, "length_m": r.length,
                                            "curve": r.curve}
    return out


@dataclass(frozen=True, eq=False)
class ReliefSDOFModel(SDOFModel):
    """:class:`~gear_dyn.models.sdof.SDOFModel` that also reports its tip relief in summaries."""

    info: dict[str, Any] = field(default_factory=dict)

    def summary_info(self) -> dict[str, Any]:
        """Extra summary entries: relief, loaded stiffness, static transmission error, f_n."""
        return {**self.info, "natural_frequency_hz": self.natural_frequency,
                "equivalent_mass_kg": self.mass}


class ContactSDOFModel(ModelDefaults):
    """Reference single-DOF model with the loaded-contact force itself (no linearisation).

        m_e x'' + c x' + sum_j K_j(s_j) max(0, x - g_j(s_j)) = W

    Every pair in geometric contact pushes only once ``x`` has closed its relief gap ``g_j``,
    at every instant of the motion (not only at the static load), so contact loss and the
    load-dependent pick-up are exact. Used to judge the linearised forms of :func:`relief_sdof`.
    ``K`` and ``g`` are tabulated along the path of contact (``table_points``, linear
    interpolation). Damping ``c = 2 xi sqrt(m_e k_m)`` with k_m the unmodified mean stiffness,
    acting on ``x'``. Contact loss is part of the force law: the model is nonlinear, not the
    linear mesh equation, and has no contact events (pairs pick up smoothly as the approach
    closes their relief gap).

    Parameters
    ----------
    pair : GearPair
        Spur pair.
    speed, torque : float
        Pinion speed (rad/s) and torque (N m).
    modification : ProfileModification or None
    pair_stiffness : callable
        Unmodified single-pair stiffness ``K(s)`` in N/m.
    damping_ratio : float
    inertias : (float, float) or None
    table_points : int
        Points of the K and g tables along the path (>= 16).
    """

    state_labels: tuple[str, ...] = ("x", "v")
    output_names: tuple[str, ...] = ("dte", "mesh_force", "stiffness")
    mean_stiffness: float

    def __init__(self, pair: GearPair, speed: float, torque: float,
                 modification: ProfileModification | None,
                 pair_stiffness: Callable[[FloatArray], FloatArray],
                 damping_ratio: float = 0.06, inertias: tuple[float, float] | None = None,
                 table_points: int = 2001) -> None:
        base = sdof_from_pair(pair, speed, torque,
                              loaded_contact(pair, pair_stiffness, torque).mesh_stiffness(),
                              damping_ratio, inertias)
        self.mass = base.mass
        self.damping = base.damping
        self.static_load = base.static_load
        self.mesh_frequency = base.mesh_frequency
        self.mean_stiffness = base.mean_stiffness
        self.natural_frequency = base.natural_frequency  # k_m the unmodified mean stiffness
        self._unmodified = base.stiffness  # switching at the geometric entry and exit
        self._s_a, self._pb = pair.start_of_contact, pair.base_pitch
        self._s_e = pair.end_of_contact
        self._n = int(math.ceil(pair.contact_ratio)) + 1
        self._s = np.linspace(self._s_a, self._s_e, max(int(table_points), 16))
        self._k = np.asarray(pair_stiffness(self._s), dtype=float)
        if modification is None or modification.is_zero:
            self._g = np.zeros_like(self._s)
        else:
            modification.check(pair)
            self._g = modification.separation(pair, self._s)
        self._modification = modification
        self._ds = float(self._s[1] - self._s[0])
        self._n_tab = int(self._s.size)
        self._k_list = [float(v) for v in self._k]
        self._g_list = [float(v) for v in self._g]

    def at_mesh_frequency(self, mesh_frequency: float) -> ContactSDOFModel:
        """A copy at another mesh frequency (only f_m depends on speed here)."""
        other = copy.copy(self)
        other.mesh_frequency = float(mesh_frequency)
        return other

    @property
    def state_scale(self) -> FloatArray:
        """Typical magnitudes [m, m/s]."""
        x = self.static_load / self.mean_stiffness
        return np.array([x, x * np.sqrt(self.mean_stiffness / self.mass)])

    def _elastic(self, t: float, x: float) -> tuple[float, float]:
        """(elastic force N, tangent stiffness N/m) at time t and approach x (pure Python: the
        solver's hot path; K and g interpolated linearly on the uniform table)."""
        p = (self.mesh_frequency * t) % 1.0
        s0, ds, n_tab = self._s_a, self._ds, self._n_tab
        k_list, g_list = self._k_list, self._g_list
        force = 0.0
        kt = 0.0
        for j in range(self._n):
            s = s0 + (p + j) * self._pb
            if s > self._s_e:
                break
            u = (s - s0) / ds
            i = min(int(u), n_tab - 2)
            w = u - i
            g = g_list[i] + w * (g_list[i + 1] - g_list[i])
            if x > g:
                k = k_list[i] + w * (k_list[i + 1] - k_list[i])
                force += k * (x - g)
                kt += k
        return force, kt

    def initial_state(self) -> FloatArray:
        """Static solution at t = 0 (bisection on the monotone elastic force), at rest."""
        lo, hi = 0.0, 10 * self.static_load / float(np.min(self._k)) + float(np.max(self._g))
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if self._elastic(0.0, mid)[0] < self.static_load:
                lo = mid
            else:
                hi = mid
        return np.array([0.5 * (lo + hi), 0.0])

    def rhs(self, t: float, y: FloatArray) -> FloatArray:
        """[x', v'] at time t (s)."""
        f, _ = self._elastic(t, float(y[0]))
        return np.array([y[1], (self.static_load - self.damping * y[1] - f) / self.mass])

    def jac(self, t: float, y: FloatArray) -> FloatArray:
        """Jacobian with the tangent stiffness of the pairs in contact."""
        _, kt = self._elastic(t, float(y[0]))
        return np.array([[0.0, 1.0], [-kt / self.mass, -self.damping / self.mass]])

    def switching_times(self, t0: float, t1: float) -> FloatArray:
        """Geometric entry/exit instants (a pair without relief enters with a force jump)."""
        return self._unmodified.switching_times(t0, t1, self.mesh_frequency)

    def summary_info(self) -> dict[str, Any]:
        """Extra summary entries."""
        return {"stiffness_method": "loaded contact (nonlinear contact force)",
                "tip_relief": relief_info(self._modification)}

    def outputs(self, t: FloatArray, y: FloatArray) -> dict[str, FloatArray]:
        """``dte`` (m), ``mesh_force`` (N), ``stiffness`` (tangent, N/m)."""
        f = np.empty(len(t))
        kt = np.empty(len(t))
        for i, (ti, xi) in enumerate(zip(t, y[0], strict=True)):
            f[i], kt[i] = self._elastic(float(ti), float(xi))
        return {"dte": np.asarray(y[0], dtype=float), "mesh_force": f + self.damping * y[1],
                "stiffness": kt}
