"""The one face every dynamic model offers (docs/architecture.md, "The Model protocol"): callers
ask, never test a class.

A model is an object with:

Identity and scales
    ``state_labels`` (names of the states), ``output_names`` (names of ``outputs``),
    ``mesh_frequency`` (Hz), ``static_load`` (W in N), ``state_scale`` (typical magnitude of each
    state, SI: absolute tolerances and relative error figures), ``natural_frequency`` (Hz of the
    mesh mode, or None), ``mean_stiffness`` (N/m, or None).
Capabilities
    ``is_linear``: the right-hand side is affine in the state (no contact loss, no backlash);
    ``mesh_periodic``: the model is the single-DOF mesh equation
    ``m x'' + c (x' - e') + k(p) f(x - e) = W`` with coefficients periodic in the mesh period
    (it then also offers ``mass``, ``damping``, ``stiffness``, ``transmission_error``,
    ``phase0`` and ``phase(t)``: see :class:`MeshModel`), and its transmission error repeats
    every mesh period (manufacturing deviations, which repeat over the hunting period, make it
    False); the periodic steady state, the Floquet multipliers and the stability chart apply;
    ``backlash``: the half gap in m, or None;
    ``linear_segments(t0, t1)``: for a linear model with piecewise-constant coefficients, the
    pieces ``(t_start, t_end, A, g)`` with ``y' = A y + g``; None otherwise (exact propagation);
    ``contact_events()``: scalar functions ``g(t, y)`` whose zeros are contact changes (the
    solver restarts there); empty when there are none;
    ``at_mesh_frequency(f)``: the same model at another mesh frequency when nothing else depends
    on speed; None when it has to be rebuilt from its parameters.
    Optional: ``force_form(t)``: for models ``q' = v``, ``v' = u(t) F + g_v`` with one scalar
    force ``F = f(t) . y + f0(t)`` (affine while a condition on F holds), the arrays
    ``(u, f, f0, g_v)`` at many times, or None; the ``gauss`` solver uses it
    (:mod:`gear_dyn.solvers.gauss`; the torsional model offers it).
Dynamics
    ``initial_state()``, ``rhs(t, y)``, ``jac(t, y)``, ``switching_times(t0, t1)`` (instants where
    the right-hand side jumps; the solver never steps across them), ``outputs(t, y)`` (derived
    series from states shaped (n_states, n_times)), ``summary_info()`` (model constants for the
    run summary, SI units in the key names).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import fields, is_dataclass, replace
from typing import Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError
from gear_dyn.geometry import check_speed, check_torque, teeth_mesh_frequency

FloatArray = NDArray[np.float64]
EventFn = Callable[[float, FloatArray], float]
Segment = tuple[float, float, FloatArray, FloatArray]


@runtime_checkable
class Model(Protocol):
    """Structural type of a gear_dyn dynamic model (see the module docstring)."""

    @property
    def state_labels(self) -> tuple[str, ...]: ...

    @property
    def output_names(self) -> tuple[str, ...]: ...

    @property
    def mesh_frequency(self) -> float: ...

    @property
    def static_load(self) -> float: ...

    @property
    def state_scale(self) -> FloatArray: ...

    @property
    def natural_frequency(self) -> float | None: ...

    @property
    def mean_stiffness(self) -> float | None: ...

    @property
    def is_linear(self) -> bool: ...

    @property
    def mesh_periodic(self) -> bool: ...

    @property
    def backlash(self) -> float | None: ...

    def initial_state(self) -> FloatArray: ...

    def rhs(self, t: float, y: FloatArray) -> FloatArray: ...

    def jac(self, t: float, y: FloatArray) -> FloatArray: ...

    def switching_times(self, t0: float, t1: float) -> FloatArray: ...

    def linear_segments(self, t0: float, t1: float) -> list[Segment] | None: ...

    def contact_events(self) -> list[EventFn]: ...

    def at_mesh_frequency(self, mesh_frequency: float) -> Model | None: ...

    def outputs(self, t: FloatArray, y: FloatArray) -> dict[str, FloatArray]: ...

    def summary_info(self) -> dict[str, Any]: ...


@runtime_checkable
class MeshModel(Model, Protocol):
    """A model with ``mesh_periodic`` True: the single-DOF mesh equation's coefficients."""

    @property
    def mass(self) -> float: ...

    @property
    def damping(self) -> float: ...

    @property
    def damping_ratio(self) -> float: ...

    @property
    def stiffness(self) -> Any: ...

    @property
    def transmission_error(self) -> Any: ...

    @property
    def phase0(self) -> float: ...

    def phase(self, t: Any) -> Any: ...


