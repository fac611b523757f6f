"""``gear-dyn response SCENE --speeds LO:HI --torques LO:HI:N --out DIR``: the jump map.

The ``--torques`` part of the response command (:mod:`gear_dyn.cli.response`): folds of the
scene's periodic orbits followed over torque by :func:`gear_dyn.analysis.continuation.
fold_map`; writes ``jump_map.png``, ``fold_curve.csv`` and ``fold_map.json`` into the staged
output folder.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from gear_dyn.errors import InputError


def parse_torques(text: str) -> list[float]:
    """``LO:HI:N`` (with units, e.g. ``'100 N*m:600 N*m:11'``) as N torques in N m.

    Raises
    ------
    InputError
        Not three parts, a plain number or bad unit, N outside 2..200, a torque <= 0.
    """
    from gear_dyn.scene.operating import parse_operating

    parts = text.split(":")
    if len(parts) != 3:
        raise InputError(f"--torques {text!r}: expected LO:HI:N, e.g. '100 N*m:600 N*m:11'")
    lo, hi = (parse_operating("torque", p.strip(), f"--torques {name}")
              for p, name in zip(parts[:2], ("LO", "HI"), strict=True))
    try:
        n = int(parts[2])
    except ValueError:
        raise InputError(f"--torques N = {parts[2]!r}: expected a whole number 2..200") from None
    if not 2 <= n <= 200:
        raise InputError(f"--torques N = {n}: valid range 2..200")
    if min(lo, hi) <= 0.0 or lo == hi:
        raise InputError(f"--torques {text!r}: LO and HI must differ and be > 0 N*m")
    return [float(t) for t in np.linspace(lo, hi, n)]


def write_jump_map(scene: Any, speeds: tuple[float, float], torques: list[float],
                   settings: Any, out: Path) -> Any:
    """Compute the fold map of ``scene`` and write ``jump_map.png``, ``fold_curve.csv`` and
    ``fold_map.json`` into ``out``; returns the FoldMap."""
    from gear_dyn.analysis.continuation import SpeedTorqueFamily, fold_map
    from gear_dyn.io import save_figure, write_json
    from gear_dyn.plots.fold_map import plot_fold_map
    from gear_dyn.scene.sweep import SceneModels

    models = SceneModels.of(scene)
    if not models.torque > 0:
        raise InputError(f"{scene.name}: operating.torque = 0 N*m: the jump map scales the "
                         "static load with torque and needs a scene torque > 0")
    family = SpeedTorqueFamily(models)  # the scene's torque, from the scene
    fm = fold_map(family, speeds, torques, settings=settings, reference_torque=family.reference)
    save_figure(plot_fold_map(fm), out / "jump_map.png", dpi=120)
    fm.to_csv(out / "fold_curve.csv")
    write_json(out / "fold_map.json", {"scene": scene.name, **fm.to_dict()})
    return fm
