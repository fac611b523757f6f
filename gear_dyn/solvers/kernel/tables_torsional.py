"""Tables of the kernel's models in the mesh phase: the torsional model's.

The kernel (``gd_torsional.c``) steps the four states ``[q1, q2, q1', q2']`` of
:class:`~gear_dyn.models.torsional.TorsionalModel` (eccentricity and friction; no backlash,
no transmission error) from a table of its state-free coefficients in the mesh phase
``p = z1 th1 / (2 pi)`` (cycles): :data:`QUANTITIES` on pieces between the model's switching
instants, over the hunting period with eccentricity (one mesh cycle without), each interpolated
at Chebyshev points with the lowest degree (<= :data:`MAX_DEGREE`) that meets
:data:`TABLE_ERROR` (``TorsionalTable.max_error``). An eccentric pair whose stiffness and
friction come from its contact lines stores no polynomials: the kinematics are smooth and
periodic over the hunting period (sums of shaft-order terms), so the table holds their Fourier
coefficients (:class:`LineKinematics`) and the kernel evaluates the contact-line overlap of Liu
et al. (2017), eqs. 14-27, from them; the pieces remain, as the switching instants the kernel
steps between. The native FMU writes these arrays as C text (:mod:`gear_dyn.fmu.export_c`), the
solvers' ``kernel`` method passes them through ctypes (:mod:`gear_dyn.solvers.kernel.run`). Why
tables in phase, and the figures: docs/native_fmu.md, "The torsional model".
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.eccentricity.contact_lines import LineLayout, contact_lines
from gear_dyn.eccentricity.friction import friction_factors
from gear_dyn.errors import InputError
from gear_dyn.models.torsional_parts import ContactLineStiffness
from gear_dyn.models.torsional_table import node_matrix
from gear_dyn.solvers.kernel.tables import CHECK_POINTS, check_points, piecewise_values

FloatArray = NDArray[np.float64]

#: the quantities of the table, in the kernel's order
QUANTITIES = ("e_ecc", "de_dp", "stiffness", "phi1", "phi2")
#: table error allowed, relative to each quantity's scale (far below the stated RK_ERROR)
TABLE_ERROR = 1e-9
#: lowest and highest polynomial degree tried
MIN_DEGREE, MAX_DEGREE = 3, 10
#: the widest piece in SCREEN tries each degree before all pieces do (the degree search's screen)
SCREEN = 8
#: the kinematics of the contact-line form, in the kernel's order (gd_lines in gd_kernel.h);
#: ``travel`` less its mean growth ``p p_bt``
KINEMATICS = ("e_ecc", "travel", "l_ac", "l_cd", "l_cp", "foot1", "foot2")
#: samples per mesh cycle of the kinematics' discrete Fourier transform
FOURIER_SAMPLES = 64
#: Fourier terms smaller than this times W/k_m are dropped: the largest cut that meets
#: :data:`TABLE_ERROR`, one for e_ecc (it makes e and de/dp) and one for the positions (they make
#: k, phi1 and phi2)
FOURIER_CUTS = (1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13)


@dataclass(frozen=True)
class LineKinematics:
    """The eccentric kinematics as Fourier series in the mesh phase, and the contact-line layout.

    Attributes
    ----------
    fourier : ndarray (K + 1, 7, 2)
        Amplitudes (m) of ``cos(2 pi k p / P)`` and ``sin(2 pi k p / P)``, k = 0..K, of
        :data:`KINEMATICS` (P = ``period`` cycles). ``de_ecc/dp`` is the series' derivative.
    period : int
        P, the hunting period in mesh cycles.
    layout : LineLayout
        Pitch, line width and index range of the contact lines.
    per_length : float
        k_l in N/m^2 (k = k_l L).
    friction : float or None
        Mean friction coefficient, None without friction (phi1 = phi2 = 0).
    """

    fourier: FloatArray
    period: int
    layout: LineLayout
    per_length: float
    friction: float | None

    def kinematics(self, phase: FloatArray) -> tuple[dict[str, FloatArray], FloatArray]:
        """:data:`KINEMATICS` (``travel`` whole) and ``de_ecc/dp`` (m/cycle) at phases."""
        p = np.asarray(phase, dtype=float)
        k = np.nonzero(np.any(self.fourier != 0.0, axis=(1, 2)))[0]  # the terms kept only
        f = self.fourier[k]
        th = np.outer(2.0 * np.pi * np.mod(p, self.period) / self.period, k)
        c, s = np.cos(th), np.sin(th)
        vals = c @ f[:, :, 0] + s @ f[:, :, 1]  # (n, 7)
        kin = {q: vals[:, i] for i, q in enumerate(KINEMATICS)}
        kin["travel"] = kin["travel"] + p * self.layout.pitch
        w = 2.0 * np.pi * k / self.period
        rate = c @ (w * f[:, 0, 1]) - s @ (w * f[:, 0, 0])
        return kin, rate

    def evaluate(self, phase: FloatArray) -> FloatArray:
        """The five quantities of :data:`QUANTITIES` at phases (cycles): array (5, n)."""
        from types import SimpleNamespace

        kin, rate = self.kinematics(phase)
        place = SimpleNamespace(**kin)
        k = self.per_length * contact_lines(self.layout, place).total  # type: ignore[arg-type]
        if self.friction is None:
            phi1 = phi2 = np.zeros_like(k)
        else:
            ff = friction_factors(self.layout, place, self.friction)  # type: ignore[arg-type]
            phi1, phi2 = ff.torque_pinion, ff.torque_gear
        return np.array([kin["e_ecc"], rate, k, phi1, phi2])


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
    #: the contact-line form: no polynomials (``coef`` has no columns), the kernel evaluates
    #: these series and the overlap
    lines: LineKinematics | None = None

    #: fitted, not exact (the single-DOF PhaseTable's attribute, for code that shows both)
    exact = False

    def evaluate(self, phase: FloatArray) -> FloatArray:
        """The five quantities at phases (cycles, any real), vectorised: array (5, n)."""
        if self.lines is not None:
            return self.lines.evaluate(np.mod(np.asarray(phase, dtype=float), self.period))
        return piecewise_values(self.breaks, self.coef, phase, float(self.period))

    @property
    def has_rate(self) -> bool:
        """de_ecc/dp is not zero everywhere (the damping force moves with the speed input)."""
        return self.lines is not None or bool(np.any(self.coef[:, 1] != 0.0))

    @property
    def has_friction(self) -> bool:
        """phi1 or phi2 is not zero everywhere."""
        if self.lines is not None:
            return self.lines.friction is not None
        return bool(np.any(self.coef[:, 3:] != 0.0))



def _period_cycles(model: Any) -> int:
    """Mesh cycles in the table: the hunting period with eccentricity, else one."""
    if not model.eccentric:
        return 1
    n = model.mesh.hunting_period * model.mesh_frequency
    if abs(n - round(n)) > 1e-9 * n:
        raise InputError(f"native FMU: the hunting period is {n!r} mesh cycles, not a whole "
                         "number")
    return int(round(n))


def torsional_table(model: Any, lines: bool = True) -> TorsionalTable:
    """Tabulate the torsional model's state-free coefficients in the mesh phase.

    ``lines``: an eccentric pair with contact-line stiffness gets the contact-line form
    (:class:`LineKinematics`: small, for the FMU; each right-hand side then sums the series and
    the overlap); False gives it polynomials on every piece like any other model (larger,
    about 10x cheaper to step: the solvers' ``kernel`` method).

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
    if lines and model.eccentric and isinstance(model.stiffness, ContactLineStiffness):
        u = np.linspace(-0.98, 0.98, CHECK_POINTS)
        chk = (mid[:, None] + half[:, None] * u[None, :]).ravel()
        return _line_table(model, br, chk, direct(chk), scale)

    def at(pieces: Any, s: FloatArray) -> FloatArray:
        """The quantities at the local points ``s`` of ``pieces``: (5, pieces, points)."""
        ph = (mid[pieces, None] + half[pieces, None] * s[None, :]).ravel()
        return direct(ph).reshape(5, -1, s.size)

    def fit_error(pieces: Any, degree: int) -> tuple[FloatArray, FloatArray]:
        """The fit at ``degree`` on ``pieces`` and its largest error at the check points (the
        extrema of T_{degree+1}), relative to the scales."""
        s, to_mono = node_matrix(degree)
        coef = _fit(to_mono, at(pieces, s))
        u = check_points(degree)
        approx = _at(coef, np.vander(u, degree + 1))
        exact = at(pieces, u).reshape(5, -1)
        return coef, np.max(np.abs(approx - exact), axis=1) / scale

    # the widest share 1/SCREEN of the pieces first (an interpolant's error grows with the
    # width as width^(degree + 1)): a degree that fails there fails on all pieces (the error is
    # a maximum over pieces, each fitted alone), so only a degree that passes is fitted on all
    few = np.sort(np.argsort(a - b, kind="stable")[: -(-a.size // SCREEN)])
    every = np.arange(a.size)
    for degree in range(MIN_DEGREE, MAX_DEGREE + 1):
        if degree < MAX_DEGREE and few.size < a.size:
            if not np.all(fit_error(few, degree)[1] <= TABLE_ERROR):
                continue
        coef, err = fit_error(every, degree)
        if np.all(err <= TABLE_ERROR):
            return TorsionalTable(br, degree, coef, period,
                                  {n: float(e) for n, e in zip(QUANTITIES, err, strict=True)})
    raise InputError(f"native FMU table: no polynomial degree up to {MAX_DEGREE} reaches the "
                     f"table error {TABLE_ERROR:g} (reached {float(np.max(err)):.3g})")


def split_table(table: TorsionalTable) -> TorsionalTable:
    """The polynomial table with every piece split at its middle: the same polynomials (each
    half re-expanded in its own local variable, exactly up to rounding) on twice the pieces, so
    a stepper whose steps end at piece edges takes half steps where the edges set them."""
    if table.lines is not None:
        raise InputError("split_table: the contact-line form has no polynomials to split")
    a, b = table.breaks[:-1], table.breaks[1:]
    br = np.empty(2 * a.size + 1)
    br[0::2], br[1::2] = table.breaks, 0.5 * (a + b)
    s, to_mono = node_matrix(table.degree)
    p, q, d = table.coef.shape
    coef = np.empty((2 * p, q, d))
    for half, shift in ((0, -1.0), (1, 1.0)):  # s = (s' -+ 1) / 2 on the two halves
        m = to_mono @ np.vander(0.5 * (s + shift), d)  # coefficients -> the half's
        coef[half::2] = (table.coef.reshape(p * q, d) @ m.T).reshape(p, q, d)
    return TorsionalTable(br, table.degree, coef, table.period, dict(table.max_error))


def _fit(to_mono: FloatArray, vals: FloatArray) -> FloatArray:
    """Coefficients (pieces, 5, degree + 1) from values (5, pieces, nodes) at the nodes."""
    q, p, n = vals.shape
    flat = np.ascontiguousarray(vals).reshape(q * p, n) @ to_mono.T  # one matrix product
    return np.ascontiguousarray(flat.reshape(q, p, -1).transpose(1, 0, 2))


def _at(coef: FloatArray, vander: FloatArray) -> FloatArray:
    """The polynomials ``coef`` (pieces, 5, degree + 1) at the points of ``vander`` on every
    piece: (5, pieces x points)."""
    p, q, d = coef.shape
    flat = coef.reshape(p * q, d) @ vander.T  # one matrix product
    return np.ascontiguousarray(flat.reshape(p, q, -1).transpose(1, 0, 2)).reshape(q, -1)


def _line_table(model: Any, br: FloatArray, chk: FloatArray, exact: FloatArray,
                scale: FloatArray) -> TorsionalTable:
    """The contact-line form: Fourier series of the kinematics over the hunting period, the
    largest cuts of :data:`FOURIER_CUTS` that meet :data:`TABLE_ERROR` on the check points.

    Raises
    ------
    InputError
        No cut meets the table error.
    """
    fm = model.mesh_frequency
    period = int(round(br[-1]))
    lay = model._layout
    n = period * FOURIER_SAMPLES
    p = np.arange(n) * (period / n)
    kin = model.mesh.kinematics(p / fm)
    samples = np.array([np.asarray(getattr(kin, q), dtype=float) for q in KINEMATICS])
    samples[1] -= p * lay.pitch
    spec = np.fft.rfft(samples, axis=1)[:, : n // 2] / n  # no Nyquist term
    weight = np.where(np.arange(spec.shape[1]) == 0, 1.0, 2.0)
    full = np.stack([weight * spec.real, -weight * spec.imag], axis=-1)  # (7, n/2, 2)
    amp = np.hypot(full[..., 0], full[..., 1]) / scale[0]
    # e_ecc alone makes e and de/dp; the positions alone make k, phi1 and phi2: a cut each
    groups = ((np.arange(7) == 0, slice(0, 2)), (np.arange(7) > 0, slice(2, 5)))
    chosen: list[float | None] = [None, None]
    err = np.full(5, np.inf)
    for cut in FOURIER_CUTS:
        trial = [c if c is not None else cut for c in chosen]
        lines = _line_series(full, amp, trial, groups, period, lay, model)
        err_c = np.max(np.abs(lines.evaluate(chk) - exact), axis=1) / scale
        for g, (_, out) in enumerate(groups):
            if chosen[g] is None and np.all(err_c[out] <= TABLE_ERROR):
                chosen[g] = cut
                err[out] = err_c[out]
        if all(c is not None for c in chosen):
            lines = _line_series(full, amp, [float(c) for c in chosen],  # type: ignore[arg-type]
                                 groups, period, lay, model)
            return TorsionalTable(br, 0, np.zeros((br.size - 1, 5, 0)), period,
                                  {q: float(e) for q, e in zip(QUANTITIES, err, strict=True)},
                                  lines)
    raise InputError(f"native FMU table: no Fourier cut down to {FOURIER_CUTS[-1]:g} W/k_m "
                     f"reaches the table error {TABLE_ERROR:g} (reached "
                     f"{float(np.max(err_c)):.3g})")


def _line_series(full: FloatArray, amp: FloatArray, cuts: list[float],
                 groups: tuple[tuple[Any, slice], ...], period: int, lay: LineLayout,
                 model: Any) -> LineKinematics:
    """The series of ``full`` (7, n, 2) without the terms below each group's cut (W/k_m)."""
    keep = np.zeros(amp.shape, dtype=bool)
    for cut, (rows, _) in zip(cuts, groups, strict=True):
        keep[rows] = amp[rows] >= cut
    used = np.nonzero(np.any(keep, axis=0))[0]
    top = int(used[-1]) if used.size else 0
    fourier = np.where(keep[..., None], full, 0.0)[:, : top + 1].transpose(1, 0, 2)
    return LineKinematics(np.ascontiguousarray(fourier), period, lay,
                          float(model.stiffness.per_length), model.friction)
