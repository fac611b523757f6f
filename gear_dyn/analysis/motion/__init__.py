"""What the motion of a mesh model is, and how it changes with speed.

- :mod:`.samples`: stroboscopic (Poincare) samples, one per mesh period, from the exact
  piecewise flow where it applies (else event-located DOP853);
- :mod:`.period`: period-n detection from the samples;
- :mod:`.lyapunov`: the largest Lyapunov exponent from the tangent flow with renormalisation
  (Benettin et al. 1980), with its standard error;
- :mod:`.classify`: period-n (confirmed by shooting over n mesh periods), quasi-periodic or
  chaotic: a :class:`Motion` with a label;
- :mod:`.diagram`: the bifurcation diagram, samples against speed swept up and down.

Period-n orbits of the sweep (:mod:`gear_dyn.analysis.sweep`) are classified here; branches of
orbits and their bifurcations are in :mod:`gear_dyn.analysis.continuation`.
"""

from gear_dyn.analysis.motion.classify import (
    KINDS,
    Motion,
    classify_motion,
    classify_samples,
    confirm_period,
    find_orbit,
)
from gear_dyn.analysis.motion.diagram import (
    BifurcationDiagram,
    DiagramCurve,
    DiagramOptions,
    bifurcation_diagram,
)
from gear_dyn.analysis.motion.lyapunov import LyapunovEstimate, largest_lyapunov
from gear_dyn.analysis.motion.period import MAX_PERIOD, detect_period, repeat_errors
from gear_dyn.analysis.motion.samples import flow_periods, propagator, stroboscopic

__all__ = [
    "KINDS", "MAX_PERIOD", "BifurcationDiagram", "DiagramCurve", "DiagramOptions",
    "LyapunovEstimate", "Motion", "bifurcation_diagram", "classify_motion", "classify_samples",
    "confirm_period", "detect_period", "find_orbit", "flow_periods", "largest_lyapunov",
    "propagator", "repeat_errors", "stroboscopic",
]
