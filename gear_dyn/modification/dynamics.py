"""Tip relief in the single-DOF model: load-dependent stiffness plus the relief's TE.

The loaded-contact analysis (:mod:`.contact`) at the operating load gives, over one mesh cycle,
the tangent stiffness ``k_t(p)`` (sum of the loaded pairs) and the transmission error the relief
adds, ``e(p)``; the single-DOF model ``m x'' + c (x' - e') + k_t(p) (x - e) = W`` then has the
loaded static transmission error ``delta(p)`` as its quasi-static solution. Alternatively
(``linearisation="secant"``) the model gets the seed's ``K_TPM = F / delta`` and no ``e``: the same
static solution, with the secant instead of the incremental stiffness (for comparison only).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..geometry import GearPair
from ..models.sdof import SDOFModel, sdof_from_pair
from .contact import LoadedContact, loaded_contact
from .relief import ProfileModification

FloatArray = NDArray[np.float64]

#: single-pair stiffness methods usable for the loaded contact
PAIR_METHODS: tuple[str, ...] = ("potential_energy", "weber")
LINEARISATIONS: tuple[str, ...] = ("tangent", "secant")


def _pem(pair: GearPair, s: ArrayLike) -> FloatArray:
    from ..stiffness.potential_energy import potential_energy_pair_stiffness

    return potential_energy_pair_stiffness(pair, s)


def _weber(pair: GearPair, s: ArrayLike) -> FloatArray:
    from ..stiffness.weber import weber_pair_stiffness

    return weber_pair_stiffness(pair, s)


def pair_stiffness_function(pair: GearPair, method: str = "potential_energy") -> Callable[
        [FloatArray], FloatArray]:
    """The unmodified single-pair stiffness ``K(s)`` (N/m, s in m from T1) of a method.

    Parameters
    ----------
    pair : GearPair
    method : str
        ``"potential_energy"`` (Hertz, bending, shear, axial, fillet foundation; seed 001 eq. 5)
        or ``"weber"`` (seed 002).

    Raises
    ------
    InputError
        Unknown method.
    """
    funcs = {"potential_energy": _pem, "weber": _weber}
    if method not in funcs:
        raise InputError(
            f"pair stiffness method = {method!r}: valid values are {', '.join(PAIR_METHODS)}")
    return partial(funcs[method], pair)


def relief_sdof(
    pair: GearPair,
    speed: float,
    torque: float,
    modification: ProfileModification | None,
    pair_stiffness: Callable[[FloatArray], FloatArray],
    damping_ratio: float = 0.06,
    inertias: tuple[float, float] | None = None,
    linearisation: str = "tangent",
    samples_per_segment: int = 48,
) -> tuple[SDOFModel, LoadedContact]:
    """Single-DOF model of a spur pair with tip relief at its operating load.

    Parameters
    ----------
    pair : GearPair
        Spur pair.
    speed : float
        Pinion speed in rad/s (> 0).
    torque : float
        Pinion torque in N m (> 0).
    modification : ProfileModification or None
        Tip reliefs (None: the unmodified pair through the same machinery).
    pair_stiffness : callable
        Unmodified single-pair stiffness ``K(s)`` in N/m.
    damping_ratio : float
        Mesh damping ratio xi.
    inertias : (float, float) or None
        (I1, I2) in kg m^2; None uses solid blanks.
    linearisation : str
        ``"tangent"`` (default: k_t and e) or ``"secant"`` (K_TPM, no e).
    samples_per_segment : int
        Loaded-contact samples per segment between switching phases.

    Returns
    -------
    (SDOFModel, LoadedContact)

    Raises
    ------
    InputError
        Bad parameters (see :func:`~gear_dyn.modification.contact.loaded_contact` and
        :func:`~gear_dyn.models.sdof.sdof_from_pair`).
    """
    if linearisation not in LINEARISATIONS:
        raise InputError(f"linearisation = {linearisation!r}: valid values are "
                         f"{', '.join(LINEARISATIONS)}")
    lc = loaded_contact(pair, pair_stiffness, torque, modification, samples_per_segment)
    if linearisation == "secant":
        model = sdof_from_pair(pair, speed, torque, lc.mesh_stiffness(), damping_ratio,
                               inertias)
    else:
        te = lc.transmission_error() if modification is not None and not modification.is_zero \
            else None
        model = sdof_from_pair(pair, speed, torque, lc.tangent_stiffness(), damping_ratio,
                               inertias, transmission_error=te)
    return model, lc
