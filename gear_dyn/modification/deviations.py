"""Manufacturing deviations of a gear pair as a static transmission error (shaft orders).

Tolerances (ISO 1328-1:2013, clause 5.2, eqs. 5-12, unrounded; the standard rounds its tables):
the grade-5 value of each tolerance times the grade step ``sqrt(2)^(A - 5)``, with ``d`` the
reference diameter, ``m_n`` the normal module and ``b`` the face width in mm, the results in um:

    f_pT   = 0.001 d + 0.4 m_n + 5                        single pitch
    F_pT   = 0.002 d + 0.55 sqrt(d) + 0.7 m_n + 12        cumulative pitch (total)
    f_HaT  = 0.4 m_n + 0.001 d + 4                        profile slope
    f_faT  = 0.55 m_n + 5                                 profile form
    F_aT   = sqrt(f_HaT^2 + f_faT^2)                      profile total
    f_HbT  = 0.05 sqrt(d) + 0.35 sqrt(b) + 4              helix slope
    f_fbT  = 0.07 sqrt(d) + 0.45 sqrt(b) + 4              helix form
    F_bT   = sqrt(f_HbT^2 + f_fbT^2)                      helix total

for grades A = 1..11 (the standard's validity: 0.5 <= m_n <= 70 mm, 5 <= d <= 15 000 mm,
4 <= b <= 1 200 mm; the formulas are applied as they are outside).

Excitation (docs/tolerance.md): the tooth of index ``i`` of a gear with ``z`` teeth stands
``F_p,i`` (its cumulative pitch deviation, on the reference circle) from its nominal place;
along the line of action that is ``F_p,i cos a_t``. The tooth pair of mesh cycle ``n`` is pinion
tooth ``n mod z1`` and gear tooth ``n mod z2``; its transmission error is the sum of both
teeth's deviations. As a function of the mesh phase the sequence of one gear is taken as its
trigonometric interpolant: the one signal of period ``z`` mesh cycles, made of that gear's shaft
orders ``1 .. z/2``, that passes through every tooth's value at its mesh cycle (finer detail
within a mesh cycle, the steps between teeth, is load sharing's business and is left out). The
pinion's part has period ``z1`` mesh cycles, the gear's ``z2``, so the whole repeats over the
hunting period ``lcm(z1, z2)``. F_p is the once-per-revolution component: a sine of range
``F_p`` over the revolution (the signature of a runout). The profile form deviation gives a
mesh-order harmonic: each gear's form deviation of range ``f_fa`` becomes a first mesh harmonic
of amplitude ``f_fa / 2`` (an upper bound: the load sharing of a second pair and the form's
finer content are left out). The helix deviation F_beta is derived and reported, but it
excites no single-DOF model: it is a misalignment of the contact line, which ISO 6336-1 books
in the face load factor K_Hbeta, not a transmission error.

Patterns: ``sine`` (deterministic: the cumulative pitch a sine of range F_p, the profile
harmonics of both gears in phase at amplitude f_fa/2); ``random`` (a sample within the grade:
single pitch deviations uniform in +-f_pt, closed over the revolution, plus a once-per-revolution
component of uniform random amplitude up to F_p/2 and phase, the whole scaled down where needed
so that every single pitch deviation stays within +-f_pt and the cumulative range within F_p;
profile harmonics of uniform amplitude up to f_fa/2 and uniform phase), ``none``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gear_dyn.errors import InputError, check_range
from gear_dyn.excitation import HarmonicSignal, SumSignal
from gear_dyn.geometry import GearPair

FloatArray = NDArray[np.float64]
UM = 1e-6
#: deviation patterns
PATTERNS = ("random", "sine", "none")


def grade_step(grade: int) -> float:
    """ISO 1328-1:2013 step between grades: ``sqrt(2)^(A - 5)`` for grade A in 1..11."""
    a = check_range("accuracy_grade", grade, "", low=1, high=11)
    if int(a) != a:
        raise InputError(f"accuracy_grade = {grade!r}: expected a whole number 1..11")
    return math.sqrt(2.0) ** (int(a) - 5)


@dataclass(frozen=True)
class Tolerances:
    """Tolerances of one gear in m (ISO 1328-1:2013 symbols without the T).

    Attributes
    ----------
    f_pt : float
        Single pitch tolerance (m).
    F_p : float
        Cumulative (total) pitch tolerance (m).
    f_falpha : float
        Profile form tolerance (m).
    F_beta : float
        Helix total tolerance (m).
    """

    f_pt: float
    F_p: float  # noqa: N815 (the standard's symbol)
    f_falpha: float
    F_beta: float  # noqa: N815

    def __post_init__(self) -> None:
        for name in ("f_pt", "F_p", "f_falpha", "F_beta"):
            check_range(name, getattr(self, name), "m", low=0.0, high=1e-2)


def iso1328_tolerances(grade: int, module: float, diameter: float, face_width: float
                       ) -> Tolerances:
    """Tolerances of a gear of ``grade`` (ISO 1328-1:2013, eqs. 5-12, unrounded; module
    docstring).

    Parameters
    ----------
    grade : int
        Flank tolerance class A, 1..11.
    module : float
        Normal module m_n in m (> 0).
    diameter : float
        Reference diameter d in m (> 0).
    face_width : float
        Face width b in m (> 0).

    Returns
    -------
    Tolerances
        In m.

    Raises
    ------
    InputError
        Grade outside 1..11 or a size <= 0.

    Examples
    --------
    >>> t = iso1328_tolerances(6, 3e-3, 120e-3, 30e-3)
    >>> round(t.f_pt * 1e6, 3), round(t.F_p * 1e6, 2)
    (8.938, 28.8)
    """
    step = grade_step(grade)
    m = check_range("module", module, "m", low=0.0, low_open=True) * 1e3
    d = check_range("diameter", diameter, "m", low=0.0, low_open=True) * 1e3
    b = check_range("face_width", face_width, "m", low=0.0, low_open=True) * 1e3
    f_pt = 0.001 * d + 0.4 * m + 5.0
    f_p = 0.002 * d + 0.55 * math.sqrt(d) + 0.7 * m + 12.0
    f_fa = 0.55 * m + 5.0
    f_hb = 0.05 * math.sqrt(d) + 0.35 * math.sqrt(b) + 4.0
    f_fb = 0.07 * math.sqrt(d) + 0.45 * math.sqrt(b) + 4.0
    return Tolerances(f_pt * step * UM, f_p * step * UM, f_fa * step * UM,
                      math.hypot(f_hb, f_fb) * step * UM)


def pair_tolerances(pair: GearPair, grade: int) -> tuple[Tolerances, Tolerances]:
    """(pinion, gear) tolerances of ``pair`` at ``grade`` (reference diameters 2 r)."""
    return tuple(iso1328_tolerances(grade, pair.module, 2 * r, pair.face_width)  # type: ignore
                 for r in (pair.r1, pair.r2))


def pitch_pattern(z: int, tol: Tolerances, pattern: str,
                  rng: np.random.Generator | None = None) -> FloatArray:
    """Cumulative pitch deviation of every tooth, ``F_p,i`` for i = 0..z-1, in m.

    Parameters
    ----------
    z : int
        Number of teeth (>= 5).
    tol : Tolerances
        The gear's tolerances (f_pt, F_p used).
    pattern : {"random", "sine", "none"}
        As in the module docstring.
    rng : numpy.random.Generator or None
        Random source of ``random`` (required there).

    Raises
    ------
    InputError
        Unknown pattern, or ``random`` without ``rng``.
    """
    i = np.arange(z)
    if pattern == "none":
        return np.zeros(z)
    if pattern == "sine":
        return 0.5 * tol.F_p * np.sin(2 * np.pi * i / z)
    if pattern != "random":
        raise InputError(f"deviations.pattern = {pattern!r}: valid choices are "
                         f"{', '.join(PATTERNS)}")
    if rng is None:
        raise InputError("pitch_pattern: pattern 'random' needs a random generator (seed)")
    single = rng.uniform(-tol.f_pt, tol.f_pt, z)
    single -= single.mean()  # the pitches of one revolution close the circle
    cum = np.cumsum(single)
    amp, ph = rng.uniform(0.0, 0.5 * tol.F_p), rng.uniform(0.0, 2 * np.pi)
    cum = cum - cum.mean() + amp * np.sin(2 * np.pi * i / z + ph)
    steps = np.abs(np.diff(np.append(cum, cum[0])))
    scale = min(1.0, tol.F_p / max(float(np.ptp(cum)), 1e-300),
                tol.f_pt / max(float(steps.max()), 1e-300))
    return cum * scale


def shaft_order_signal(values: ArrayLike, z: int) -> HarmonicSignal:
    """The trigonometric interpolant of one value per tooth, as a signal of period ``z`` mesh
    cycles: shaft orders 1..z/2, ``e(n) = values[n] - mean`` at mesh cycle n (m).

    Raises
    ------
    InputError
        ``values`` not of length ``z``, or not finite.
    """
    v = np.asarray(values, dtype=float)
    if v.shape != (z,) or not np.all(np.isfinite(v)):
        raise InputError(f"deviations: {v.size} tooth values for {z} teeth: expected {z} finite "
                         "numbers (m)")
    spec = np.fft.rfft(v)[1:]
    coef = 2.0 * spec / z
    if z % 2 == 0:  # the order z/2 (alternate teeth) appears once: half the weight
        coef[-1] *= 0.5
    return HarmonicSignal(0.0, coef.real.copy(), -coef.imag.copy(), period=z)


@dataclass(frozen=True, eq=False)
class PairDeviations:
    """One realisation of the deviations of a pair, along the line of action (m).

    Attributes
    ----------
    z1, z2 : int
        Teeth of pinion and gear.
    pitch_pinion, pitch_gear : ndarray
        Cumulative pitch deviations per tooth along the line of action (m).
    profile : complex
        First mesh harmonic of the profile form deviations (both gears), complex amplitude
        ``a - i b`` of ``a cos(2 pi p) + b sin(2 pi p)`` in m.
    """

    z1: int
    z2: int
    pitch_pinion: FloatArray
    pitch_gear: FloatArray
    profile: complex

    def signals(self) -> tuple[HarmonicSignal, HarmonicSignal, HarmonicSignal]:
        """(pinion part, gear part, mesh part): periods z1, z2 and 1 mesh cycles."""
        mesh = HarmonicSignal(0.0, np.array([self.profile.real]),
                              np.array([-self.profile.imag]))
        return (shaft_order_signal(self.pitch_pinion, self.z1),
                shaft_order_signal(self.pitch_gear, self.z2), mesh)

    def transmission_error(self) -> SumSignal:
        """The static transmission error e(p) of the deviations (m), period lcm(z1, z2)."""
        return SumSignal(self.signals())


def sample_deviations(pair: GearPair, tolerances: tuple[Tolerances, Tolerances], pattern: str,
                      seed: int | Sequence[int] | None = None) -> PairDeviations:
    """Deviations of both gears of ``pair`` within ``tolerances`` (pinion, gear), by
    ``pattern`` (module docstring); ``random`` draws from ``numpy.random.default_rng(seed)``.

    Raises
    ------
    InputError
        Unknown pattern, or ``random`` without a seed.
    """
    if pattern == "random" and seed is None:
        raise InputError("deviations.pattern = 'random' needs deviations.seed (an integer)")
    rng = np.random.default_rng(seed) if pattern == "random" else None
    ca = math.cos(pair.alpha_t)
    p1 = pitch_pattern(pair.z1, tolerances[0], pattern, rng) * ca
    p2 = pitch_pattern(pair.z2, tolerances[1], pattern, rng) * ca
    half = 0.5 * np.array([tolerances[0].f_falpha, tolerances[1].f_falpha])
    if pattern == "sine":
        prof = complex(half.sum())
    elif pattern == "random":
        assert rng is not None
        amp, ph = rng.uniform(0.0, 1.0, 2) * half, rng.uniform(0.0, 2 * np.pi, 2)
        prof = complex(np.sum(amp * np.exp(-1j * ph)))
    else:
        prof = 0j
    return PairDeviations(pair.z1, pair.z2, p1, p2, prof)


__all__ = ["PATTERNS", "PairDeviations", "Tolerances", "grade_step", "iso1328_tolerances",
           "pair_tolerances", "pitch_pattern", "sample_deviations", "shaft_order_signal"]