class ModelDefaults:
    """Conservative answers to the capability questions, for a model written by hand.

    Subclass it and define the dynamics (``state_labels``, ``mesh_frequency``, ``static_load``,
    ``state_scale``, ``initial_state``, ``rhs``, ``jac``, ``switching_times``, ``outputs``); the
    capabilities default to "no": nonlinear, not mesh-periodic, no backlash, no exact pieces,
    no contact events, rebuilt at a new speed. Override what your model can do.
    """

    is_linear: bool = False
    mesh_periodic: bool = False
    backlash: float | None = None
    natural_frequency: float | None = None
    mean_stiffness: float | None = None

    @property
    def output_names(self) -> tuple[str, ...]:
        """Names of ``outputs`` (evaluated once at the initial state)."""
        y0 = self.initial_state()  # type: ignore[attr-defined]
        return tuple(self.outputs(np.zeros(1), np.asarray(y0)[:, None]))  # type: ignore[attr-defined]

    def linear_segments(self, t0: float, t1: float) -> list[Segment] | None:
        """None: not known to be linear with piecewise-constant coefficients."""
        del t0, t1
        return None

    def contact_events(self) -> list[EventFn]:
        """No contact changes."""
        return []

    def at_mesh_frequency(self, mesh_frequency: float) -> Model | None:
        """None: rebuild the model at another speed."""
        del mesh_frequency
        return None

    def summary_info(self) -> dict[str, Any]:
        """No model constants to report."""
        return {}


def at_speed(model: Model, teeth: int, speed: float) -> Model | None:
    """The one rule for a model at another pinion speed: ``speed`` in rad/s checked
    (:func:`gear_dyn.geometry.check_speed`), its mesh frequency ``f_m = z1 w / (2 pi)``
    (:func:`gear_dyn.geometry.teeth_mesh_frequency`, ``teeth`` = z1) and
    ``model.at_mesh_frequency(f_m)``: None where more than f_m depends on speed and the model
    has to be rebuilt from its parameters (:class:`gear_dyn.scene.sweep.SceneModels` rebuilds
    the scene's).

    Raises
    ------
    InputError
        A speed out of range.

    Examples
    --------
    >>> from gear_dyn import SDOFModel, rectangular_stiffness
    >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
    >>> round(at_speed(m, 20, 100.0).mesh_frequency, 6)  # 20 * 100 / (2 pi) Hz
    318.309886
    """
    return model.at_mesh_frequency(teeth_mesh_frequency(teeth, check_speed(speed)))


def at_torque(model: Any, torque: float, reference_load: float,
              reference_torque: float = 1.0) -> Any:
    """The one rule for a model at another pinion torque: ``torque`` in N m checked
    (:func:`gear_dyn.geometry.check_torque`) and the static load, proportional to the torque,
    ``W = reference_load * torque / reference_torque`` in N (W = T / r_b1: ``reference_load``
    ``1 / r_b1`` per N m, or the load ``W_ref`` at ``reference_torque`` T_ref), set on the
    model, whose other fields are kept (only W depends on torque in the single-DOF model: its
    stiffness is the model's own).

    Raises
    ------
    InputError
        A torque out of range, or a model without a ``static_load`` field (only the
        single-DOF mesh model changes torque alone; rebuild others from the scene).

    Examples
    --------
    >>> from gear_dyn import SDOFModel, rectangular_stiffness
    >>> m = SDOFModel(0.5, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 500.0)
    >>> at_torque(m, 120.0, 500.0, 20.0).static_load  # 500 N at 20 N m: 3000 N at 120 N m
    3000.0
    """
    check_torque(torque)
    if (isinstance(model, type) or not is_dataclass(model)
            or "static_load" not in {f.name for f in fields(model)}):
        raise InputError(f"a model at another torque needs a static_load field (the "
                         f"single-DOF mesh model); got {type(model).__name__}")
    same: Any = model  # (is_dataclass narrows ``model`` to a class or an instance)
    return replace(same, static_load=reference_load * torque / reference_torque)
