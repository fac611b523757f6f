"""Folds followed in two parameters, pinion speed and torque: the jump region of the
operating map (Seydel 2010, sec. 5.7; Kuznetsov 2004, sec. 8.2 and 10.2).

Natural-parameter continuation in torque: at each torque of a sequence the speed branch is
followed by :func:`~gear_dyn.analysis.continuation.arclength.continue_orbits` over the whole speed
window and its folds are located
there (to the continuation's ``locate_tol``). Consecutive folds that bound an unstable stretch
are the two ends of one hysteresis loop; loops are matched from one torque to the next, and a
loop that vanishes between two torques ends at a cusp, located by bisection in torque.
docs/response.md ("Jump map", **How.**) says why this and not the augmented fold system
``P(y) - y = 0, det(M - I) = 0``, and what it costs.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np

from gear_dyn.analysis.continuation.arclength import continue_orbits
from gear_dyn.analysis.continuation.branch import Bifurcation, Branch
from gear_dyn.analysis.continuation.jump_map import Cusp, FoldMap, JumpRegion
from gear_dyn.analysis.continuation.settings import ContinuationSettings
from gear_dyn.analysis.threads import blas_limited
from gear_dyn.errors import InputError, check_range
from gear_dyn.geometry import check_speed, check_torque
from gear_dyn.models.base import Model, at_torque

#: a fold pair as (low speed, high speed, low error, high error) in rad/s, and the stability
#: before and after the low and the high fold along the branch
_Pair = tuple[float, float, float, float, str, str]


@dataclass(frozen=True)
class SpeedTorqueFamily:
    """``SpeedTorqueFamily(speed_family)(speed, torque)``: the model of ``speed_family(speed)``
    with its static load scaled to ``torque`` (``W = T / r_b1``, so
    ``W(T) = W(T_ref) T / T_ref``; the stiffness of the model is kept as it is).

    Parameters
    ----------
    speed_family : callable
        ``speed (rad/s) -> model`` at the torque ``torque_ref``:
        :class:`~gear_dyn.scene.sweep.SceneModels` (which knows its scene's torque, its ``torque``
        attribute), or
        :func:`~gear_dyn.analysis.continuation.family.sdof_family` in ``speed``; its models must be
        dataclasses with a
        ``static_load`` field (the single-DOF mesh model).
    torque_ref : float or None
        The torque (N m, > 0) of ``speed_family``'s models. None: the family's own
        ``torque`` (a scene's ``operating.torque``); needed for a family that does not know
        its torque (:func:`~gear_dyn.analysis.continuation.family.sdof_family`). Given for a family
        that knows it, it must agree
        with it (a wrong value would scale every load by the wrong factor).

    Raises
    ------
    InputError
        No torque known, a torque out of 0..1e8 N m, or one that contradicts the family's.

    See Also
    --------
    :func:`~gear_dyn.analysis.continuation.fold_curve.fold_map`
        The jump regions over speed and torque.
    :func:`~gear_dyn.analysis.continuation.family.sdof_family`
        A speed family of a single-DOF model.

    Examples
    --------
    >>> from gear_dyn import SDOFModel, rectangular_stiffness, sdof_family
    >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
    ...               backlash=1e-3)
    >>> fam = SpeedTorqueFamily(sdof_family(m, "speed", teeth=20), torque_ref=52.0)
    >>> fam.reference  # N m
    52.0
    >>> fam(40.0, 26.0).static_load  # half the torque: half the load (N)
    520.0
    """

    speed_family: Callable[[float], Model]
    torque_ref: float | None = None

    def __post_init__(self) -> None:
        own = getattr(self.speed_family, "torque", None)
        if self.torque_ref is None:
            if own is None:
                raise InputError(f"torque_ref: {type(self.speed_family).__name__} does not "
                                 "know the torque of its models; give torque_ref (N*m)")
            object.__setattr__(self, "torque_ref", float(own))
        elif own is not None and abs(float(self.torque_ref) - float(own)) > 1e-9 * abs(own):
            raise InputError(f"torque_ref = {self.torque_ref:.6g} N*m: the family's models are "
                             f"at {float(own):.6g} N*m (its scene's operating.torque); leave "
                             "torque_ref out")
        check_torque(self.reference, "torque_ref", positive=True)

    @property
    def reference(self) -> float:
        """The torque of ``speed_family``'s models (N m)."""
        assert self.torque_ref is not None  # set in __post_init__
        return float(self.torque_ref)

    def __call__(self, speed: float, torque: float) -> Any:
        """The model at ``speed`` (rad/s) and ``torque`` (N m).

        Raises
        ------
        InputError
            A torque out of 0..1e8 N m, or a model without a ``static_load`` field.
        """
        check_torque(torque)  # before the model is built
        model = self.speed_family(speed)
        return at_torque(model, torque, getattr(model, "static_load", math.nan), self.reference)

    def at_torque(self, torque: float) -> Callable[[float], Any]:
        """The speed family ``speed (rad/s) -> model`` at ``torque`` (N m; picklable).

        Parameters
        ----------
        torque : float
            Pinion torque in N m (0..1e8).

        Returns
        -------
        callable
            ``speed (rad/s) -> model`` with the static load scaled to ``torque``.

        See Also
        --------
        :func:`~gear_dyn.analysis.continuation.arclength.continue_orbits` : Takes such a family.

        Examples
        --------
        >>> from gear_dyn import SDOFModel, rectangular_stiffness, sdof_family
        >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0)
        >>> fam = SpeedTorqueFamily(sdof_family(m, "speed", teeth=20), torque_ref=52.0)
        >>> fam.at_torque(104.0)(40.0).static_load  # N
        2080.0
        """
        return partial(self, torque=float(torque))


