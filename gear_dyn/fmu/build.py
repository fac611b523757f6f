"""Build an FMI 2.0 (pythonfmu) or FMI 3.0 (pythonfmu3) co-simulation FMU of a scene.

The FMU carries everything it runs (the generated slave script over
:class:`gear_dyn.fmu.slave.GearDynSlave`, or :class:`gear_dyn.fmu.slave3.GearDynSlave3` for
FMI 3, a private copy of the gear_dyn sources under a name unique to this build without the
other version's slave, :mod:`.staging`, the scene in SI values and the exporter's loader), so
the importing machine needs only Python with numpy and scipy; what is in the zip: docs/fmu.md,
"The pythonfmu FMU: build". Neither exporter writes units, bounds, enumeration types or initial
unknowns, so the modelDescription.xml in the zip is completed afterwards
(:func:`gear_dyn.fmu.staging.complete_model_description`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from gear_dyn.errors import InputError
from gear_dyn.fmu.fmu_info import read_fmu
from gear_dyn.fmu.staging import BuiltFmu, build_with
from gear_dyn.fmu.variables import SPEC_FILE
from gear_dyn.scene import Scene


def build_fmu(target: str | Path | Scene, out: str | Path, fmi: int = 2) -> BuiltFmu:
    """Build the FMU of a scene into ``out`` (a ``.fmu`` file, written whole or not at all).

    Parameters
    ----------
    target : str, Path or Scene
        Scene file, packaged scene name, model name (``sdof``, ``torsional``) or a Scene.
    out : str or Path
        FMU file to write (must end in ``.fmu``).
    fmi : int
        FMI version: 2 (pythonfmu) or 3 (pythonfmu3).

    Raises
    ------
    InputError
        Bad target or output name, invalid scene, pythonfmu without binaries for this platform,
        an FMI version other than 2 and 3, or pythonfmu3 missing for FMI 3.
    """
    if fmi not in (2, 3):
        raise InputError(f"--fmi {fmi}: valid FMI versions are 2 and 3")
    if fmi == 2:
        from pythonfmu import FmuBuilder

        return build_with(FmuBuilder, target, out, 2,
                          canGetAndSetFMUstate=True, canSerializeFMUstate=True)
    try:
        from pythonfmu3 import FmuBuilder as FmuBuilder3
    except ImportError:
        raise InputError("--fmi 3 needs pythonfmu3 (pip install 'gear_dyn[fmi3]' or "
                         "pip install pythonfmu3)") from None
    return build_with(FmuBuilder3, target, out, 3,
                      canGetAndSetFMUState=True, canSerializeFMUState=True)


def read_spec(fmu: str | Path) -> dict[str, Any]:
    """The gear_dyn spec (scene, variables, experiment) stored in a pythonfmu FMU built here
    (:func:`gear_dyn.fmu.fmu_info.read_fmu`, which reads native FMUs too).

    Raises
    ------
    InputError
        Not a readable FMU, or not a pythonfmu FMU built by gear_dyn.
    """
    info = read_fmu(fmu)
    if info.backend != "python":
        raise InputError(f"{fmu}: not a pythonfmu FMU built by gear_dyn (no "
                         f"resources/{SPEC_FILE}: a native FMU)")
    return info.spec
