"""The face every dynamic model offers to the solvers (STYLE.md rule 5).

A model is an object with:

- ``state_labels``: names of the state components (tuple of str)
- ``state_scale``: typical magnitude of each state (array, SI), used for absolute tolerances and
  for relative error figures
- ``mesh_frequency``: mesh frequency in Hz
- ``static_load``: the transmitted static load W in N (for dynamic factors)
- ``initial_state()``: the state at t = 0 (static deflection, so the transient is short)
- ``rhs(t, y)`` and ``jac(t, y)``: right-hand side and its Jacobian d rhs / d y
- ``switching_times(t0, t1)``: instants in (t0, t1) where the right-hand side jumps (teeth entering
  or leaving contact); the solver never steps across them
- ``outputs(t, y)``: derived time series (dict of arrays) from the states, ``y`` shaped
  (n_states, n_times)
- ``linear_segments(t0, t1)`` (optional): for models that are linear with piecewise-constant
  coefficients, the list of ``(t_start, t_end, A, g)`` with ``y' = A y + g`` on each piece; None
  when the model is not of that kind. Exact propagators use it.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


@runtime_checkable
class Model(Protocol):
    """Structural type of a gear_dyn dynamic model."""

    @property
    def state_labels(self) -> tuple[str, ...]: ...

    @property
    def mesh_frequency(self) -> float: ...

    @property
    def static_load(self) -> float: ...

    @property
    def state_scale(self) -> FloatArray: ...

    def initial_state(self) -> FloatArray: ...

    def rhs(self, t: float, y: FloatArray) -> FloatArray: ...

    def jac(self, t: float, y: FloatArray) -> FloatArray: ...

    def switching_times(self, t0: float, t1: float) -> FloatArray: ...

    def outputs(self, t: FloatArray, y: FloatArray) -> dict[str, FloatArray]: ...
