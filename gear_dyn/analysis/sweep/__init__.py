"""Speed sweeps: dynamic factor, DTE, stability and spectra over a range of pinion speeds.

A sweep evaluates a model at many speeds; it takes a model factory ``speed -> Model`` (the scene
layer builds one from a scene: :func:`gear_dyn.scene.sweep.sweep_scene`). Two methods:

- ``steady`` (default): the periodic steady state directly
  (:mod:`gear_dyn.analysis.stability`). Linear models: the monodromy matrix and one linear solve per
  speed; a Floquet multiplier outside the unit circle flags parametric instability (no blow-up is
  integrated). Backlash: continuation from the previous speed's orbit and shooting; where the orbit
  is lost (a jump, or a response that is not period-1) the sweep integrates a settling transient
  from the previous state, as a slow physical sweep would, and shoots again.
- ``transient``: what ``gear-dyn run`` does, at every speed: integrate the scene's number of
  mesh periods and measure the last ``steady_periods`` (linear models still get their Floquet
  check first). With backlash each speed starts from the previous speed's end state.

The factory rebuilds the speed-dependent parts exactly as :func:`gear_dyn.scene.run_scene` builds
them (for the single-DOF model only the mesh frequency ``f_m = z1 w / 2 pi``). Models with backlash
are swept up and down (the two curves differ where the response has coexisting orbits: the jumps of
Kahraman & Singh 1990).

It runs in the calling process unless asked for ``workers`` or an ``executor`` (:func:`sweep`).
Jumps are found from the orbits (:mod:`.orbit_jumps`); up and down sweeps that differ are
hysteresis only where both found a periodic orbit (:func:`hysteresis_ranges`,
:func:`aperiodic_ranges`). docs/sweep.md, "Parallel runs" and "How jumps are found", gives the
details.
"""

from gear_dyn.analysis.sweep.driver import ModelFactory, sweep
from gear_dyn.analysis.sweep.jump import JUMP_KINDS, Jump
from gear_dyn.analysis.sweep.orbit_jumps import find_jumps
from gear_dyn.analysis.sweep.report import (
    aperiodic_ranges,
    hysteresis_ranges,
    jumps,
    periodic_response,
    summarize_sweep,
    sweep_columns,
)
from gear_dyn.analysis.sweep.types import (
    DIRECTIONS,
    METHODS,
    RPM,
    Point,
    SweepCurve,
    SweepOptions,
    SweepResult,
)

__all__ = [
    "DIRECTIONS", "JUMP_KINDS", "METHODS", "RPM", "Jump", "ModelFactory", "Point", "SweepCurve",
    "SweepOptions", "SweepResult", "aperiodic_ranges", "find_jumps", "hysteresis_ranges",
    "jumps", "periodic_response",
    "summarize_sweep", "sweep", "sweep_columns",
]
