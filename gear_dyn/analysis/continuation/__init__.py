"""Continuation of periodic orbits of the single-DOF mesh model, with their bifurcations.

:func:`continue_orbits` follows a branch of period-n orbits in pinion speed or another
parameter (:func:`sdof_family`) by pseudo-arclength continuation of the shooting equations,
locates its folds, period doublings and grazing points, and switches to the period-2n branches.
docs/response.md describes the method and its tests.

Modules, one concern each: :mod:`.settings` (the knobs), :mod:`.family` (value -> model),
:mod:`.orbit` (n-period map, Liouville, contact pattern), :mod:`.shooting` (the augmented
equations, corrector, tangent), :mod:`.detect` (test functions, location), :mod:`.graze` (the
grazing test), :mod:`.arclength` (the continuation loop), :mod:`.switch` (period-doubling branch
switching), :mod:`.branch` (result objects), :mod:`.points` (a point from a converged
evaluation), :mod:`.strobe` (the orbits' stroboscopic samples: the continuation's bifurcation
diagram).
"""

from gear_dyn.analysis.continuation.arclength import continue_orbits
from gear_dyn.analysis.continuation.branch import Bifurcation, Branch, OrbitPoint
from gear_dyn.analysis.continuation.detect import fold_test, pd_test
from gear_dyn.analysis.continuation.family import PARAMETERS, SDOFFamily, sdof_family
from gear_dyn.analysis.continuation.fold_curve import SpeedTorqueFamily, fold_map
from gear_dyn.analysis.continuation.jump_map import Cusp, FoldMap, JumpRegion
from gear_dyn.analysis.continuation.orbit import liouville_residual
from gear_dyn.analysis.continuation.settings import ContinuationSettings
from gear_dyn.analysis.continuation.strobe import BranchSamples, branch_samples

__all__ = [
    "PARAMETERS", "Bifurcation", "Branch", "BranchSamples", "ContinuationSettings", "Cusp",
    "FoldMap", "JumpRegion", "SpeedTorqueFamily", "fold_map", "OrbitPoint", "SDOFFamily",
    "branch_samples", "continue_orbits", "fold_test", "liouville_residual", "pd_test",
    "sdof_family",
]
