"""Solvers: trajectories and solver statistics only (no analysis, no scene, no plots).

- :mod:`.settings`: :class:`SolverSettings`, the method names and the work limits;
- ``integrate`` (:func:`integrate`): method choice (``auto``) and dispatch;
- :mod:`.ode`: solve_ivp piece by piece; :mod:`.events`: restarts at contact changes;
- :mod:`.exact`: exact propagation of piecewise-constant linear models;
- :mod:`.periodic`: step maps of linear mesh-periodic models;
- :mod:`.kernel_method`: the native FMU's compiled stepper over the whole grid (``kernel``);
- ``simulate_bare`` (:func:`simulate_bare`): one run -> :class:`Result` (:mod:`.result`),
  without the checks that
  :func:`~gear_dyn.analysis.study.simulate` adds.
"""

from gear_dyn.solvers.exact import exact_applies, propagate_exact, propagate_pieces
from gear_dyn.solvers.integrate import integrate, resolve_auto, resolve_method
from gear_dyn.solvers.ode import atol_of, check_work, integrate_ode
from gear_dyn.solvers.periodic import periodic_map_applies, propagate_periodic
from gear_dyn.solvers.pieces import pieces
from gear_dyn.solvers.result import Result, SolverStats, time_grid
from gear_dyn.solvers.settings import (
    DEFAULT_ODE_METHOD,
    IMPLICIT,
    MAX_NATURAL_PERIODS,
    MAX_NFEV,
    MAX_SAMPLES,
    METHODS,
    SolverSettings,
)
from gear_dyn.solvers.simulate_bare import output_grid, simulate_bare

__all__ = [
    "DEFAULT_ODE_METHOD", "IMPLICIT", "MAX_NATURAL_PERIODS", "MAX_NFEV", "MAX_SAMPLES",
    "METHODS", "Result", "SolverSettings", "SolverStats", "atol_of", "check_work",
    "exact_applies", "integrate", "integrate_ode", "output_grid", "periodic_map_applies",
    "pieces", "propagate_exact", "propagate_periodic", "propagate_pieces", "resolve_auto",
    "resolve_method", "simulate_bare", "time_grid",
]
