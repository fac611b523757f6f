"""The largest Lyapunov exponent from the tangent (variational) flow, with renormalisation.

Benettin, Galgani, Giorgilli & Strelcyn (1980): a tangent vector ``v`` is carried along the
trajectory by the flow's sensitivity ``Phi = dy(t + T)/dy(t)`` over each mesh period T, its
growth ``g = |Phi v|`` is logged and ``v`` renormalised to unit length (so it neither overflows
nor underflows); the exponent is the mean of ``log g`` per second. Wolf, Swift, Swinney &
Vastano (1985) and Parker & Chua (1989, sec. 10.2) describe the same algorithm. The log growths
are summed in blocks of periods; the estimate is the mean over the blocks and its uncertainty
the blocks' standard error (``std / sqrt(n_blocks)``), which shrinks as ``1/sqrt(time)`` for
a chaotic attractor.

The sensitivity comes from :func:`gear_dyn.solvers.sensitivity.integrate_with_sensitivity`: the
exact flow or the variational equations, two independent integrators of the same tangent flow.
On the exact route the whole run is one walk of the closed-form pieces
(:func:`gear_dyn.solvers.contact_exact.walk`) that hands back each period's sensitivity.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import check_range
from gear_dyn.models.base import MeshModel
from gear_dyn.solvers.contact_exact import contact_exact_applies, walk
from gear_dyn.solvers.sensitivity import integrate_with_sensitivity

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class LyapunovEstimate:
    """The largest Lyapunov exponent of a trajectory.

    Attributes
    ----------
    value : float
        Estimate in 1/s (mean over the blocks).
    error : float
        Its standard error in 1/s: the spread of the block estimates over ``sqrt(n_blocks)``.
    blocks : ndarray
        Exponent of each block in 1/s.
    periods : int
        Mesh periods averaged over (the alignment periods excluded).
    mesh_period : float
        T = 1/f_m in s.
    route : str
        ``exact`` or ``variational``
        (:func:`gear_dyn.solvers.sensitivity.integrate_with_sensitivity`).
    y_end : ndarray
        State at the end of the run, SI units.
    """

    value: float
    error: float
    blocks: FloatArray
    periods: int
    mesh_period: float
    route: str
    y_end: FloatArray

    @property
    def per_period(self) -> float:
        """The exponent per mesh period (dimensionless: ``value * T``)."""
        return self.value * self.mesh_period

    def __repr__(self) -> str:
        return (f"LyapunovEstimate({self.value:.4g} +- {self.error:.2g} 1/s over "
                f"{self.periods} mesh periods, {self.route})")


def largest_lyapunov(model: MeshModel, y0: FloatArray, periods: int = 400, block: int = 50,
                     align: int = 20, rtol: float = 1e-10, route: str = "auto"
                     ) -> LyapunovEstimate:
    """The largest Lyapunov exponent of the trajectory from ``y(0) = y0`` (Benettin et al. 1980).

    Parameters
    ----------
    model : MeshModel
        Single-DOF mesh model (linear or with backlash).
    y0 : ndarray
        Start state at t = 0, SI units; start on the attractor (after settling).
    periods : int
        Mesh periods averaged over (2..1e6), cut into blocks of ``block``.
    block : int
        Mesh periods per block (1..periods); at least two blocks are needed for an error.
    align : int
        Mesh periods run first and not counted (0..1e5): the tangent vector turns into the
        most expanding direction.
    rtol : float
        Relative tolerance of the variational route (unused by the exact route).
    route : {"auto", "exact", "variational"}
        Sensitivity of each period
        (:func:`gear_dyn.solvers.sensitivity.integrate_with_sensitivity`).

    Returns
    -------
    LyapunovEstimate

    Raises
    ------
    InputError
        A bad argument, or ``route = "exact"`` where it does not apply.
    SolverError
        Integration failure.
    """
    check_range("periods", periods, "", low=2, high=1_000_000)
    check_range("block", block, "", low=1, high=periods)
    check_range("align", align, "", low=0, high=100_000)
    n_blocks = int(periods) // int(block)
    check_range("periods // block", n_blocks, "", low=2)
    used = "exact" if route == "auto" and contact_exact_applies(model) else route
    used = "variational" if used == "auto" else used
    mesh_period = 1.0 / model.mesh_frequency
    scale = np.asarray(model.state_scale, dtype=float)
    y = np.asarray(y0, dtype=float).copy()
    v = np.ones_like(y) / math.sqrt(y.size)  # in scaled coordinates y / scale
    logs = np.empty(n_blocks * int(block))
    n_run = int(align) + logs.size
    phis = None
    if used == "exact" and contact_exact_applies(model):  # one walk, a sensitivity per period
        fm = model.mesh_frequency
        walked = walk(model, y, n_run / fm, marks=np.arange(1, n_run) / fm)
        phis, y = walked.mark_sensitivities(), walked.end
    for k in range(n_run):
        if phis is None:
            y, phi = integrate_with_sensitivity(model, y, mesh_period, rtol, used)
        else:
            phi = phis[k]
        v = (phi @ (v * scale)) / scale
        g = float(np.linalg.norm(v))
        v = v / g
        if k >= align:
            logs[k - align] = math.log(g)
    per_block = logs.reshape(n_blocks, int(block)).sum(axis=1) / (int(block) * mesh_period)
    return LyapunovEstimate(
        value=float(np.mean(per_block)),
        error=float(np.std(per_block, ddof=1) / math.sqrt(n_blocks)),
        blocks=per_block, periods=int(logs.size), mesh_period=mesh_period, route=used,
        y_end=y)
