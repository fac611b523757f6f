"""Newton iteration settings: the one option object of every Newton solve in the analysis layer.

Shooting (:func:`gear_dyn.analysis.stability.shoot`) and the continuation corrector
(:meth:`gear_dyn.analysis.continuation.shooting.Shooting.correct`) both iterate Newton's method
on the closing equations of a periodic orbit (Seydel 2010, ch. 4 and 7). How many iterations
and to what residual is one small frozen object, :class:`NewtonSettings`, nested in the option
objects of the studies that shoot; each study keeps its own default instance.
"""

from __future__ import annotations

from dataclasses import dataclass

from gear_dyn.errors import check_range


@dataclass(frozen=True)
class NewtonSettings:
    """How far Newton's method is iterated on the closing equations of a periodic orbit.

    Parameters
    ----------
    max_iter : int
        Newton iterations at most (1..100). Shooting also gives up early where from the
        fourth iteration on the residual no longer halves.
    tolerance : float or None
        Residual at which the iteration stops (-, 1e-14..1e-4). Shooting measures the
        relative closing error ``max_i |P(y0)_i - y0_i| / max(scale_i, |y0_i|)``, the
        continuation corrector the scaled residual of the shooting equations and the
        arclength condition. None: ``100 rtol`` of the map's integration (the map is only
        known to about ``rtol``); the continuation corrector needs a number.

    Raises
    ------
    InputError
        A field outside its range.

    Notes
    -----
    The defaults of each study that shoots (each keeps its own instance, so its results do
    not depend on another's):

    ==========================================================  ========  =========
    where                                                       max_iter  tolerance
    ==========================================================  ========  =========
    ``ContinuationSettings.newton`` (corrector of each step)    8         1e-10
    ``ContinuationSettings.start_newton`` (the first orbit)     30        100 rtol
    ``SweepOptions.newton`` (each speed of a sweep)             12        100 rtol
    ``DiagramOptions.newton`` (each speed of a diagram)         15        100 rtol
    ``classify_motion``, ``shoot``, ``periodic_steady_state``   15        100 rtol
    ``classify.LEAST_PERIOD_NEWTON`` (an orbit's least period)  3         100 rtol
    ``study.orbit_check`` (the check of ``gear-dyn run``)       12        100 rtol
    ==========================================================  ========  =========

    Examples
    --------
    >>> NewtonSettings(max_iter=20).tolerance is None  # 100 rtol of the map
    True
    >>> NewtonSettings(max_iter=0)
    Traceback (most recent call last):
    ...
    gear_dyn.errors.InputError: max_iter = 0 is out of range: valid range 1 <= x <= 100
    """

    max_iter: int = 15
    tolerance: float | None = None

    def __post_init__(self) -> None:
        check_range("max_iter", self.max_iter, "", low=1, high=100)
        if self.tolerance is not None:
            check_range("tolerance", self.tolerance, "", low=1e-14, high=1e-4)