def fold_pairs(branch: Branch) -> list[_Pair]:
    """The hysteresis loops of a speed branch: consecutive folds whose first turns the branch
    from stable to unstable (``after == "unstable"``), as (low, high, low error, high error,
    low stability, high stability) in order along the branch (stability: ``before->after``
    along the branch)."""
    folds: list[Bifurcation] = branch.of_kind("fold")
    out: list[_Pair] = []
    i = 0
    while i + 1 < len(folds):
        a, b = folds[i], folds[i + 1]
        if a.after == "unstable":
            (lo, elo, slo), (hi, ehi, shi) = sorted(
                [(x.parameter, x.parameter_error, f"{x.before}->{x.after}") for x in (a, b)])
            out.append((lo, hi, elo, ehi, slo, shi))
            i += 2
        else:
            i += 1
    return out


class _Tracer:
    """Speed branches at torques, cached, with their cost."""

    def __init__(self, family: SpeedTorqueFamily, speeds: tuple[float, float], periods: int,
                 settings: ContinuationSettings) -> None:
        self.family, self.speeds, self.periods, self.settings = family, speeds, periods, settings
        self.cache: dict[float, tuple[list[_Pair], tuple[float, ...]]] = {}
        self.n_maps = 0

    def pairs(self, torque: float) -> list[_Pair]:
        hit = self.cache.get(torque)
        if hit is None:
            br = continue_orbits(self.family.at_torque(torque), self.speeds[0], self.speeds[1],
                                 periods=self.periods, settings=self.settings, doublings=0)
            self.n_maps += br.n_maps
            hit = (fold_pairs(br), tuple(b.parameter for b in br.of_kind("fold")))
            self.cache[torque] = hit
        return hit[0]


def _match(prev: list[_Pair], new: list[_Pair], width: float) -> list[tuple[int, int]]:
    """Index pairs (prev, new) of the same loop: by order where the counts agree, else by
    least fold-speed distance (the sum of the two folds' speed differences, rad/s: an
    assignment), refusing matches further apart than ``width``.
    (A midpoint would match a wide loop to a small one born inside it.)"""
    if len(prev) == len(new):
        return [(i, i) for i in range(len(prev))]
    if not prev or not new:
        return []
    from scipy.optimize import linear_sum_assignment  # here: a sweep imports this package

    cost = np.array([[abs(p[0] - q[0]) + abs(p[1] - q[1]) for q in new] for p in prev])
    rows, cols = linear_sum_assignment(cost)
    return [(int(r), int(c)) for r, c in zip(rows, cols, strict=True) if cost[r, c] < width]


def _cusp(tr: _Tracer, t_has: float, pairs_has: list[_Pair], index: int, t_not: float,
          bisections: int, width: float, track: list[tuple[float, _Pair]]) -> Cusp:
    """Bisection in torque between ``t_has`` (the loop ``pairs_has[index]`` is there) and
    ``t_not`` (it is gone): the loop is there at a torque where :func:`_match` matches it.
    Points found on the way are appended to ``track``."""
    for _ in range(bisections):
        t_mid = 0.5 * (t_has + t_not)
        pairs = tr.pairs(t_mid)
        hit = [k for i, k in _match(pairs_has, pairs, width) if i == index]
        if hit:
            t_has, pairs_has, index = t_mid, pairs, hit[0]
            track.append((t_mid, pairs[index]))
        else:
            t_not = t_mid
    pair = pairs_has[index]
    return Cusp(speed=0.5 * (pair[0] + pair[1]), torque=0.5 * (t_has + t_not),
                torque_error=0.5 * abs(t_has - t_not), half_gap=0.5 * (pair[1] - pair[0]))


