"""Lead modifications and mesh misalignment: separations across the face width.

Every quantity here is a gap (m) added to the rigid-body separation of the flanks, measured along
the transverse line of action like the tip relief amounts and the transmission error, as a
function of the face position ``y`` (m from the front face, 0 .. B). ``y_c = y - B / 2`` is the
distance from mid-face.

- crowning ``C_b`` (parabolic, ISO 21771 ``C_b``): ``C_b (2 y_c / B)^2``, ``C_b`` at both ends;
- end relief ``C_e`` over ``L_e`` at each end (linear): ``C_e (1 - d / L_e)`` for a distance
  ``d < L_e`` from the nearer end;
- helix slope ``f_H`` (ISO 21771 helix slope modification ``C_Hb``): ``f_H y_c / B``, a linear
  gap that grows by ``f_H`` from the front to the rear face (negative: towards the front);
- misalignment (ISO 6336-1, ISO/TR 10064-3): the mesh misalignment ``f_ma`` (already in the plane
  of action) and the axis-parallelism deviations ``f_Sigma_beta`` (out of plane) and
  ``f_Sigma_delta`` (in plane), each given over the face width, projected onto the line of
  action: ``f_eq = f_ma + f_Sigma_beta cos a_wt + f_Sigma_delta sin a_wt`` and the gap
  ``f_eq y_c / B``.

docs/modification.md, "Lead modifications and misalignment", states the conventions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gear_dyn.errors import InputError, check_range
from gear_dyn.geometry import GearPair
from gear_dyn.modification.relief import ProfileModification

FloatArray = NDArray[np.float64]

_MAX_AMOUNT = 1e-3  # m: a lead modification or misalignment above 1 mm is a typo


@dataclass(frozen=True)
class LeadModification:
    """Lead (face-width) modification of one gear, as gaps along the line of action.

    Parameters
    ----------
    crowning : float
        Crowning height C_b in m at each face end relative to mid-face (0 .. 1 mm).
    end_relief : float
        End relief amount C_e in m at each face end (0 .. 1 mm).
    end_relief_length : float
        End relief length L_e in m from each end (0 .. B/2, checked against the pair in
        :meth:`separation`); needed when ``end_relief > 0``.
    helix_slope : float
        Helix slope modification f_H in m: the gap grows linearly by f_H from the front face
        (y = 0) to the rear face (y = B); signed, -1 .. 1 mm.

    Raises
    ------
    InputError
        Values out of range, an end relief without a length.
    """

    crowning: float = 0.0
    end_relief: float = 0.0
    end_relief_length: float = 0.0
    helix_slope: float = 0.0

    def __post_init__(self) -> None:
        check_range("crowning", self.crowning, "m", low=0.0, high=_MAX_AMOUNT)
        check_range("end_relief", self.end_relief, "m", low=0.0, high=_MAX_AMOUNT)
        check_range("end_relief_length", self.end_relief_length, "m", low=0.0, high=10.0)
        check_range("helix_slope", self.helix_slope, "m", low=-_MAX_AMOUNT, high=_MAX_AMOUNT)
        if self.end_relief > 0.0 and self.end_relief_length == 0.0:
            raise InputError(f"end_relief = {self.end_relief * 1e6:.6g} um needs "
                             "end_relief_length > 0 m (from each face end)")

    @property
    def is_zero(self) -> bool:
        """True if the modification removes no material."""
        return self.crowning == 0.0 and self.end_relief == 0.0 and self.helix_slope == 0.0

    def separation(self, face_width: float, y: ArrayLike) -> FloatArray:
        """Gap in m at face position ``y`` (m from the front face) of a face ``face_width`` wide.

        Raises
        ------
        InputError
            End relief longer than half the face width.
        """
        b = float(face_width)
        if self.end_relief > 0.0:
            check_range("end_relief_length", self.end_relief_length, "m", low=0.0,
                        high=0.5 * b, low_open=True)
        yy = np.asarray(y, dtype=float)
        yc = yy - 0.5 * b
        gap = self.crowning * (2.0 * yc / b) ** 2 + self.helix_slope * yc / b
        if self.end_relief > 0.0:
            d = np.minimum(yy, b - yy)
            gap = gap + self.end_relief * np.clip(1.0 - d / self.end_relief_length, 0.0, 1.0)
        return np.asarray(gap, dtype=float)


@dataclass(frozen=True)
class Misalignment:
    """Mesh misalignment of a pair, each value over the face width (m).

    Parameters
    ----------
    f_ma : float
        Mesh misalignment in the plane of action (ISO 6336-1 ``f_ma``), signed, ``abs(f) <= 1 mm``.
    f_sigma_beta : float
        Out-of-plane axis deviation ``f_Sigma_beta`` over the face width (ISO/TR 10064-3),
        signed; it acts on the line of action with ``cos a_wt``.
    f_sigma_delta : float
        In-plane axis deviation ``f_Sigma_delta`` over the face width, signed; acts with
        ``sin a_wt``.

    Raises
    ------
    InputError
        Values out of range.
    """

    f_ma: float = 0.0
    f_sigma_beta: float = 0.0
    f_sigma_delta: float = 0.0

    def __post_init__(self) -> None:
        for name in ("f_ma", "f_sigma_beta", "f_sigma_delta"):
            check_range(name, getattr(self, name), "m", low=-_MAX_AMOUNT, high=_MAX_AMOUNT)

    def equivalent(self, pair: GearPair) -> float:
        """Equivalent misalignment along the line of action over the face width, m."""
        a = pair.alpha_wt
        return self.f_ma + self.f_sigma_beta * math.cos(a) + self.f_sigma_delta * math.sin(a)

    def separation(self, pair: GearPair, y: ArrayLike) -> FloatArray:
        """Gap in m at face position ``y`` (m from the front face): ``f_eq (y - B/2) / B``."""
        b = pair.face_width
        return self.equivalent(pair) * (np.asarray(y, dtype=float) - 0.5 * b) / b


@dataclass(frozen=True)
class FlankModification:
    """Everything that opens the unloaded gap of a pair: profile, lead, misalignment.

    Parameters
    ----------
    profile : ProfileModification or None
        Tip reliefs (:class:`~gear_dyn.modification.relief.ProfileModification`).
    lead_pinion, lead_gear : LeadModification or None
        Lead modifications of each gear (their gaps add).
    misalignment : Misalignment or None
    """

    profile: ProfileModification | None = None
    lead_pinion: LeadModification | None = None
    lead_gear: LeadModification | None = None
    misalignment: Misalignment | None = None

    def face_separation(self, pair: GearPair, y: ArrayLike) -> FloatArray:
        """Gap (m) of the lead modifications and misalignment at face position ``y`` (m)."""
        yy = np.asarray(y, dtype=float)
        gap = np.zeros_like(yy)
        for lead in (self.lead_pinion, self.lead_gear):
            if lead is not None and not lead.is_zero:
                gap = gap + lead.separation(pair.face_width, yy)
        if self.misalignment is not None:
            gap = gap + self.misalignment.separation(pair, yy)
        return gap
