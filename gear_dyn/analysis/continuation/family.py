"""The one-parameter family of single-DOF mesh models that a branch follows.

A family is a callable ``value -> model`` (value in SI units of the parameter), like the sweep's
model factory (:mod:`gear_dyn.analysis.sweep`); the scene layer's
:class:`gear_dyn.scene.sweep.SceneModels` is one in pinion speed. :func:`sdof_family` makes one
from a single model for the parameters a designer varies: pinion speed, torque, damping ratio
or backlash.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, cast

from gear_dyn.errors import InputError, check_range
from gear_dyn.models.base import MeshModel, at_speed, at_torque

#: parameters :func:`sdof_family` varies, and their SI units
PARAMETERS: dict[str, str] = {
    "speed": "rad/s", "torque": "N*m", "damping_ratio": "", "backlash": "m",
}


@dataclass(frozen=True)
class SDOFFamily:
    """``SDOFFamily(model, parameter, factor)(value)``: ``model`` with one field set from
    ``value`` (see :func:`sdof_family`; ``factor`` is the pinion teeth z1 for ``speed``, one
    over the base radius r_b1 for ``torque``). Picklable when the model is."""

    model: Any
    parameter: str
    factor: float = 1.0

    @property
    def mesh_frequency_only(self) -> bool:
        """True for ``speed``: the models differ only in the mesh frequency, proportional
        to the value (``model.at_mesh_frequency``), so the continuation takes the shooting
        map's exact speed derivative (:mod:`.shooting`)."""
        return self.parameter == "speed"

    def __call__(self, value: float) -> MeshModel:
        """The model at ``value`` (SI unit of the parameter, :data:`PARAMETERS`)."""
        if self.parameter == "speed":  # the one rule of the model at a speed
            model = at_speed(self.model, int(self.factor), value)
            if model is None:
                raise InputError(f"sdof_family: a {type(self.model).__name__} cannot change "
                                 "speed alone; use the scene's model factory")
            return cast(MeshModel, model)
        if self.parameter == "torque":  # the one rule of the model at a torque
            return cast(MeshModel, at_torque(self.model, value, self.factor))
        if self.parameter == "damping_ratio":
            return replace(self.model, damping_ratio=value)
        return replace(self.model, backlash=value)


def sdof_family(model: MeshModel, parameter: str, *, teeth: int | None = None,
                base_radius: float | None = None) -> SDOFFamily:
    """The family ``value -> model`` varying one parameter of a single-DOF model.

    Parameters
    ----------
    model : SDOFModel
        The model at any value of the parameter (the other fields are kept).
    parameter : str
        ``speed`` (pinion speed in rad/s: ``f_m = teeth * speed / (2 pi)``), ``torque``
        (pinion torque in N m: ``W = torque / base_radius``), ``damping_ratio`` (-) or
        ``backlash`` (half gap in m).
    teeth : int or None
        Pinion teeth z1; needed for ``speed``.
    base_radius : float or None
        Pinion base radius r_b1 in m; needed for ``torque``.

    Returns
    -------
    SDOFFamily

    Raises
    ------
    InputError
        An unknown parameter, a missing ``teeth`` or ``base_radius``, or ``backlash`` for a
        model without backlash.

    See Also
    --------
    :func:`~gear_dyn.analysis.continuation.arclength.continue_orbits`
        Follows the orbits of the family.
    :class:`~gear_dyn.analysis.continuation.fold_curve.SpeedTorqueFamily`
        The family over speed and torque.
    :class:`~gear_dyn.models.sdof.SDOFModel` : The models.

    Examples
    --------
    >>> from gear_dyn import SDOFModel, rectangular_stiffness
    >>> m = SDOFModel(1.0, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 1000.0,
    ...               backlash=1e-5)
    >>> sdof_family(m, "speed", teeth=20)(100.0).mesh_frequency  # 20 * 100 / (2 pi) Hz
    318.3098861837907
    """
    if parameter not in PARAMETERS:
        raise InputError(f"parameter = {parameter!r}: valid choices are "
                         f"{', '.join(PARAMETERS)}")
    if parameter == "speed":
        if teeth is None:
            raise InputError("sdof_family(parameter='speed') needs teeth (pinion teeth z1)")
        check_range("teeth", teeth, "", low=1, high=10000)
        return SDOFFamily(model, parameter, int(teeth))
    if parameter == "torque":
        if base_radius is None:
            raise InputError("sdof_family(parameter='torque') needs base_radius (m)")
        check_range("base_radius", base_radius, "m", low=0.0, low_open=True)
        return SDOFFamily(model, parameter, 1.0 / base_radius)
    if parameter == "backlash" and model.backlash is None:
        raise InputError("parameter = 'backlash': the model has no backlash to vary")
    return SDOFFamily(model, parameter)