@blas_limited
def fold_map(family: SpeedTorqueFamily, speeds: tuple[float, float], torques: Sequence[float],
             *, periods: int = 1, settings: ContinuationSettings | None = None,
             cusp_bisections: int = 4, reference_torque: float | None = None) -> FoldMap:
    """The jump regions in (speed, torque): fold curves followed over torque, with their cusps.

    Parameters
    ----------
    family : SpeedTorqueFamily
        ``(speed, torque) -> model`` (rad/s, N m).
    speeds : (float, float)
        Speed window (rad/s) of the branch at every torque; it starts at ``speeds[0]``, which
        should lie where the response has one orbit (below the jump regions). A loop with a
        fold outside the window is not reported (the branch leaves the window there).
    torques : sequence of float
        Torques (N m, > 0), at least 2; sorted here.
    periods : int
        Mesh periods n of the orbits (1..16).
    settings : ContinuationSettings or None
        Continuation settings of every speed branch.
    cusp_bisections : int
        Bisections in torque locating each cusp (0..30); each costs one speed branch and
        halves the cusp's ``torque_error``.
    reference_torque : float or None
        The scene's own torque (N m), for the figure.

    Returns
    -------
    FoldMap
        The jump regions, the fold speeds at each torque and the cusps.

    Raises
    ------
    InputError
        Fewer than 2 torques, a torque <= 0, an empty speed window, bad ``cusp_bisections``.
    SolverError
        No periodic orbit at the start of a branch.

    See Also
    --------
    :class:`~gear_dyn.analysis.continuation.fold_curve.SpeedTorqueFamily` : The family it takes.
    :func:`~gear_dyn.analysis.continuation.arclength.continue_orbits` : One speed branch.
    :class:`~gear_dyn.analysis.continuation.jump_map.FoldMap` : The result.

    Examples
    --------
    >>> from gear_dyn import SDOFModel, rectangular_stiffness
    >>> from gear_dyn.analysis.continuation import sdof_family
    >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 8e5, 1.2e6), 0.05, 1040.0, 100.0,
    ...               backlash=1e-3)
    >>> fam = SpeedTorqueFamily(sdof_family(m, "speed", teeth=20), torque_ref=1040.0 * 0.05)
    >>> fam(40.0, 2 * 52.0).static_load  # twice the torque: twice the load (N)
    2080.0
    >>> fmap = fold_map(fam, (43.0, 44.5), [50.0, 52.0], cusp_bisections=0)
    >>> [[round(f, 2) for f in folds] for folds in fmap.folds]  # fold speeds (rad/s)
    [[43.96], [43.96]]
    """
    if len(torques) < 2:
        raise InputError(f"torques: {len(torques)} given, at least 2 needed")
    for t in torques:
        check_torque(t, positive=True)
    lo, hi = (float(s) for s in speeds)
    check_speed(lo, "speeds[0]")
    check_speed(hi, "speeds[1]")
    if lo == hi:
        raise InputError(f"speeds = ({lo:.6g}, {hi:.6g}) rad/s: the window is empty")
    check_range("cusp_bisections", cusp_bisections, "", low=0, high=30)
    ts = sorted(float(t) for t in torques)
    tr = _Tracer(family, (lo, hi), periods, settings or ContinuationSettings())
    width = abs(hi - lo)
    tracks: list[list[tuple[float, _Pair]]] = []  # each loop: (torque, pair) in any order
    cusps: list[list[Cusp]] = []
    active: dict[int, int] = {}  # index of a pair at the previous torque -> its track
    prev = tr.pairs(ts[0])
    for j, p in enumerate(prev):
        active[j] = len(tracks)
        tracks.append([(ts[0], p)])
        cusps.append([])
    for t_prev, t in zip(ts[:-1], ts[1:], strict=True):
        new = tr.pairs(t)
        matched = _match(prev, new, width)
        nxt: dict[int, int] = {}
        for i, k in matched:
            nxt[k] = active[i]
            tracks[active[i]].append((t, new[k]))
        for i in set(range(len(prev))) - {i for i, _k in matched}:  # a loop ends: cusp
            tk = active[i]
            cusps[tk].append(_cusp(tr, t_prev, prev, i, t, cusp_bisections, width,
                                   tracks[tk]))
        for k in set(range(len(new))) - {k for _i, k in matched}:  # a loop begins: cusp
            nxt[k] = len(tracks)
            tracks.append([(t, new[k])])
            cusps.append([_cusp(tr, t, new, k, t_prev, cusp_bisections, width,
                                tracks[-1])])
        prev, active = new, nxt
    regions = []
    for track, cs in zip(tracks, cusps, strict=True):
        track.sort(key=lambda x: x[0])
        a = np.array([[t, *p[:4]] for t, p in track], dtype=float)
        regions.append(JumpRegion(a[:, 0], a[:, 1], a[:, 2], a[:, 3], a[:, 4], tuple(cs),
                                  tuple(p[4] for _t, p in track),
                                  tuple(p[5] for _t, p in track)))
    all_t = sorted(tr.cache)
    model = family(lo, ts[0])
    fn = model.natural_frequency
    return FoldMap(tuple(regions), np.array(all_t), (lo, hi),
                   tuple(tr.cache[t][1] for t in all_t), reference_torque, tr.n_maps,
                   math.nan if fn is None else float(fn), float(model.mesh_frequency) / lo,
                   tr.settings.locate_tol)
