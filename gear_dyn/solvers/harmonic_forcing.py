"""The harmonic particular solution of a contact state forced by a static transmission error.

With ``u = x - e(t)`` the single-DOF model ``m x'' + c (x' - e') + k f(x - e) = W`` becomes
``m u'' + c u' + k f(u) = W - m e''(t)``: the dead-zone oscillator forced by ``-e''``. For a
transmission error ``e(p) = e0 + sum_n C_n cos(2 pi n p) + S_n sin(2 pi n p)`` of the mesh phase
``p = f_m t + p0`` the forcing is ``-e'' = sum_n W_n^2 (C_n cos th_n + S_n sin th_n)`` with
``W_n = 2 pi n f_m`` and ``th_n = 2 pi n p``. In a contact state with stiffness ``k``
(``w2 = k/m``, 0 in the gap) and ``a = c/m``, one harmonic ``g cos th + h sin th`` has the
particular solution ``A cos th + B sin th`` with

    (w2 - W^2) A + a W B = g,    -a W A + (w2 - W^2) B = h,

solvable whenever ``D = (w2 - W^2)^2 + (a W)^2 > 0`` (always in the gap, and with damping; an
undamped resonance has no periodic particular solution). The full solution of a piece is this
particular part plus the homogeneous-and-load closed form of
:func:`gear_dyn.solvers.contact_exact.flow`. Zero harmonics (no transmission error) give the
zero particular solution.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.excitation import HarmonicSignal

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class Forcing:
    """The forcing ``-e''(t)`` of a harmonic transmission error, harmonic by harmonic.

    Attributes
    ----------
    fm : float
        Mesh frequency f_m in Hz.
    p0 : float
        Mesh phase at t = 0 in cycles.
    n : ndarray of float
        Harmonic numbers with a nonzero coefficient.
    fc, fs : ndarray
        Forcing coefficients ``W_n^2 C_n`` and ``W_n^2 S_n`` in m/s^2.
    """

    fm: float
    p0: float
    n: FloatArray
    fc: FloatArray
    fs: FloatArray

    @classmethod
    def of(cls, model: Any) -> Forcing:
        """The forcing of ``model``'s transmission error (none: zero harmonics).

        ``model`` has ``mesh_frequency``, ``phase0`` and ``transmission_error`` (None or a
        :class:`~gear_dyn.excitation.HarmonicSignal`).
        """
        te = getattr(model, "transmission_error", None)
        fm, p0 = float(model.mesh_frequency), float(getattr(model, "phase0", 0.0))
        if not isinstance(te, HarmonicSignal):
            empty = np.zeros(0)
            return cls(fm, p0, empty, empty, empty)
        if te.period != 1:  # the phase is reduced to one mesh cycle below
            raise ValueError(f"harmonic forcing: a transmission error of period {te.period} "
                             "mesh cycles; this closed form takes mesh harmonics only")
        n = np.arange(1, te.cos.size + 1, dtype=float)
        keep = (te.cos != 0.0) | (te.sin != 0.0)
        om2 = (2 * math.pi * n[keep] * fm) ** 2
        return cls(fm, p0, n[keep], om2 * te.cos[keep], om2 * te.sin[keep])

    @property
    def top_frequency(self) -> float:
        """Largest forcing frequency in rad/s (0 without harmonics)."""
        return float(2 * math.pi * self.fm * self.n[-1]) if self.n.size else 0.0

    def value(self, t: float) -> float:
        """``-e''(t)`` in m/s^2."""
        p = math.fmod(self.fm * t + self.p0, 1.0)
        return sum(g * math.cos(2 * math.pi * k * p) + h * math.sin(2 * math.pi * k * p)
                   for k, g, h in zip(self.n.tolist(), self.fc.tolist(), self.fs.tolist(),
                                      strict=True))

    def particular(self, w2: float, a: float) -> Particular:
        """The particular solution in a state with ``w2 = k/m`` (1/s^2) and ``a = c/m`` (1/s).

        Raises
        ------
        ZeroDivisionError
            An undamped state at exact resonance with a harmonic (``D = 0``); the callers
            refuse undamped models with a transmission error first.
        """
        if not self.n.size:
            return Particular(self, self.n, self.n, self.n)
        om = 2 * math.pi * self.n * self.fm
        det = (w2 - om**2) ** 2 + (a * om) ** 2
        if np.any(det == 0.0):
            raise ZeroDivisionError("undamped resonance with a transmission-error harmonic")
        ca = ((w2 - om**2) * self.fc - a * om * self.fs) / det
        cb = (a * om * self.fc + (w2 - om**2) * self.fs) / det
        return Particular(self, om, ca, cb)

    def particular_rate(self, w2: float, a: float) -> tuple[FloatArray, FloatArray]:
        """``d A_n / d f_m, d B_n / d f_m`` (m/Hz) of :meth:`particular` at fixed ``w2, a``.

        With ``P = w2 - W^2``, ``Q = a W``, ``D = P^2 + Q^2`` the solution of the module's 2 x 2
        system is ``A = (P g - Q h) / D``, ``B = (Q g + P h) / D``; its forcing ``g = W^2 C_n``,
        ``h = W^2 S_n`` and ``W = 2 pi n f_m`` all depend on the mesh frequency
        (``dW/df_m = 2 pi n``, ``dP = -2 W dW``, ``dQ = a dW``, ``dg = 2 g dW / W``), so by the
        quotient rule ``dA = (dP g + P dg - dQ h - Q dh) / D - A dD / D`` and
        ``dB = (dQ g + Q dg + dP h + P dh) / D - B dD / D``, ``dD = 2 (P dP + Q dQ)``.
        Empty arrays without harmonics.
        """
        part = self.particular(w2, a)
        if not self.n.size:
            return part.ca, part.cb
        om = part.om
        dom = 2 * math.pi * self.n
        p, q = w2 - om**2, a * om
        dp, dq = -2 * om * dom, a * dom
        dg, dh = 2 * self.fc * dom / om, 2 * self.fs * dom / om
        det = p**2 + q**2
        dd = 2 * (p * dp + q * dq)
        da = (dp * self.fc + p * dg - dq * self.fs - q * dh - part.ca * dd) / det
        db = (dq * self.fc + q * dg + dp * self.fs + p * dh - part.cb * dd) / det
        return da, db


class Particular:
    """``u_p(t) = sum_n A_n cos th_n + B_n sin th_n`` of one contact state (m, m/s).

    ``amplitude`` bounds ``|u_p|`` and ``curvature`` bounds ``|u_p''|`` for all t (sums of the
    harmonics' amplitudes ``hypot(A_n, B_n)``, times ``W_n^2`` for the curvature).
    """

    def __init__(self, forcing: Forcing, om: FloatArray, ca: FloatArray, cb: FloatArray
                 ) -> None:
        self.forcing = forcing
        self.fm, self.p0, self.n = forcing.fm, forcing.p0, forcing.n
        self.om, self.ca, self.cb = om, ca, cb
        #: False without harmonics: u_p = 0 and the pieces skip it (the unforced hot path)
        self.active = om.size > 0
        self.amplitude = self.curvature = 0.0
        self._terms: list[tuple[float, float, float, float]] = []
        if self.active:
            amp = np.hypot(ca, cb)
            self.amplitude = float(np.sum(amp))
            self.curvature = float(np.sum(amp * om**2))
            self._terms = list(zip((2 * math.pi * self.n).tolist(), om.tolist(), ca.tolist(),
                                   cb.tolist(), strict=True))

    def at(self, t: FloatArray) -> tuple[FloatArray, FloatArray]:
        """``u_p(t), u_p'(t)`` at times ``t`` in s (vectorised)."""
        t = np.asarray(t, dtype=float)
        if not self._terms:
            return np.zeros_like(t), np.zeros_like(t)
        p = np.mod(self.fm * t + self.p0, 1.0)
        th = 2 * math.pi * p[..., None] * self.n
        cs, sn = np.cos(th), np.sin(th)
        return cs @ self.ca + sn @ self.cb, (cs @ (self.cb * self.om) - sn @ (self.ca * self.om))

    def at_scalar(self, t: float) -> tuple[float, float]:
        """:meth:`at` at one time with Python floats (the root finders' inner loop)."""
        if not self._terms:
            return 0.0, 0.0
        p = math.fmod(self.fm * t + self.p0, 1.0)
        u = v = 0.0
        for tn, om, ca, cb in self._terms:
            cs, sn = math.cos(tn * p), math.sin(tn * p)
            u += ca * cs + cb * sn
            v += om * (cb * cs - ca * sn)
        return u, v
