"""Stability charts of the linear single-DOF mesh model.

:func:`stability_chart` maps the largest Floquet multiplier modulus over a grid of mesh frequency
and stiffness variation (or damping) for the linear model, with the monodromy matrix of a
staircase of the stiffness (exact for a rectangular wave) from the solvers' closed-form 2x2
exponentials (:func:`gear_dyn.solvers.linear_maps.cell_monodromy`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.analysis.stability import _require_sdof, floquet_stable
from gear_dyn.errors import InputError
from gear_dyn.models.base import MeshModel
from gear_dyn.solvers.linear_maps import cell_monodromy

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


def staircase(model: MeshModel, pieces: int = 128) -> tuple[FloatArray, FloatArray]:
    """Piecewise-constant form of the model's stiffness over one mesh cycle.

    Exact (the stiffness's own segments) where the stiffness is piecewise constant; otherwise
    ``pieces`` cells (cut also at the switching phases), each at its mean value by Simpson's
    rule. The Floquet multipliers of the staircase converge to the true ones as ``pieces**-2``.

    Returns
    -------
    edges : ndarray
        Cell edges in mesh cycles, 0..1.
    values : ndarray
        Stiffness of each cell in N/m.
    """
    seg = model.stiffness.segments()
    if seg is not None:
        return seg
    edges = np.union1d(np.linspace(0.0, 1.0, pieces + 1),
                       np.mod(model.stiffness.switching_phases, 1.0))
    lo, hi = edges[:-1], edges[1:]
    eps = 1e-12
    k = model.stiffness
    vals = (np.asarray(k(lo + eps)) + 4 * np.asarray(k(0.5 * (lo + hi)))
            + np.asarray(k(hi - eps))) / 6
    return edges, vals


def spectral_radius_grid(mass: float, edges: FloatArray, values: FloatArray,
                         damping: FloatArray, mesh_frequency: FloatArray) -> FloatArray:
    """Largest Floquet multiplier modulus of ``m x'' + c x' + k(f_m t) x = 0``, vectorised.

    Parameters
    ----------
    mass : float
        m_e in kg.
    edges : ndarray (S+1,)
        Cell edges of a piecewise-constant stiffness in mesh cycles, 0..1.
    values : ndarray (..., S)
        Stiffness of each cell in N/m; leading axes broadcast with ``damping`` and
        ``mesh_frequency``.
    damping : ndarray (...)
        c in N s/m.
    mesh_frequency : ndarray (...)
        f_m in Hz.

    Returns
    -------
    ndarray (...)
        Spectral radius of the monodromy matrix (> 1: parametrically unstable).
    """
    p11, p12, p21, p22 = cell_monodromy(mass, edges, values, damping, mesh_frequency)
    tr = p11 + p22
    det = p11 * p22 - p12 * p21
    disc = np.sqrt((0.25 * tr**2 - det).astype(np.complex128))
    lam1 = np.abs(0.5 * tr + disc)
    lam2 = np.abs(0.5 * tr - disc)
    return np.asarray(np.maximum(lam1, lam2), dtype=float)


@dataclass(frozen=True, eq=False)
class StabilityChart:
    """Largest Floquet multiplier modulus over mesh frequency and a second parameter.

    Attributes
    ----------
    frequency_ratio : ndarray (nf,)
        f_m / f_n (f_n = sqrt(k_m / m_e) / 2 pi).
    parameter : ndarray (np,)
        Values of the second axis: relative stiffness variation (k_max - k_min) / (2 k_m)
        or damping ratio.
    parameter_name : str
        ``stiffness_variation`` or ``damping_ratio``.
    spectral_radius : ndarray (np, nf)
        > 1: parametrically unstable.
    scene_value : float
        The model's own value of the second parameter.
    natural_frequency : float
        f_n in Hz.
    """

    frequency_ratio: FloatArray
    parameter: FloatArray
    parameter_name: str
    spectral_radius: FloatArray
    scene_value: float
    natural_frequency: float


def relative_variation(values: FloatArray, mean: float) -> float:
    """(k_max - k_min) / (2 k_m) of a staircase stiffness."""
    return float((np.max(values) - np.min(values)) / (2 * mean))


def stability_chart(
    model: MeshModel, frequency_ratio: FloatArray, parameter: FloatArray,
    parameter_name: str = "stiffness_variation", pieces: int = 128,
) -> StabilityChart:
    """Stability chart of the linear single-DOF model (backlash, if any, ignored: full contact).

    Parameters
    ----------
    model : MeshModel
        Its stiffness shape, mass, mean stiffness and damping ratio define the chart.
    frequency_ratio : array_like
        f_m / f_n values (> 0).
    parameter : array_like
        For ``stiffness_variation``: relative variation eps = (k_max - k_min) / (2 k_m) (>= 0),
        the stiffness is ``k_m + (eps / eps_0) (k(p) - k_m)`` with eps_0 the model's own
        (values that would make k negative are refused). For ``damping_ratio``: xi (>= 0).
    parameter_name : {"stiffness_variation", "damping_ratio"}
    pieces : int
        Staircase cells for a stiffness that is not piecewise constant.

    Raises
    ------
    InputError
        Bad axis values, or a constant stiffness asked for a variation chart.
    """
    model = _require_sdof(model)
    ratio = np.asarray(frequency_ratio, dtype=float)
    par = np.asarray(parameter, dtype=float)
    if ratio.ndim != 1 or np.any(~np.isfinite(ratio)) or np.any(ratio <= 0):
        raise InputError("stability chart: frequency ratios must be finite and > 0")
    if par.ndim != 1 or np.any(~np.isfinite(par)) or np.any(par < 0):
        raise InputError(f"stability chart: {parameter_name} values must be finite and >= 0")
    edges, vals = staircase(model, pieces)
    k_m = float(np.sum(vals * np.diff(edges)))
    eps0 = relative_variation(vals, k_m)
    fn = math.sqrt(k_m / model.mass) / (2 * math.pi)
    fm = ratio * fn
    if parameter_name == "stiffness_variation":
        if eps0 <= 0:
            raise InputError("stability chart over stiffness variation: the stiffness is "
                             "constant, so there is no variation to scale")
        alpha = par / eps0
        k = k_m + alpha[:, None] * (vals - k_m)[None, :]
        if np.any(k < 0):
            top = float(k_m / (k_m - np.min(vals)) * eps0)
            raise InputError(f"stability chart: stiffness_variation up to {top:.4g} keeps the "
                             "stiffness >= 0; got more")
        rho = spectral_radius_grid(model.mass, edges, k[:, None, :], np.asarray(model.damping),
                                   fm[None, :])
        scene_value = eps0
    elif parameter_name == "damping_ratio":
        c = 2 * par * math.sqrt(model.mass * k_m)
        rho = spectral_radius_grid(model.mass, edges, vals, c[:, None], fm[None, :])
        scene_value = model.damping_ratio
    else:
        raise InputError(f"stability chart parameter {parameter_name!r}: valid choices are "
                         "'stiffness_variation', 'damping_ratio'")
    return StabilityChart(ratio, par, parameter_name, rho, scene_value, fn)


def sweep_charts(model: MeshModel, ratio_lo: float, ratio_hi: float, which: str = "both"
                 ) -> list[StabilityChart]:
    """The stability charts drawn beside a sweep over frequency ratios ``ratio_lo..ratio_hi``.

    ``which``: ``stiffness`` (over the stiffness variation, up to twice the model's own),
    ``damping`` (over the damping ratio), ``both`` or ``none``. The frequency-ratio axis spans
    the sweep with a margin and at least 0.02..2.5 (the principal instability region).
    """
    if which == "none":
        return []
    grid = np.linspace(max(0.02, 0.9 * ratio_lo), max(1.1 * ratio_hi, 2.5), 300)
    charts = []
    _, vals = staircase(model)
    k_m = float(model.mean_stiffness or np.mean(vals))
    eps0 = relative_variation(vals, k_m)
    if which in ("stiffness", "both") and eps0 > 0:
        top = min(2 * eps0, 0.999 * k_m / (k_m - float(np.min(vals))) * eps0)
        charts.append(stability_chart(model, grid, np.linspace(0, top, 120)))
    if which in ("damping", "both"):
        charts.append(stability_chart(
            model, grid, np.linspace(0, max(3 * model.damping_ratio, 0.2), 120),
            parameter_name="damping_ratio"))
    return charts


def chart_summary(charts: list[StabilityChart]) -> dict[str, Any]:
    """Per chart parameter: the scene's value and the unstable share of the chart."""
    return {ch.parameter_name: {
        "scene_value": ch.scene_value,
        "unstable_share_of_chart": float(np.mean(~floquet_stable(ch.spectral_radius)))}
            for ch in charts}
