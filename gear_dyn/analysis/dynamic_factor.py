"""The dynamic factor like for like with ISO 6336-1 K_v, and the stiffness-jump overshoot.

Definitions (docs/dynamic_factor.md):

- **peak force ratio** ``F_max / W``: the peak dynamic mesh force over the steady window over
  the static load W = T1 / r_b1 (:attr:`gear_dyn.solvers.result.Result.peak_force_ratio`).
- **quasi-static peak ratio** ``F_qs,max / W``: the same figure from a quasi-static run of the
  same model (same k(t), transmission error, damping and load) at a mesh frequency far below
  the natural frequency, ``f_m = QS_SPEED_RATIO f_n``. With a constant load the quasi-static
  mesh force is W at every phase where k(t) and e(t) change slowly; it exceeds W only where they
  jump (the rectangular ISO 6336-1 wave: from one to two pairs in contact, the force jumps by
  k_double / k_single = 1.75 while the deflection cannot follow). That excess is the
  **stiffness-jump overshoot**; it is present at every speed, however slow.
- **dynamic factor** ``K_dyn = F_max / F_qs,max``: the ratio of the maximum dynamic mesh force
  to the maximum quasi-static mesh force of the same model, the force-based dynamic factor of
  Tamminana, Kahraman & Vijayakar (2007). It tends to 1 as the speed goes to 0 for every
  stiffness model, as ISO 6336-1 K_v does, so the two compare like for like; the peak force
  ratio is their product with the overshoot, ``F_max / W = K_dyn x F_qs,max / W``.

Why the reference is a run and not ``x_s = W / k(phase)``, and what the quasi-static run's
stated error is made of (residual dynamics, the ring-down of one jump at the next, the sampling
of the peak): docs/dynamic_factor.md.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from gear_dyn.models.base import Model
from gear_dyn.solvers import Result, SolverSettings, simulate_bare

#: f_m / f_n of the quasi-static run: 64 natural periods per mesh period
QS_SPEED_RATIO = 1 / 64
#: output samples per natural period in the quasi-static run (the peak's sampling error); with
#: QS_SPEED_RATIO, 4096 samples per mesh period, the most a run takes (solvers.settings)
QS_SAMPLES_PER_NATURAL_PERIOD = 64
#: mesh periods of the quasi-static run; the last half is measured (the start transient rings
#: down over 1 / (zeta 2 pi f_n), a small part of one mesh period at QS_SPEED_RATIO)
QS_PERIODS = 4

#: what the dynamic factor is (summary.json ``dynamic_factor_definition``, terminal output)
DYNAMIC_FACTOR_DEFINITION = (
    "K_dyn = peak dynamic mesh force / peak quasi-static mesh force of the same model (a run at "
    f"f_m = f_n / {1 / QS_SPEED_RATIO:.0f}); tends to 1 at low speed, like ISO 6336-1 K_v "
    "(Tamminana, Kahraman & Vijayakar 2007)")
#: what the stiffness-jump overshoot is (summary.json ``stiffness_jump_definition``)
STIFFNESS_JUMP_DEFINITION = (
    "peak quasi-static mesh force / W: the force overshoot at the jumps of k(t) (and of the "
    "transmission error), present at any speed; 1 for a smooth k(t)")


def quasi_static_model(model: Model) -> Model | None:
    """``model`` at the quasi-static mesh frequency ``QS_SPEED_RATIO f_n``, or None where the
    model cannot change its speed alone (``at_mesh_frequency`` returns None) or states no f_n."""
    fn = model.natural_frequency
    if fn is None or not math.isfinite(fn) or fn <= 0:
        return None
    return model.at_mesh_frequency(QS_SPEED_RATIO * fn)


def quasi_static_model_of(factory: Callable[[float], Model], speed: float,
                          model: Model) -> Model | None:
    """The quasi-static model of a model factory ``speed -> Model`` (a sweep's): ``model``
    (``factory(speed)``, ``speed`` in rad/s) at the mesh frequency ``QS_SPEED_RATIO f_n``, or,
    where the model cannot change its speed alone (eccentric kinematics change with it), the
    factory's model at the pinion speed of that mesh frequency; None without f_n.

    The quasi-static peak force does not depend on the speed the model was built at, so one
    reference serves every speed of a sweep.
    """
    qs = quasi_static_model(model)
    fn = model.natural_frequency
    if qs is not None or fn is None or not math.isfinite(fn) or fn <= 0:
        return qs
    return factory(speed * QS_SPEED_RATIO * fn / model.mesh_frequency)


def quasi_static_reference(model: Model, settings: SolverSettings) -> dict[str, Any]:
    """The quasi-static run of ``model`` (already at its quasi-static mesh frequency) and its
    peak force ratio.

    Parameters
    ----------
    model : Model
        At a mesh frequency far below f_n (:func:`quasi_static_model`, or the scene's model
        rebuilt at a low speed).
    settings : SolverSettings
        The run's method and tolerances; the sampling is raised to resolve the peak.

    Returns
    -------
    dict
        ``peak_force_ratio`` (F_qs,max / W), ``speed_ratio`` (f_m / f_n of the run),
        ``mesh_frequency_hz``, ``estimated_error`` (relative, of the peak ratio:
        docs/dynamic_factor.md), ``run_time_s``.

    Raises
    ------
    SolverError
        The integration failed.
    """
    fm, fn = model.mesh_frequency, model.natural_frequency or math.nan
    spp = min(max(settings.samples_per_period,
                  int(math.ceil(QS_SAMPLES_PER_NATURAL_PERIOD * fn / fm))), 4096)
    qs_settings = replace(settings, samples_per_period=spp)
    res = simulate_bare(model, QS_PERIODS / fm, qs_settings, (QS_PERIODS // 2) / fm)
    force = res.outputs["mesh_force"][res.steady]
    ratio = float(np.max(force) / res.static_load)
    zeta = float(getattr(model, "damping_ratio", 0.05) or 0.05)
    over = max(ratio - 1.0, 0.0)
    err = ((fm / fn) ** 2 + over * (math.pi / QS_SAMPLES_PER_NATURAL_PERIOD) ** 2 / 2
           + over * math.exp(-zeta * 2 * math.pi * 0.25 * fn / fm))
    return {"peak_force_ratio": ratio, "speed_ratio": fm / fn, "mesh_frequency_hz": fm,
            "estimated_error": err, "run_time_s": res.stats.run_time_s}


def dynamic_factor_figures(result: Result, reference: dict[str, Any] | None) -> dict[str, Any]:
    """``dynamic_factor`` (K_dyn), ``peak_force_ratio`` and ``stiffness_jump_factor`` of a run.

    ``reference``: :func:`quasi_static_reference` of the same model, or None (then K_dyn is
    NaN: no like-for-like figure without the quasi-static peak).
    """
    peak = result.peak_force_ratio
    if reference is None:
        return {"peak_force_ratio": peak, "dynamic_factor": math.nan}
    qs = float(reference["peak_force_ratio"])
    return {"peak_force_ratio": peak, "dynamic_factor": peak / qs, "stiffness_jump_factor": qs,
            "quasi_static": dict(reference)}
