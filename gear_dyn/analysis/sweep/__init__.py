"""Speed sweeps: dynamic factor, DTE, stability and spectra over a range of pinion speeds.

A sweep evaluates a model factory ``speed -> Model`` at many speeds (the scene layer builds one
that rebuilds the speed-dependent parts exactly as :func:`gear_dyn.scene.run_scene` does:
:func:`gear_dyn.scene.sweep.sweep_scene`). Method ``steady`` (default) solves for the periodic
steady state directly (:mod:`gear_dyn.analysis.stability`); ``transient`` integrates at every
speed as ``gear-dyn run`` does. Models with backlash are swept up and down (coexisting orbits:
the jumps of Kahraman & Singh 1990). docs/sweep.md, "How the steady state is found", "How jumps
are found" and "Parallel runs", gives the routes, the statuses and where the blocks run.
"""

from gear_dyn.analysis.sweep.driver import ModelFactory, sweep
from gear_dyn.analysis.sweep.jump import JUMP_KINDS, Jump
from gear_dyn.analysis.sweep.orbit_jumps import find_jumps
from gear_dyn.analysis.sweep.types import (
    DIRECTIONS,
    METHODS,
    RPM,
    Point,
    SweepCurve,
    SweepOptions,
    SweepResult,
    aperiodic_ranges,
    hysteresis_ranges,
    jumps,
    periodic_response,
    summarize_sweep,
    sweep_columns,
)

__all__ = [
    "DIRECTIONS", "JUMP_KINDS", "METHODS", "RPM", "Jump", "ModelFactory", "Point", "SweepCurve",
    "SweepOptions", "SweepResult", "aperiodic_ranges", "find_jumps", "hysteresis_ranges",
    "jumps", "periodic_response",
    "summarize_sweep", "sweep", "sweep_columns",
]
