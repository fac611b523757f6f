"""Continuation settings: one small immutable object (step bounds, tolerances, detection).

As in BifurcationKit's ``ContinuationPar`` and AUTO-07p's constants file, the knobs of a
continuation run live in one frozen dataclass, checked on construction.
"""

from __future__ import annotations

from dataclasses import dataclass

from gear_dyn.analysis.newton import NewtonSettings
from gear_dyn.errors import InputError, check_range


@dataclass(frozen=True)
class ContinuationSettings:
    """How a branch of periodic orbits is followed
    (:func:`~gear_dyn.analysis.continuation.arclength.continue_orbits`).

    Lengths are in the scaled space of the unknowns ``z = (x / x_s, v / v_s, p / p_ref)``
    (``x_s, v_s`` the model's ``state_scale``, ``p_ref`` the start value of the parameter), so
    a step of 0.01 moves the parameter by about 1 % where the branch runs along it.

    Parameters
    ----------
    step : float
        First arclength step (scaled, > 0).
    step_min, step_max : float
        Bounds of the adaptive step (scaled; ``0 < step_min <= step <= step_max``). The run
        stops with a message when a step below ``step_min`` would be needed.
    max_points : int
        Largest number of points on one branch (1..100000).
    newton : NewtonSettings
        The corrector: ``tolerance``, the scaled residual of the shooting equations and the
        arclength condition it stops at (1e-14..1e-4; a number, not None), and ``max_iter``,
        its iterations before the step is halved (2..50). Default 8 iterations to 1e-10.
    start_newton : NewtonSettings
        Shooting for the branch's first orbit from the given state
        (:func:`~gear_dyn.analysis.continuation.arclength.start_orbit`). Default 30
        iterations to 100 ``rtol``.
    target_newton : int
        Corrector iterations aimed at: at most this many grow the step by ``grow``, more than
        ``target_newton + 2`` shrink it. With the exact speed column (a speed family on the
        exact route, :mod:`.shooting`) the corrector is Newton's method with the exact
        Jacobian: about 3 iterations to ``newton.tolerance`` on the packaged backlash scene.
        Otherwise it starts from the parameter column of the Jacobian at the step's start and
        corrects it by the secant condition of each Newton step (the state columns are
        exact): 4-5 iterations on a smooth stretch.
    grow : float
        Step growth factor after an easy corrector (1..4).
    max_turn : float
        Largest angle in rad between consecutive tangents (0..pi/2); a larger turn rejects the
        step and halves it, so a fold is never stepped over and the corrector never lands on
        another branch.
    rtol : float
        Relative tolerance of the variational integration (route ``variational``; unused by
        the exact route), 1e-13..1e-6.
    fd_step : float
        Relative step of the central difference for the parameter derivative of the shooting
        map (1e-9..1e-2); its error is O(fd_step**2) (truncation) plus O(eps / fd_step)
        (rounding), both about 1e-10 at the default. On the exact route, where the corrector's
        secant column is at hand to check it, the one-map forward difference steps
        ``FORWARD_STEP_RATIO`` (1e-3) of it instead (:mod:`.shooting`). Unused where the
        column is exact (a speed family on the exact route).
    locate_tol : float
        Relative error of the parameter to which folds, period doublings and grazing points
        are located (1e-14..1e-4): the bracketing stops when the parameter changes by at most
        ``locate_tol |p|`` over the final bracket (:mod:`.detect`). The default is a
        hundredth of the 1e-8 asked for, which leaves room for the corrector's own error
        (each point closes to ``newton.tolerance``); both make up a located point's stated
        ``parameter_error``.
    liouville_tol : float
        Largest relative mismatch ``|det M / exp(-c nT / m) - 1|`` accepted on a point
        (1e-14..1); a point over it is flagged (``liouville_ok`` False), not dropped.
    detect : bool
        Detect and locate folds, period doublings and grazing (contact-pattern changes).

    Raises
    ------
    InputError
        Any field outside its range.

    See Also
    --------
    :func:`~gear_dyn.analysis.continuation.arclength.continue_orbits`
        Follows a branch with these settings.
    :func:`~gear_dyn.analysis.continuation.fold_curve.fold_map` : Uses them for every speed branch.

    Examples
    --------
    >>> settings = ContinuationSettings(step=0.01, max_points=200)
    >>> settings.step_max  # the default bound (scaled)
    0.1
    >>> ContinuationSettings(step=0.0)
    Traceback (most recent call last):
    ...
    gear_dyn.errors.InputError: step = 0 is out of range: valid range 1e-07 <= x <= 0.1
    """

    step: float = 0.02
    step_min: float = 1e-7
    step_max: float = 0.1
    max_points: int = 2000
    newton: NewtonSettings = NewtonSettings(max_iter=8, tolerance=1e-10)
    start_newton: NewtonSettings = NewtonSettings(max_iter=30)
    target_newton: int = 4
    grow: float = 1.5
    max_turn: float = 0.3
    rtol: float = 1e-10
    fd_step: float = 1e-5
    locate_tol: float = 1e-10
    liouville_tol: float = 1e-6
    detect: bool = True

    def __post_init__(self) -> None:
        check_range("step_max", self.step_max, "", low=0.0, low_open=True, high=10.0)
        check_range("step_min", self.step_min, "", low=0.0, low_open=True, high=self.step_max)
        check_range("step", self.step, "", low=self.step_min, high=self.step_max)
        check_range("max_points", self.max_points, "", low=1, high=100000)
        if self.newton.tolerance is None:
            raise InputError("newton.tolerance = None: the continuation corrector needs a "
                             "residual to stop at, valid range 1e-14 <= x <= 0.0001")
        check_range("newton.max_iter", self.newton.max_iter, "", low=2, high=50)
        check_range("target_newton", self.target_newton, "", low=1, high=self.newton.max_iter)
        check_range("grow", self.grow, "", low=1.0, high=4.0)
        check_range("max_turn", self.max_turn, "rad", low=0.0, high=1.5707963267948966,
                    low_open=True)
        check_range("rtol", self.rtol, "", low=1e-13, high=1e-6)
        check_range("fd_step", self.fd_step, "", low=1e-9, high=1e-2)
        check_range("locate_tol", self.locate_tol, "", low=1e-14, high=1e-4)
        check_range("liouville_tol", self.liouville_tol, "", low=1e-14, high=1.0)
