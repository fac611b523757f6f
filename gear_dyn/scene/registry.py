"""Registries that let each part of the toolkit declare its scene table and model builder.

A feature module (eccentricity, tip relief, ...) declares its own
:class:`~gear_dyn.scene.fields.Section` and calls
:func:`register_section`; a model kind registers a builder with :func:`register_model`. The
scene loader (:mod:`gear_dyn.scene.loader`) imports every module that declares a table.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from gear_dyn.errors import InputError
from gear_dyn.scene.fields import Section

#: scene tables by name, as :func:`register_section` added them
SECTIONS: dict[str, Section] = {}
#: model builders by ``[scene] model`` name, as :func:`register_model` added them
MODEL_BUILDERS: dict[str, Callable[[Any], Any]] = {}


def register_section(section: Section) -> Section:
    """Make ``section`` a valid table of scene files (idempotent for the same object)."""
    old = SECTIONS.get(section.name)
    if old is not None and old is not section and old != section:
        raise InputError(f"scene section [{section.name}] registered twice with different fields")
    SECTIONS[section.name] = section
    return section


def register_model(name: str, builder: Callable[[Any], Any]) -> None:
    """Register ``builder(scene) -> Model`` for ``[scene] model = name``: once per name (the
    packaged kinds: ``sdof`` in :mod:`gear_dyn.scene.modification`, which covers the scenes
    with and without ``[tip_relief]``, and ``torsional`` in :mod:`gear_dyn.scene.eccentricity`),
    so no builder silently replaces another by import order.

    Raises
    ------
    InputError
        ``name`` already has another builder.
    """
    old = MODEL_BUILDERS.get(name)
    if old is not None and old is not builder:
        raise InputError(f"scene model {name!r} registered twice (by {old.__module__} and "
                         f"{builder.__module__}): one builder per model kind")
    MODEL_BUILDERS[name] = builder
