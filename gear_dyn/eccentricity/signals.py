"""Excitation signals of an eccentric pair (Liu et al. 2017) on a uniform grid: driven speed,
contact-line length, friction.

The grid spans whole hunting periods (``z2 / gcd(z1, z2)`` pinion turns, after which both gears
are back where they started), so every shaft, mesh and sideband line of the signals falls exactly
on a bin of the spectrum.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from gear_dyn.eccentricity.contact_lines import LineLayout, contact_lines
from gear_dyn.eccentricity.friction import friction_factors
from gear_dyn.eccentricity.kinematics import EccentricMesh
from gear_dyn.errors import check_range

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class ExcitationSignals:
    """The excitations of a pair at constant input speed and constant normal load.

    Attributes
    ----------
    t : ndarray
        Times in s (uniform, whole hunting periods, end excluded).
    w2 : ndarray
        Driven speed in rad/s (eq. 12).
    contact_length : ndarray
        Total contact-line length L(t) in m (eq. 17).
    friction_force : ndarray or None
        Friction force F_f in N (eq. 23; positive beyond the pitch line), None without friction.
    friction_torque_pinion, friction_torque_gear : ndarray or None
        Friction torques in N m on pinion and gear (eq. 27; positive in each gear's sense of
        rotation), None without friction.
    """

    t: FloatArray
    w2: FloatArray
    contact_length: FloatArray
    friction_force: FloatArray | None
    friction_torque_pinion: FloatArray | None
    friction_torque_gear: FloatArray | None


def excitation_signals(mesh: EccentricMesh, normal_load: float, friction: float | None = None,
                       periods: int = 1, samples_per_mesh: int = 64) -> ExcitationSignals:
    """The excitations of an eccentric pair over ``periods`` hunting periods.

    Parameters
    ----------
    mesh : EccentricMesh
    normal_load : float
        Total mesh force F in N (>= 0), spread uniformly on the contact lines (eq. 18).
    friction : float or None
        Mean friction coefficient mu (0..1); None skips the friction signals.
    periods : int
        Number of hunting periods (1..100).
    samples_per_mesh : int
        Samples per mesh period (8..4096).

    Raises
    ------
    InputError
        Values out of range, or more than 5e6 samples.
    """
    check_range("normal_load", normal_load, "N", low=0.0, high=1e9)
    check_range("periods", periods, "hunting periods", low=1, high=100)
    check_range("samples_per_mesh", samples_per_mesh, "", low=8, high=4096)
    span = periods * mesh.hunting_period
    n = int(round(span * mesh.mesh_frequency)) * int(samples_per_mesh)
    check_range("samples", n, "", high=5e6)
    t = np.arange(n, dtype=np.float64) * (span / n)
    kin = mesh.kinematics(t)
    layout = LineLayout.of(mesh)
    length = np.asarray(contact_lines(layout, kin).total, dtype=float)
    ff = tp = tg = None
    if friction is not None:
        fac = friction_factors(layout, kin, friction)
        ff = normal_load * np.asarray(fac.force, dtype=float)
        tp = normal_load * np.asarray(fac.torque_pinion, dtype=float)
        tg = normal_load * np.asarray(fac.torque_gear, dtype=float)
    return ExcitationSignals(t=t, w2=np.asarray(kin.w2, dtype=float), contact_length=length,
                             friction_force=ff, friction_torque_pinion=tp,
                             friction_torque_gear=tg)
