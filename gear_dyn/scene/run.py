"""Run a scene: build its plan, simulate it with the run's checks, attach what the scene says.

The step above :mod:`gear_dyn.scene.build`: it adds the simulation
(:func:`gear_dyn.analysis.study.simulate`) and the ISO 6336-1 K_v beside it (:mod:`.iso`).
"""

from __future__ import annotations

from typing import Any

from gear_dyn.analysis.dynamic_factor import quasi_static_model_of
from gear_dyn.analysis.study import simulate
from gear_dyn.errors import InputError
from gear_dyn.scene.build import build_model, build_pair, build_plan, scene_facts
from gear_dyn.scene.deviations import deviations_summary
from gear_dyn.scene.hints import backlash_gap_hint
from gear_dyn.scene.iso import iso_kv_summary
from gear_dyn.scene.operating import check_keywords, with_operating
from gear_dyn.scene.validated import Scene, scene_error
from gear_dyn.solvers import Result

#: the ``[solver]`` values a run may override (as the CLI's flags do)
RUN_SOLVER_OVERRIDES = ("method", "rtol", "atol", "periods", "steady_periods",
                        "samples_per_period", "max_nfev")
#: every keyword of :func:`run_scene`
RUN_KEYWORDS = ("speed", "torque", "si", *RUN_SOLVER_OVERRIDES)


def run_scene(scene: Scene, speed: Any = None, torque: Any = None, *, si: bool = False,
              **solver: Any) -> Result:
    """Build and simulate a scene, optionally at another speed or torque.

    The Result carries the scene and, in ``extra``, what the scene says about the case
    (:func:`~gear_dyn.scene.build.scene_facts`: speeds, contact ratio, backlash, ...) and
    ``iso_6336_kv``, the ISO 6336-1 method B K_v at the same speed (:mod:`gear_dyn.scene.iso`).

    Parameters
    ----------
    scene : Scene
        From :func:`~gear_dyn.scene.load_scene` or :func:`~gear_dyn.scene.parse_scene`.
    speed : str or float, optional
        Pinion speed replacing ``[operating] speed``, with its unit as in a scene file
        (``"6000 rpm"``, ``"628 rad/s"``); a plain number only with ``si=True`` (rad/s).
    torque : str or float, optional
        Pinion torque replacing ``[operating] torque`` (``"200 Nm"``; N m with ``si=True``).
    si : bool
        Plain numbers for ``speed`` and ``torque`` are SI values (rad/s, N m).
    **solver
        ``[solver]`` overrides: ``method``, ``rtol``, ``atol``, ``periods``, ``steady_periods``,
        ``samples_per_period`` (None keeps the scene's value), and ``max_nfev`` (the work
        budget of a solve_ivp run, :class:`~gear_dyn.solvers.SolverSettings`).

    Returns
    -------
    Result
        The run, with the scene and its facts in ``extra``.

    Raises
    ------
    InputError
        An unknown keyword (with the closest valid one), a plain number for ``speed`` or
        ``torque`` without ``si=True``, a bad unit or a value out of range (as the scene's
        ``[operating]`` keys), bad solver overrides.
    SolverError
        The integration failed.

    See Also
    --------
    :func:`~gear_dyn.scene.load_scene` : Loads the scene.
    :func:`~gear_dyn.scene.sweep.sweep_scene` : The scene over a range of speeds.
    :func:`~gear_dyn.analysis.study.simulate` : The model-level run.

    Examples
    --------
    >>> import gear_dyn as gd
    >>> scene = gd.load_scene("helicopter_tail")
    >>> res = gd.run_scene(scene, speed="1000 rpm", periods=20)
    >>> round(res.extra["input_speed_rpm"])
    1000
    >>> gd.run_scene(scene, sped="1000 rpm")
    Traceback (most recent call last):
    ...
    gear_dyn.errors.InputError: run_scene: unknown keyword 'sped'; did you mean 'speed'? ...
    """
    check_keywords("run_scene", solver, RUN_KEYWORDS)
    scene = with_operating(scene, speed, torque, si=si, function="run_scene")
    plan = build_plan(scene, **solver)
    pair = build_pair(scene)  # once: the facts, K_v and deviations below read it
    iso_kv = iso_kv_summary(scene, pair)  # before the run: a bad [iso] table fails fast
    try:
        # the dynamic factor's reference, as a sweep takes it: the scene rebuilt at the
        # quasi-static speed where more than f_m depends on speed (eccentric kinematics)
        quasi_static = quasi_static_model_of(
            lambda s: build_model(with_operating(scene, s, si=True)),
            scene.tables["operating"]["speed"], plan.model)
        result = simulate(plan.model, plan.t_end, plan.settings, plan.steady_start, scene=scene,
                          quasi_static=quasi_static)
    except InputError as exc:  # e.g. a run too long for the solver: name the file
        raise scene_error(scene.source, exc) from None
    for key, value in scene_facts(scene, pair).items():
        result.extra.setdefault(key, value)  # the model's own figures take precedence
    result.extra.setdefault("iso_6336_kv", iso_kv)
    contact = result.extra.get("contact") or {}
    hint = backlash_gap_hint(scene, contact.get("separation_share", 0.0) > 0)
    if hint is not None:
        result.extra.setdefault("warnings", []).append(hint)
    if (dev := deviations_summary(scene, pair)) is not None:
        result.extra.setdefault("deviations", dev)
    return result
