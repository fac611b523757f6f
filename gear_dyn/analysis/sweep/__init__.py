"""Speed sweeps: dynamic factor, DTE, stability and spectra over a range of pinion speeds.

A sweep evaluates a model at many speeds; it takes a model factory ``speed -> Model`` (the scene
layer builds one from a scene: :func:`gear_dyn.scene.sweep_scene`). Two methods:

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

Parallel runs: speeds are cut into blocks and the blocks run on any
:class:`concurrent.futures.Executor`: by default a process pool over the local cores; a Dask
``distributed.Client(...).get_executor()`` runs the same sweep on a cluster. Linear sweeps run
all blocks at once; continuation sweeps run their blocks in order, one chain per direction (the
up and down chains run side by side). Every speed is computed by the same code whatever the
executor, so the results are identical.
"""

from gear_dyn.analysis.sweep.driver import ModelFactory, run_block, sweep
from gear_dyn.analysis.sweep.report import (
    hysteresis_ranges,
    jumps,
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
    "DIRECTIONS", "METHODS", "RPM", "ModelFactory", "Point", "SweepCurve", "SweepOptions",
    "SweepResult", "hysteresis_ranges", "jumps", "run_block", "summarize_sweep", "sweep",
    "sweep_columns",
]
