"""Name the peaks of a gear spectrum: shaft frequencies, mesh harmonics and their sidebands.

Every line of a gear pair's spectrum is a combination ``n f_m + a f1 + b f2`` of the mesh
frequency ``f_m = z1 f1`` and the shaft frequencies ``f1`` (pinion) and ``f2 = f1 z1 / z2``
(gear). A peak gets the simplest combination within the frequency tolerance: the smallest
``|a| + |b|``, then the smallest ``n``. Labels read ``f1``, ``2f2``, ``fm``, ``2fm``,
``fm-f1``, ``fm+2f2``, ``3fm-f1+f2`` ...; kinds are ``shaft`` (n = 0, one shaft),
``combination`` (n = 0, both shafts), ``mesh`` (a = b = 0) and ``sideband``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from gear_dyn.analysis.spectrum import find_peaks
from gear_dyn.errors import check_range


@dataclass(frozen=True)
class Basis:
    """The frequencies every line is built from.

    Parameters
    ----------
    mesh : float
        Mesh frequency f_m in Hz (> 0).
    shaft1, shaft2 : float
        Pinion and gear shaft frequencies f1, f2 in Hz (> 0).
    """

    mesh: float
    shaft1: float
    shaft2: float

    def __post_init__(self) -> None:
        check_range("mesh frequency", self.mesh, "Hz", low=0.0, low_open=True)
        check_range("pinion shaft frequency", self.shaft1, "Hz", low=0.0, low_open=True)
        check_range("gear shaft frequency", self.shaft2, "Hz", low=0.0, low_open=True)

    @classmethod
    def of_pair(cls, z1: int, z2: int, speed: float) -> Basis:
        """Basis of a pair with pinion speed ``speed`` in rad/s."""
        f1 = speed / (2 * math.pi)
        return cls(mesh=z1 * f1, shaft1=f1, shaft2=f1 * z1 / z2)


@dataclass(frozen=True)
class Label:
    """A named line ``n f_m + a f1 + b f2``."""

    name: str
    kind: str
    n: int
    a: int
    b: int
    frequency: float


def _name(n: int, a: int, b: int) -> str:
    terms = [(n, "fm"), (a, "f1"), (b, "f2")]
    terms.sort(key=lambda c: c[0] < 0)  # a positive term first: "4f2-f1", not "-f1+4f2"
    out = ""
    for coef, sym in terms:
        if coef != 0:
            sign = "-" if coef < 0 else ("+" if out else "")
            out += f"{sign}{'' if abs(coef) == 1 else abs(coef)}{sym}"
    return out or "0"


def label_frequency(freq: float, basis: Basis, tol: float, max_mesh: int = 10000,
                    max_order: int = 6) -> Label | None:
    """The simplest line within ``tol`` Hz of ``freq``, or None.

    Parameters
    ----------
    freq : float
        Frequency in Hz.
    basis : Basis
    tol : float
        Largest distance in Hz (typically the spectral resolution).
    max_mesh : int
        Highest mesh harmonic n considered.
    max_order : int
        Largest ``|a|`` and ``|b|`` considered.
    """
    best: tuple[int, int, float, Label] | None = None
    n_hi = min(max_mesh, int(freq / basis.mesh + 1.5))
    for n in range(0, n_hi + 1):
        for a in range(-max_order, max_order + 1):
            base = n * basis.mesh + a * basis.shaft1
            # b from the residual: only the nearest two values can fall within tol
            b0 = (freq - base) / basis.shaft2
            for b in {math.floor(b0), math.ceil(b0)}:
                if abs(b) > max_order:
                    continue
                f = base + b * basis.shaft2
                err = abs(f - freq)
                if f <= 0 or err > tol:
                    continue
                cost = abs(a) + abs(b)
                key = (cost, n, err)
                if best is None or key < best[:3]:
                    if a == 0 and b == 0:
                        kind = "mesh"
                    elif n == 0:
                        kind = "shaft" if a == 0 or b == 0 else "combination"
                    else:
                        kind = "sideband"
                    best = (cost, n, err, Label(_name(n, a, b), kind, n, a, b, f))
    return best[3] if best is not None else None


def labelled_peaks(f: ArrayLike, amp: ArrayLike, basis: Basis, n: int = 30,
                   rel_height: float = 1e-4, min_freq: float | None = None) -> list[dict[str, Any]]:
    """The ``n`` largest peaks of a spectrum with their names.

    Returns
    -------
    list of dict
        ``frequency_hz`` (refined peak), ``amplitude``, ``label`` (or None), ``kind``,
        ``line_hz`` (the exact combination frequency), sorted by decreasing amplitude.
    """
    f = np.asarray(f, dtype=float)
    a = np.asarray(amp, dtype=float)
    df = float(f[1] - f[0])
    lo = 0.5 * df if min_freq is None else min_freq
    out = []
    for freq, height in find_peaks(f, a, n=n, min_freq=lo, rel_height=rel_height):
        lab = label_frequency(freq, basis, tol=0.75 * df)
        out.append({
            "frequency_hz": freq, "amplitude": height,
            "label": lab.name if lab else None, "kind": lab.kind if lab else None,
            "line_hz": lab.frequency if lab else None,
        })
    return out
