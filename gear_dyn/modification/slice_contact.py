"""Loaded tooth contact analysis (LTCA) by the slice method, for spur and helical pairs.

The face width B is cut into ``n`` slices of width ``dy = B / n`` (centres ``y_i``). In the plane
of action the contact line of tooth pair ``j`` is inclined by the base helix angle ``b_b``: at
mesh phase ``p`` its slice ``i`` touches at the roll distance

    u_ij = (p + j) p_bt - y_i tan b_b        (from the start of contact A; s = s_A + u)

(the convention of :mod:`gear_dyn.stiffness.contact_line`: phase 0, a line enters at A on the
front face). A slice is in contact for ``0 <= u_ij <= g_a``; spur pairs (``b_b = 0``) have all
slices of a pair at one position, which is the spur analysis of :mod:`.contact` cut in ``n``.

**Compliance of a slice** (thin-slice approximation, the transverse section per unit face width
as in :mod:`gear_dyn.stiffness.mesh`): the single-pair stiffness ``K(s)`` of the whole face (the
potential-energy method by default; Wang et al. 2024, eq. 5) splits into the Hertzian
compliance ``c_h = 2 / (pi B E*)`` and the structural rest ``c_b(s) = 1/K(s) - c_h`` (bending,
shear, axial, fillet foundation of both teeth). Slice ``i`` gets the structural (Winkler) spring
``k_w,i = dy / (B c_b(s_i))`` in series with the local Hertzian spring ``dy / (B c_h)``.

**Coupling of neighbouring slices.** A tooth is not a row of independent springs: the structural
springs of one tooth pair are joined by a shear layer (a Pasternak foundation, Pasternak 1954),
as in the elastic-foundation model of wide-faced spur and helical gears of Ajmi & Velex (2005):
``k_w w - d/dy (k_G dw/dy) = q`` along the face, free at both faces, discretised as springs
``k_c = k_G / dy`` between neighbouring slices. ``k_G = lambda^2 k_w_mean`` with the decay length
``lambda`` of a concentrated load along the face (``exp(-|y|/lambda)``, the beam on an elastic
foundation). Its default ``lambda = h / sqrt(2)``, h the whole depth ``(2 ha* + c*) m_n``, is a
Rayleigh-Ritz estimate (decision, docs/modification.md): a Kirchhoff cantilever plate of length
h under a tip line load ``W cos(k y)``, deflected in the cubic cantilever shape, stores the
energy of a stiffness per unit width ``k_0 (1 + h^2 k^2 / 2)`` (nu = 0.3), which is a Pasternak
foundation with ``lambda^2 = h^2 / 2``; 0 gives independent springs.
The Hertzian springs stay local. Per tooth pair the compliance matrix is
``C = (diag(k_w) + k_c L)^-1 + diag(1 / k_h)`` with ``L`` the free-free difference Laplacian.

**Load distribution** with the unilateral contact constraint (an active-set method on the
compliance system, as the influence-coefficient method of Conry & Seireg 1973): find the slice
loads ``f >= 0`` (along the transverse line of action) and the approach ``delta`` (the loaded
static transmission error, m along the line of action) with

    (C f)_i = delta - g_i  where f_i > 0,   (C f)_i >= delta - g_i  where f_i = 0,
    sum f_i = F_t = T1 / r_b1,

``g_i`` the unloaded gap of slice ``i``: tip reliefs (:class:`ProfileModification`), lead
modifications and misalignment (:mod:`.lead`). The normal slice loads are ``f_i / cos b_b``; they
sum to ``F_n = T1 / (r_b1 cos b_b)``.

Outputs per mesh position (and per torque of a ladder): loaded and unloaded static TE, the secant
(``F_t / delta``) and tangent (``dF_t / d delta`` at the solved active set) mesh stiffness, slice
loads, Hertz pressure (line load ``f_n / (dy / cos b_b)`` on the normal curvature), load sharing.
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gear_dyn.errors import InputError, SolverError, check_range
from gear_dyn.geometry import GearPair, check_torque
from gear_dyn.modification.lead import FlankModification
from gear_dyn.modification.stress import contact_stress
from gear_dyn.stiffness.contact_line import contact_line_breakpoints

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]
PairStiffnessFn = Callable[[FloatArray], FloatArray]

_NUDGE = 1e-9  # cycles: the one-sided limits at the corners of the field of contact


@dataclass(frozen=True)
class SliceOptions:
    """Discretisation and coupling of the slice analysis.

    Parameters
    ----------
    slices : int
        Slices across the face width (1 .. 2000).
    positions : int
        Mesh positions over one mesh cycle, uniform in phase (2 .. 100000).
    coupling_length : float or None
        Decay length lambda (m) of the shear-layer coupling of neighbouring slices; None:
        ``h / sqrt(2)`` with h the tooth's whole depth ``(2 ha* + c*) m_n`` (module docstring);
        0: independent slices.
    max_iterations : int
        Cap on the active-set iterations (>= 1).

    Raises
    ------
    InputError
        Values out of range.
    """

    slices: int = 30
    positions: int = 32
    coupling_length: float | None = None
    max_iterations: int = 500

    def __post_init__(self) -> None:
        for name, low, high in (("slices", 1, 2000), ("positions", 2, 100000),
                                ("max_iterations", 1, 100000)):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int):
                raise InputError(f"{name} = {v!r}: expected a whole number, valid range "
                                 f"{low} .. {high}")
            check_range(name, v, "", low=low, high=high)
        if self.coupling_length is not None:
            check_range("coupling_length", self.coupling_length, "m", low=0.0, high=1.0)

    def decay_length(self, pair: GearPair) -> float:
        """The coupling decay length lambda in m for ``pair`` (default ``h / sqrt(2)``, h the
        whole depth ``(2 ha* + c*) m_n``)."""
        if self.coupling_length is not None:
            return self.coupling_length
        return (2 * pair.addendum_coef + pair.clearance_coef) * pair.module / math.sqrt(2.0)


@dataclass(frozen=True, eq=False)
class SliceContact:
    """Result of :func:`slice_contact`: arrays over torque (T), mesh position (P), tooth pair
    (J) and slice (S).

    Attributes
    ----------
    pair : GearPair
    modification : FlankModification
    options : SliceOptions
    torque : ndarray (T,)
        Pinion torques in N m.
    phase : ndarray (P,)
        Mesh phases in cycles (0: a line enters at A on the front face).
    face : ndarray (S,)
        Slice centres in m from the front face.
    position : ndarray (P, J, S)
        Roll distance s of each slice's contact point in m from T1 (NaN out of contact).
    gap : ndarray (P, J, S)
        Unloaded gap in m along the line of action (NaN out of contact).
    share : ndarray (P, J, S)
        Share of each slice's contact line inside the field of contact (0 .. 1).
    load : ndarray (T, P, J, S)
        Normal load of each slice in N (0 out of contact).
    pressure : ndarray (T, P, J, S)
        Hertz peak contact pressure in Pa (0 where unloaded).
    deflection : ndarray (T, P)
        Loaded static transmission error delta in m along the transverse line of action.
    unloaded : ndarray (P,)
        Unloaded static transmission error (the smallest gap in contact) in m.
    tangent_stiffness : ndarray (T, P)
        dF_t / d delta in N/m at the solved active set.
    iterations : int
        Active-set iterations used.
    """

    pair: GearPair
    modification: FlankModification
    options: SliceOptions
    torque: FloatArray
    phase: FloatArray
    face: FloatArray
    position: FloatArray = field(repr=False)
    gap: FloatArray = field(repr=False)
    share: FloatArray = field(repr=False)
    load: FloatArray = field(repr=False)
    pressure: FloatArray = field(repr=False)
    deflection: FloatArray = field(repr=False)
    unloaded: FloatArray = field(repr=False)
    tangent_stiffness: FloatArray = field(repr=False)
    iterations: int = 0

    # ------------------------------------------------------------------ derived per position
    @property
    def transverse_load(self) -> FloatArray:
        """F_t = T1 / r_b1 in N along the transverse line of action (T,)."""
        return self.torque / self.pair.rb1

    @property
    def normal_load(self) -> FloatArray:
        """F_n = T1 / (r_b1 cos b_b) in N (T,)."""
        return self.transverse_load / math.cos(self.pair.beta_b)

    @property
    def secant_stiffness(self) -> FloatArray:
        """F_t / delta in N/m (T, P) (delta from the unmodified rigid-body position)."""
        return self.transverse_load[:, None] / self.deflection

    @property
    def relief_error(self) -> FloatArray:
        """Transmission error of the modifications for dynamics, delta - F_t / k_t, m (T, P)."""
        return self.deflection - self.transverse_load[:, None] / self.tangent_stiffness

    @property
    def pair_load(self) -> FloatArray:
        """Normal load of each tooth pair in N (T, P, J)."""
        return self.load.sum(axis=3)

    @property
    def sharing(self) -> FloatArray:
        """Load-sharing factor of each tooth pair, F_j / F (T, P, J)."""
        return self.pair_load / self.normal_load[:, None, None]

    @property
    def line_load(self) -> FloatArray:
        """Normal load per unit contact-line length in N/m (T, P, J, S)."""
        dy = self.pair.face_width / self.face.size
        length = np.where(self.share > 0.0, self.share, 1.0) * dy / math.cos(self.pair.beta_b)
        return self.load / length

    @property
    def peak_pressure(self) -> FloatArray:
        """Largest Hertz pressure over the slices at each position in Pa (T, P)."""
        return self.pressure.max(axis=(2, 3))

    @property
    def load_centre(self) -> FloatArray:
        """Face position of the resultant normal load in m from the front face (T, P)."""
        return np.einsum("tpjs,s->tp", self.load, self.face) / self.load.sum(axis=(2, 3))

    # ------------------------------------------------------------------ over the cycle
    @property
    def peak_to_peak_te(self) -> FloatArray:
        """Peak-to-peak loaded static TE over the cycle in m (T,)."""
        return np.ptp(self.deflection, axis=1)

    @property
    def peak_to_peak_unloaded_te(self) -> float:
        """Peak-to-peak unloaded static TE over the cycle in m."""
        return float(np.ptp(self.unloaded))

    @property
    def mean_secant_stiffness(self) -> FloatArray:
        """Mean over the cycle of F_t / delta in N/m (T,)."""
        return self.secant_stiffness.mean(axis=1)

    @property
    def mean_tangent_stiffness(self) -> FloatArray:
        """Mean over the cycle of the tangent stiffness in N/m (T,)."""
        return self.tangent_stiffness.mean(axis=1)

    @property
    def max_pressure(self) -> FloatArray:
        """Largest Hertz pressure over the cycle in Pa (T,)."""
        return self.peak_pressure.max(axis=1)

    def at(self, index: int) -> SliceContact:
        """The result of one torque of the ladder (``index`` into ``torque``)."""
        n = self.torque.size
        i = int(index)
        if not -n <= i < n:
            raise InputError(f"torque index = {index!r}: valid range 0 .. {n - 1}")
        sl = slice(i % n, i % n + 1)
        return SliceContact(self.pair, self.modification, self.options, self.torque[sl],
                            self.phase, self.face, self.position, self.gap, self.share,
                            self.load[sl],
                            self.pressure[sl], self.deflection[sl], self.unloaded,
                            self.tangent_stiffness[sl], self.iterations)

    # ------------------------------------------------------------------ export
    def summary(self) -> list[dict[str, float]]:
        """One row per torque: PPTE, mean TE, mean stiffnesses, peak pressure (SI keys)."""
        rows = []
        for i, t in enumerate(self.torque):
            rows.append({
                "torque_n_m": float(t),
                "normal_load_n": float(self.normal_load[i]),
                "peak_to_peak_static_te_m": float(self.peak_to_peak_te[i]),
                "mean_static_te_m": float(self.deflection[i].mean()),
                "peak_to_peak_unloaded_te_m": self.peak_to_peak_unloaded_te,
                "mean_loaded_stiffness_n_per_m": float(self.mean_secant_stiffness[i]),
                "mean_tangent_stiffness_n_per_m": float(self.mean_tangent_stiffness[i]),
                "peak_stress_pa": float(self.max_pressure[i]),
                "max_sharing": float(self.sharing[i].max()),
            })
        return rows

    def to_dict(self) -> dict[str, Any]:
        """Plain-dict form (JSON-ready, SI units in the key names): settings, per-torque
        summary, and the per-position series of every torque."""
        pair = self.pair
        return {
            "method": "slice LTCA (Pasternak-coupled slices, Ajmi & Velex 2005)",
            "slices": self.options.slices,
            "positions": self.options.positions,
            "coupling_length_m": self.options.decay_length(pair),
            "overlap_ratio": pair.overlap_ratio,
            "contact_ratio": pair.contact_ratio,
            "base_helix_angle_rad": pair.beta_b,
            "face_m": self.face.tolist(),
            "phase": self.phase.tolist(),
            "unloaded_te_m": self.unloaded.tolist(),
            "summary": self.summary(),
            "per_position": [{
                "torque_n_m": float(t),
                "loaded_te_m": self.deflection[i].tolist(),
                "secant_stiffness_n_per_m": self.secant_stiffness[i].tolist(),
                "tangent_stiffness_n_per_m": self.tangent_stiffness[i].tolist(),
                "peak_pressure_pa": self.peak_pressure[i].tolist(),
                "sharing": self.sharing[i].tolist(),
            } for i, t in enumerate(self.torque)],
        }

    def position_table(self) -> dict[str, FloatArray]:
        """Columns (one row per torque and mesh position) for CSV export, SI units."""
        t_n, p_n = self.deflection.shape
        return {
            "torque_n_m": np.repeat(self.torque, p_n),
            "phase": np.tile(self.phase, t_n),
            "loaded_te_m": self.deflection.ravel(),
            "unloaded_te_m": np.tile(self.unloaded, t_n),
            "secant_stiffness_n_per_m": self.secant_stiffness.ravel(),
            "tangent_stiffness_n_per_m": self.tangent_stiffness.ravel(),
            "peak_pressure_pa": self.peak_pressure.ravel(),
            "load_centre_m": self.load_centre.ravel(),
        }

    def rows(self) -> list[dict[str, float]]:
        """One row per torque and mesh position (:meth:`position_table` as dicts of plain
        floats, SI units in the keys): the table ``gear-dyn contact`` writes per case into
        ltca.csv.

        Returns
        -------
        list of dict
            ``torque_n_m``, ``phase``, loaded and unloaded TE (m), stiffnesses (N/m), peak
            pressure (Pa), load centre (m).
        """
        from gear_dyn.io import column_rows

        return column_rows(self.position_table())

    def to_csv(self, path: str | Path) -> Path:
        """Write :meth:`rows` as CSV atomically; returns the file written."""
        from gear_dyn.io import write_csv

        return write_csv(path, self.position_table())

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """Line load over the field of contact and the static TE
        (:func:`gear_dyn.plots.contact.plot_face_load`, looked up by name; ``ax``: None or its
        Axes, ``kwargs`` as there, e.g. ``index``, ``title``); returns the Figure."""
        plots = importlib.import_module("gear_dyn.plots.contact")
        return plots.plot_face_load(self, ax=ax, **kwargs)

    def slice_table(self) -> dict[str, FloatArray]:
        """Columns (one row per torque, position, tooth pair and slice in contact) for CSV."""
        inside = np.broadcast_to(np.isfinite(self.position), self.load.shape)
        idx = np.nonzero(inside)
        pos = np.broadcast_to(self.position, self.load.shape)
        return {
            "torque_n_m": self.torque[idx[0]],
            "phase": self.phase[idx[1]],
            "pair": idx[2].astype(float),
            "face_m": self.face[idx[3]],
            "s_from_a_m": pos[idx] - self.pair.start_of_contact,
            "gap_m": np.broadcast_to(self.gap, self.load.shape)[idx],
            "load_n": self.load[idx],
            "line_load_n_per_m": self.line_load[idx],
            "pressure_pa": self.pressure[idx],
        }


def pasternak_solve(springs: ArrayLike, k_c: float, rhs: ArrayLike) -> FloatArray:
    """Deflections of rows of slices on a Pasternak foundation under given slice forces.

    Solves ``(diag(springs) + k_c L) w = rhs`` with L the free-free second-difference matrix
    (springs ``k_c`` between neighbouring slices only, Pasternak 1954; Ajmi & Velex 2005) by
    the Thomas algorithm, batched over the leading axes. Away from the ends a unit force on
    slice k deflects slice i by ``r^|i - k|`` times its own deflection, with ``r`` the root
    below 1 of ``k_c r^2 - (k + 2 k_c) r + k_c = 0``: the discrete ``exp(-|y| / lambda)`` of a
    beam on an elastic foundation.

    Parameters
    ----------
    springs : array_like, shape (..., S)
        Spring of each slice to ground in N/m (> 0).
    k_c : float
        Coupling spring between neighbouring slices in N/m (>= 0; 0: independent slices).
    rhs : array_like, shape (..., S) or (..., S, K)
        Slice forces in N (K right-hand sides at once).

    Returns
    -------
    ndarray
        Deflections in m, shaped like ``rhs``.
    """
    k = np.asarray(springs, dtype=float)
    r = np.asarray(rhs, dtype=float)
    extra = r.ndim - k.ndim  # 0 or 1 trailing right-hand-side axis
    n = k.shape[-1]
    lap = np.full(n, 2.0 * k_c)
    lap[[0, -1]] = k_c if n > 1 else 0.0
    d = k + lap
    if extra:
        d = d[..., None]
    rows = np.moveaxis(r, -1 - extra, 0).copy()
    diag = np.moveaxis(d, -1 - extra, 0)
    cp = np.empty(rows.shape)
    m = diag[0]
    cp[0] = -k_c / m
    rows[0] = rows[0] / m
    for i in range(1, n):
        m = diag[i] + k_c * cp[i - 1]
        cp[i] = -k_c / m
        rows[i] = (rows[i] + k_c * rows[i - 1]) / m
    for i in range(n - 2, -1, -1):
        rows[i] = rows[i] - cp[i] * rows[i + 1]
    return np.moveaxis(rows, 0, -1 - extra)


def _default_pair_stiffness(pair: GearPair) -> PairStiffnessFn:
    from gear_dyn.stiffness.potential_energy import potential_energy_pair_stiffness

    return lambda s: potential_energy_pair_stiffness(pair, s)


def slice_geometry(pair: GearPair, slices: int, positions: int) -> tuple[
        FloatArray, FloatArray, FloatArray, FloatArray]:
    """Phases (P,), slice centres (S,), roll distance s (P, J, S) in m from T1 and the share
    of each slice's contact line inside the field of contact (P, J, S), 0 .. 1.

    A helical slice spans ``dy tan b_b`` of roll distance; where it straddles the start or end
    of contact only the share ``w`` inside touches, at the middle of that share (spur: w is 0
    or 1). Tooth pairs never in contact are dropped.
    """
    pb, g_a, b = pair.base_pitch, pair.path_of_contact, pair.face_width
    tan_bb = abs(math.tan(pair.beta_b))
    dy = b / slices
    y = (np.arange(slices) + 0.5) * dy
    # a left-hand helix (negative angle, should a pair carry one) enters at the rear face
    y_lag = y if pair.beta_b >= 0.0 else b - y
    kinks = contact_line_breakpoints(pair)
    phase = np.unique(np.mod(np.concatenate([np.arange(positions) / positions,
                                             kinks - _NUDGE, kinks + _NUDGE]), 1.0))
    n_lines = int(math.floor((g_a + b * tan_bb) / pb)) + 2
    j = np.arange(n_lines)
    u = (phase[:, None, None] + j[None, :, None]) * pb - y_lag[None, None, :] * tan_bb
    tol = 1e-12 * pb
    half = 0.5 * dy * tan_bb
    if half > tol:
        lo, hi = np.maximum(u - half, 0.0), np.minimum(u + half, g_a)
        share = np.clip((hi - lo) / (2 * half), 0.0, 1.0)
        share = np.where(share > 1e-9, share, 0.0)
        u = np.where(share > 0.0, 0.5 * (lo + hi), u)
    else:
        share = ((u >= -tol) & (u <= g_a + tol)).astype(float)
    keep = (share > 0.0).any(axis=(0, 2))
    f64 = np.float64
    return (np.asarray(phase, dtype=f64), np.asarray(y, dtype=f64),
            np.asarray(pair.start_of_contact + u[:, keep, :], dtype=f64),
            np.asarray(share[:, keep, :], dtype=f64))


def slice_contact(
    pair: GearPair,
    torque: ArrayLike,
    modification: FlankModification | None = None,
    pair_stiffness: PairStiffnessFn | None = None,
    options: SliceOptions | None = None,
) -> SliceContact:
    """Loaded tooth contact analysis of a spur or helical pair by the slice method.

    Parameters
    ----------
    pair : GearPair
        Spur or helical pair.
    torque : float or array_like
        Pinion torque T1 in N m (> 0), or a ladder of torques.
    modification : FlankModification or None
        Tip reliefs, lead modifications, misalignment; None for perfect, aligned flanks.
    pair_stiffness : callable or None
        ``K(s)``: unmodified single-pair stiffness of the whole face in N/m at roll distance
        ``s`` (m from T1), vectorised; None: the potential-energy method.
    options : SliceOptions or None
        Slices, positions, coupling; None: the defaults (30 slices, 32 positions).

    Returns
    -------
    SliceContact

    Raises
    ------
    InputError
        Torque not positive, a relief longer than the tooth allows, a stiffness that is not
        finite or not above the Hertzian part alone.
    SolverError
        The active set did not settle within ``options.max_iterations``.

    Examples
    --------
    >>> import math
    >>> from gear_dyn.geometry import GearPair
    >>> p = GearPair(23, 79, 6e-3, math.radians(20), 70e-3, math.radians(20), x1=0.3, x2=-0.1)
    >>> r = slice_contact(p, 2000.0)
    >>> bool(abs(r.load.sum(axis=(2, 3)) - r.normal_load[0]).max() < 1e-6 * r.normal_load[0])
    True
    """
    opts = options or SliceOptions()
    mod = modification or FlankModification()
    torques = np.atleast_1d(np.asarray(torque, dtype=float)).ravel()
    if torques.size == 0:
        raise InputError("torque: empty ladder; give at least one torque in N*m (> 0)")
    for t in torques:
        check_torque(float(t), positive=True)
    if mod.profile is not None:
        mod.profile.check(pair)
    fn = pair_stiffness or _default_pair_stiffness(pair)
    phase, y, s, share = slice_geometry(pair, opts.slices, opts.positions)
    inside = share > 0.0
    n_s = y.size
    b, dy = pair.face_width, pair.face_width / n_s
    s_clip = np.clip(s, pair.start_of_contact, pair.end_of_contact)

    # stiffness of the slices: structural (Winkler) in series with Hertz, per unit width
    k_full = np.asarray(fn(s_clip.ravel()), dtype=float).reshape(s.shape)
    c_h = 2.0 / (math.pi * b * pair.effective_youngs_modulus)
    c_b = 1.0 / k_full - c_h
    if not np.all(np.isfinite(k_full)) or np.any(c_b <= 0.0):
        bad = k_full[~np.isfinite(k_full) | (c_b <= 0.0)][0]
        raise InputError(f"single-pair stiffness = {bad:.6g} N/m: valid range 0 < K < "
                         f"{1.0 / c_h:.6g} N/m (finite, softer than the Hertzian contact alone)")
    k_w = dy / (b * c_b)  # (P, J, S) N/m per slice: the tooth spans the whole slice
    k_h = share * dy / (b * c_h)  # the contact only the share of its line inside the field
    lam = opts.decay_length(pair)
    k_w_mean = float(np.mean(k_w[inside])) / dy  # N/m per m of face
    k_c = lam**2 * k_w_mean / dy

    gap = np.zeros_like(s)
    if mod.profile is not None and not mod.profile.is_zero:
        gap = gap + mod.profile.separation(pair, s_clip)
    gap = gap + mod.face_separation(pair, y)[None, None, :]
    f_t = torques / pair.rb1
    force, delta, k_t, iters = _solve(k_w, k_c, np.where(inside, k_h, 0.0),
                                      np.where(inside, gap, 0.0), inside, f_t,
                                      opts.max_iterations)
    cos_bb = math.cos(pair.beta_b)
    load = force / cos_bb
    pressure = _pressure(pair, mod, s_clip, inside,
                         force / (np.where(inside, share, 1.0) * dy))
    unloaded = np.where(inside, gap, np.inf).min(axis=(1, 2))
    return SliceContact(pair, mod, opts, torques, phase, y, np.where(inside, s, np.nan),
                        np.where(inside, gap, np.nan), share, load, pressure, delta, unloaded,
                        k_t, iters)


def _solve(k_w: FloatArray, k_c: float, k_h: FloatArray, gap: FloatArray, inside: BoolArray,
           f_t: FloatArray, max_iter: int) -> tuple[FloatArray, FloatArray, FloatArray, int]:
    """Active-set solution of the unilateral contact, batched over torque and position.

    With the active set fixed, a loaded slice's Hertzian spring pushes the tooth pair's
    structure: ``f = k_h (delta - g - w)`` and ``(diag(k_w) + k_c L) w = f`` give the
    tridiagonal system ``(diag(k_w + k_h) + k_c L) w = k_h (delta - g)`` (k_h = 0 off the
    active set), solved for ``delta = 1`` and for the gaps; ``sum f = F_t`` fixes delta. Slices
    pulling (f < 0) leave the set; then slices the approach has closed (``delta - g - w > 0``)
    join it, until neither happens (the compliance form of Conry & Seireg 1973, solved in its
    stiffness form).

    Returns slice loads along the transverse line of action (T, P, J, S) in N, the approach
    delta (T, P) in m, the tangent stiffness ``dF_t / d delta`` (T, P) in N/m and the
    iterations used.
    """
    n_t = f_t.size
    shape = (n_t, *gap.shape)
    act = np.broadcast_to(inside, shape).copy()
    g = np.broadcast_to(gap, shape)
    kh = np.broadcast_to(k_h, shape)
    kw = np.broadcast_to(k_w, shape)
    ft = f_t[:, None]
    for it in range(1, max_iter + 1):
        ka = np.where(act, kh, 0.0)
        w = pasternak_solve(kw + ka, k_c, np.stack([ka, ka * g], axis=-1))
        w1, w2 = w[..., 0], w[..., 1]
        a = (ka * (1.0 - w1)).sum(axis=(2, 3))
        bsum = (ka * (g - w2)).sum(axis=(2, 3))
        delta = (ft + bsum) / a
        dd = delta[..., None, None]
        # closure delta - g - w at every slice (w: the structure's deflection there)
        closure = dd * (1.0 - w1) - (g - w2)
        force = ka * closure
        neg = act & (force < -1e-12 * ft[..., None, None])
        any_neg = neg.any(axis=(2, 3))
        pen = inside & ~act & (closure > 1e-10 * np.abs(dd))
        new = np.where(any_neg[..., None, None], act & ~neg, act | pen)
        if np.array_equal(new, act):
            return np.maximum(force, 0.0), delta, a, it
        act = new
    raise SolverError(f"slice contact: the active set did not settle in {max_iter} iterations "
                      "(limit SliceOptions(max_iterations=N) in Python); try more slices or a "
                      "smaller coupling_length ([slice_contact] slices, coupling_length)")


def _pressure(pair: GearPair, mod: FlankModification, s: FloatArray, inside: BoolArray,
              line_load_t: FloatArray) -> FloatArray:
    """Hertz peak pressure (Pa) of every loaded slice: the line load on the normal curvature.

    The normal line load is ``f_t / (w dy)`` (w the slice's share in contact) and the normal
    curvature ``cos b_b`` times the transverse one, so the pressure is the transverse Hertz
    value at the same line load times ``sqrt(cos b_b)`` (relieved flanks: the curvature of
    :func:`contact_stress`)."""
    out = np.zeros_like(line_load_t)
    loaded = np.broadcast_to(inside, line_load_t.shape) & (line_load_t > 0.0)
    if not np.any(loaded):
        return out
    pos = np.broadcast_to(s, line_load_t.shape)[loaded]
    w = line_load_t[loaded] * pair.face_width  # the whole-face force of that line load
    sigma, _ = contact_stress(pair, pos, w, mod.profile)
    out[loaded] = sigma * math.sqrt(math.cos(pair.beta_b))
    return out
