"""Solver settings: the method, tolerances and output grid of a run, and the work limits."""

from __future__ import annotations

import math
from dataclasses import dataclass

from gear_dyn.errors import InputError, check_range

#: the names ``SolverSettings.method`` (``[solver] method``) accepts
METHODS = ("auto", "RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA", "exact", "periodic",
           "exact_contact", "gauss", "kernel")
#: solve_ivp method of ``auto`` when the exact propagator does not apply. LSODA (restarted at
#: each switching instant) was the fastest for every target error on the helicopter tail scene
#: with rectangular and Fourier stiffness, heavy damping, a 1000x stiffer mesh and backlash
#: (docs/solvers.md, ``gear-dyn bench``), and it switches to BDF by itself when stiff.
DEFAULT_ODE_METHOD = "LSODA"
#: the implicit solve_ivp methods: they are given the model's Jacobian
IMPLICIT = ("Radau", "BDF", "LSODA")

#: work limits, so that an absurd input ends in a clear error instead of a hang or a memory blow-up
MAX_SAMPLES = 4_000_000  #: output samples of one run (periods x samples_per_period)
MAX_NATURAL_PERIODS = 50_000  #: natural periods of the mesh mode one ODE run may span
MAX_NFEV = 5_000_000  #: right-hand-side evaluations of one ODE run (checked between pieces)

@dataclass(frozen=True)
class SolverSettings:
    """Integration settings.

    Parameters
    ----------
    method : str
        ``auto`` (default: the exact propagator where it applies; ``kernel`` for the
        single-DOF model with backlash and piecewise-constant stiffness and for the eccentric
        torsional model over most of its hunting period, where the compiled kernel is built;
        else ``exact_contact`` for the
        single-DOF model with backlash; else, for a linear single-DOF model on the usual
        uniform grid, ``periodic``; else ``gauss`` where it applies; else LSODA), or one of
        RK45, RK23, DOP853, Radau, BDF, LSODA (solve_ivp), ``exact`` (piecewise-exact
        propagator, linear models with piecewise-constant coefficients only) or ``periodic``
        (linear mesh-periodic models: one period of step maps, then reused; see
        :func:`gear_dyn.solvers.periodic.propagate_periodic`) or ``gauss`` (models affine in the
        state while a condition holds, the eccentric torsional model: Gauss-Legendre step maps
        of every output interval at once; :mod:`gear_dyn.solvers.gauss`) or ``kernel`` (the
        native FMU's compiled stepper from the model's tables in the mesh phase, the whole grid
        in one call; single-DOF and eccentric torsional models;
        :mod:`gear_dyn.solvers.kernel_method`).
    rtol : float
        Relative tolerance, 1e-13..1e-2.
    atol : float or None
        Absolute tolerance in units of the states; None means ``rtol * model.state_scale``
        (the static deflection and its velocity scale), i.e. a purely relative criterion.
    samples_per_period : int
        Output points per mesh period, 4..4096.
    max_step : float
        Largest step in s (inf: unlimited).
    estimate_error : bool
        Attach an error estimate to the result (``extra["estimated_error"]``, see
        :mod:`gear_dyn.analysis.accuracy`); for solve_ivp methods it costs a second, tighter run
        over the whole span. Default True.
    max_nfev : int
        Work budget of one solve_ivp run: right-hand-side evaluations (checked between pieces;
        1000..1e12, default :data:`~gear_dyn.solvers.settings.MAX_NFEV`); the CLI's
        ``--max-nfev`` sets it.

    Raises
    ------
    InputError
        An unknown method or a field outside its range.

    See Also
    --------
    :func:`~gear_dyn.analysis.study.simulate` : Integrates with these settings.
    :class:`~gear_dyn.solvers.result.Result` : Keeps them in ``settings``.

    Examples
    --------
    >>> SolverSettings(rtol=1e-10).samples_per_period
    64
    >>> SolverSettings(method="Euler")
    Traceback (most recent call last):
    ...
    gear_dyn.errors.InputError: solver.method = 'Euler': valid choices are auto, ...
    """

    method: str = "auto"
    rtol: float = 1e-8
    atol: float | None = None
    samples_per_period: int = 64
    max_step: float = math.inf
    estimate_error: bool = True
    max_nfev: int = MAX_NFEV

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise InputError(
                f"solver.method = {self.method!r}: valid choices are {', '.join(METHODS)}"
            )
        check_range("solver.rtol", self.rtol, "", low=1e-13, high=1e-2)
        if self.atol is not None:
            check_range("solver.atol", self.atol, "", low=0.0, low_open=True)
        if isinstance(self.samples_per_period, bool) or int(self.samples_per_period) != (
            self.samples_per_period
        ):
            raise InputError(
                f"solver.samples_per_period = {self.samples_per_period!r}: expected an integer"
            )
        check_range("solver.samples_per_period", self.samples_per_period, "", low=4, high=4096)
        if not (isinstance(self.max_step, int | float) and self.max_step > 0):
            raise InputError(f"solver.max_step = {self.max_step!r} s: valid range > 0 s")
        check_range("solver.max_nfev (--max-nfev)", self.max_nfev, "", low=1000, high=1e12)
