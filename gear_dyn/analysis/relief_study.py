"""The relief design study: loaded contact of every design over a torque range and, optionally,
its dynamic consequence over a speed range (one call, :func:`relief_study`).

The static part is the slice loaded contact of each design
(:func:`gear_dyn.modification.analysis.slice_cases`). The dynamic part builds each design's
single-DOF model once at the chosen torque (:func:`gear_dyn.models.relief.slice_sdof`: the
loaded contact does not depend on speed) and sweeps it with the one sweep driver
(:func:`gear_dyn.analysis.sweep.sweep`) over its speed family
(:func:`gear_dyn.analysis.continuation.family.sdof_family`: only f_m changes with speed,
:func:`gear_dyn.models.base.at_speed`): the model is linear and mesh-periodic, so each
speed is one periodic-orbit solve (the monodromy matrix), not a rebuilt loaded contact and a
transient run.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gear_dyn.analysis.continuation.family import sdof_family
from gear_dyn.analysis.sweep import sweep
from gear_dyn.errors import InputError, check_range
from gear_dyn.geometry import GearPair, check_speed
from gear_dyn.models.relief import slice_sdof
from gear_dyn.modification.analysis import ReliefDynamics, ReliefStudy, slice_cases
from gear_dyn.modification.lead import FlankModification
from gear_dyn.modification.relief import ProfileModification
from gear_dyn.modification.slice_contact import SliceOptions
from gear_dyn.solvers import SolverSettings

FloatArray = NDArray[np.float64]


def relief_study(pair: GearPair, torques: ArrayLike,
                 designs: Mapping[str, ProfileModification | None],
                 lead: FlankModification | None = None,
                 pair_stiffness: Callable[[FloatArray], FloatArray] | None = None,
                 options: SliceOptions | None = None, *,
                 speeds: ArrayLike | None = None, torque: float | None = None,
                 damping_ratio: float = 0.06, inertias: tuple[float, float] | None = None,
                 settings: SolverSettings | None = None) -> ReliefStudy:
    """PPTE and peak contact pressure of relief designs over a torque range, the best one, and
    (with ``speeds``) each design's peak dynamic mesh force and p-p DTE over a speed range.

    Parameters
    ----------
    pair : GearPair
        Spur or helical pair.
    torques : array_like
        Pinion torques in N m (each > 0).
    designs : mapping
        Name -> tip reliefs (None: unmodified), e.g.
        :func:`~gear_dyn.modification.analysis.rule_modifications` (the published rules at one
        torque) or the user's own amounts.
    lead : FlankModification or None
        Lead modifications and misalignment applied to every design.
    pair_stiffness : callable or None
        Unmodified single-pair stiffness ``K(s)`` in N/m (None: potential energy).
    options : SliceOptions or None
    speeds : array_like or None
        Pinion speeds in rad/s (each > 0) of the dynamic part; None (default): no dynamics.
    torque : float or None
        Pinion torque in N m of the dynamic part (None: the ladder's largest torque).
    damping_ratio : float
        Mesh damping ratio xi of the single-DOF model.
    inertias : (float, float) or None
        (I1, I2) in kg m^2; None uses solid blanks.
    settings : SolverSettings or None
        Solver settings of the sweep (None: the sweep's defaults).

    Returns
    -------
    ReliefStudy
        ``dynamics`` set when ``speeds`` is given.

    Raises
    ------
    InputError
        No designs, torques or speeds not positive, reliefs the pair cannot take.

    Examples
    --------
    >>> import math
    >>> from gear_dyn.geometry import GearPair
    >>> from gear_dyn.modification.analysis import rule_modifications
    >>> p = GearPair(23, 79, 6e-3, math.radians(20), 70e-3, math.radians(20), x1=0.3, x2=-0.1)
    >>> study = relief_study(p, [500.0, 2000.0], rule_modifications(p, 2000.0))
    >>> study.best in study.names
    True
    """
    if not designs:
        raise InputError("relief study: no designs given (give at least one, e.g. "
                         "rule_modifications(pair, torque))")
    t = np.atleast_1d(np.asarray(torques, dtype=float)).ravel()
    study = ReliefStudy(t, slice_cases(pair, t, designs, lead, pair_stiffness, options))
    if speeds is None:
        return study
    sp = np.atleast_1d(np.asarray(speeds, dtype=float)).ravel()
    if sp.size < 1:
        raise InputError("relief study: speeds is empty (give at least one speed in rad/s)")
    for s in (sp.min(), sp.max()):
        check_speed(float(s), "speeds")
    t_dyn = float(t.max()) if torque is None else float(torque)
    check_range("torque", t_dyn, "N m", low=0.0, low_open=True)
    peak, ptp, status = [], [], []
    for case in study.cases.values():
        model, _ = slice_sdof(pair, float(sp[0]), t_dyn, case.modification, pair_stiffness,
                              damping_ratio, inertias, options)
        family = sdof_family(model, "speed", teeth=pair.z1)  # the design at any speed
        curve = sweep(family, sp, settings=settings).curves[0]
        peak.append(curve.peak_force_ratio)
        ptp.append(curve.ptp_dte)
        status.append(tuple(str(v) for v in curve.status))
        speed = curve.speed
    dyn = ReliefDynamics(t_dyn, np.asarray(speed, dtype=float), tuple(study.names),
                         np.array(peak), np.array(ptp), tuple(status))
    return replace(study, dynamics=dyn)
