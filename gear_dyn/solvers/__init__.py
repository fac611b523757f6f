"""Solvers: trajectories and solver statistics only (no analysis, no scene, no plots).

Every way of advancing a model's state lives here, one module per method:

- :mod:`.settings`: :class:`SolverSettings`, the method names and the work limits;
- ``integrate`` (:func:`integrate`): method choice (``auto``) and dispatch;
- :mod:`.events`: :class:`~gear_dyn.solvers.events.RestartingSolver`, one scipy
  ``OdeSolver`` kept alive, restarted at switching instants and at contact changes, and the
  one event locator of the Python solvers (roots of the contact functions on its dense
  output, grazing contacts, the chattering cap); the compiled kernel has its own;
- :mod:`.ode`: :func:`~gear_dyn.solvers.ode.flow`, the one solve_ivp driver (that solver over
  a whole grid, cut at the switching instants, optionally with the variational equations),
  and ``integrate_ode``, that driver with settings;
- :mod:`.session`: the same solver advanced point by point (switching instants found window
  by window; ``exact`` by cached exponentials), the FMU's stepper;
- :mod:`.sensitivity`: a state and ``d y(t1) / d y0`` by route (the backlash closed form or
  the driver's variational equations);
- :mod:`.exact`: exact propagation of piecewise-constant linear models;
- :mod:`.contact_exact`: the closed form between located contact changes (backlash);
- :mod:`.periodic`: step maps of linear mesh-periodic models on a commensurate grid (the
  Magnus substeps of :mod:`.linear_maps` at one speed, composed in ``kernel``);
- :mod:`.linear_maps`: one-period maps of the linear single-DOF model over many speeds at once
  (exact cells, Magnus substeps; sweeps, charts, the tolerance study, the ``periodic`` step
  maps): it builds the phase
  tables, the kernel advances every speed (:mod:`.kernel.linear`); not imported here (import
  it from its module);
- :mod:`.gauss`: Gauss-Legendre step maps of affine models (the eccentric torsional model,
  by name, or under ``auto`` where the kernel does not take it);
- ``kernel``: the compiled C kernel (products, compose, chain, fill_periodic; the linear
  single-DOF steps over many speeds and the one closed-form 2x2 exponential, ``kernel.linear``),
  shared with the native FMU;
- :mod:`.kernel_method`: the native FMU's compiled stepper over the whole grid (``kernel``;
  ``auto``'s method for the eccentric torsional model on any span, whatever ran before);
- ``simulate_bare`` (:func:`simulate_bare`): one run -> :class:`Result` (:mod:`.result`),
  without the checks that :func:`~gear_dyn.analysis.study.simulate` adds.

Adding a method
---------------
The contract a method meets (as scipy's ``OdeSolver`` states its own):

1. One module here, the method's only home. Building blocks are called, not copied: a
   solve_ivp integration goes through :func:`~gear_dyn.solvers.ode.flow`, a 2x2 exponential
   through :func:`~gear_dyn.solvers.kernel.linear.expm2`, products of step maps through
   ``kernel``.
2. A predicate ``<name>_applies(model[, t_grid]) -> bool`` that answers from the model's
   capabilities alone (``is_linear``, ``mesh_periodic``, ``backlash``, ``linear_segments``,
   ``force_form`` ...), cheaply and without integrating.
3. A function ``propagate_<name>(model, t_grid, settings, y0=None) -> (y, stats)``. It
   receives a :class:`~gear_dyn.models.base.Model`; ``t_grid``, increasing output times in s
   whose first entry is the initial time; ``settings``, a :class:`SolverSettings` whose
   ``method`` is already resolved (never ``auto``); ``y0``, the state at ``t_grid[0]`` in the
   SI units of ``model.state_labels`` (None: ``model.initial_state()``). It returns ``y``,
   ``(n_states, len(t_grid))`` floats with ``y[:, 0] = y0``, and ``stats``, a dict with at
   least the ints ``nfev`` (its unit of work: right-hand-side evaluations, exponentials,
   coefficient evaluations), ``njev``, ``nlu`` and ``n_segments``, plus method-specific keys
   (``step_maps``, ``piece_maps``, ``n_contact_events``, ...); where it hands over to another
   method, ``stats["method"]`` names the one that ran. It is pure: no printing, files or
   global state; heavy imports (scipy.integrate) on use.
4. Failures are errors, never silent garbage: :class:`~gear_dyn.errors.InputError` for a
   model or grid it does not apply to when asked for by name (or a documented hand-over, as
   ``periodic`` and ``gauss`` fall back to the ODE path), :class:`~gear_dyn.errors.SolverError`
   with the underlying message for a failed step, non-finite states or a spent work budget.
5. It states its error. Either it is exact up to rounding, or its docstring gives the rule
   that ties its steps to ``settings.rtol`` (e.g. ``(omega h / 2)^(2 s) <= rtol``). The
   estimate attached to every run is made in :func:`gear_dyn.analysis.accuracy.estimate_error`,
   by the method's name: the rounding level from ``stats["n_segments"]`` for exact methods
   (``exact_contact`` adds a run from a state moved by 1e-12, for unstable responses);
   otherwise a second run at ``rtol / 100`` (what every method gets without more code), or a
   cheaper independent check from its own stats (``periodic``: a Gauss-Legendre reference from
   ``step_maps``). The estimate's ``basis`` says which.
6. Registration: its name in ``METHODS`` (:mod:`gear_dyn.solvers.settings`), a branch in
   :func:`integrate`, and in
   :func:`resolve_method` only where ``auto`` should pick it, with the benchmark that shows
   why (docs/solvers.md). Tests compare it with an independent reference (a closed form, or
   DOP853 at a tight tolerance) within its stated error.
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
