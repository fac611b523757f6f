"""Build an FMI 2.0 co-simulation FMU of a scene with pythonfmu.

The FMU carries everything it runs (the generated slave script over
:class:`gear_dyn.fmu.slave.GearDynSlave`, a private copy of the gear_dyn sources under a name
unique to this build, :mod:`.staging`, the scene in SI values and pythonfmu's loader), so the
importing machine needs only Python with numpy and scipy; what is in the zip: docs/fmu.md, "The
pythonfmu FMU: build". pythonfmu does not write units or initial unknowns, so the
modelDescription.xml in the zip is completed afterwards (:func:`complete_model_description`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any
from xml.etree import ElementTree as ET

from gear_dyn.errors import InputError
from gear_dyn.fmu.build3 import build_fmu3
from gear_dyn.fmu.fmu_info import read_fmu
from gear_dyn.fmu.staging import BuiltFmu, build_with, unit_definitions
from gear_dyn.fmu.variables import SPEC_FILE, UNITS
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
        FMI version: 2 (pythonfmu) or 3 (pythonfmu3, :mod:`gear_dyn.fmu.build3`).

    Raises
    ------
    InputError
        Bad target or output name, invalid scene, pythonfmu without binaries for this platform,
        an FMI version other than 2 and 3, or pythonfmu3 missing for FMI 3.
    """
    if fmi not in (2, 3):
        raise InputError(f"--fmi {fmi}: valid FMI versions are 2 and 3")
    if fmi == 3:
        return build_fmu3(target, out)
    from pythonfmu import FmuBuilder

    return build_with(FmuBuilder, target, out, 2, complete_model_description,
                      canGetAndSetFMUstate=True, canSerializeFMUstate=True)


# ---------------------------------------------------------------------- modelDescription
def complete_model_description(root: ET.Element, mv: ET.Element, by_name: dict[str, Any]
                               ) -> None:
    """Add UnitDefinitions, units and InitialUnknowns to pythonfmu's modelDescription.xml
    (``root``, its ModelVariables ``mv``; ``by_name``: the spec's variables by name)."""
    used: dict[str, str] = {}
    outputs: list[int] = []
    for index, sv in enumerate(mv.findall("ScalarVariable"), start=1):
        v = by_name.get(sv.get("name", ""))
        if v is None:
            continue
        if sv.get("causality") == "output":
            outputs.append(index)
        typed = next(iter(sv), None)
        if typed is not None and typed.tag in ("Real", "Integer"):
            for key in ("min", "max", "nominal"):
                if key in v and (key != "nominal" or typed.tag == "Real"):
                    typed.set(key, repr(v[key]))
        real = sv.find("Real")
        if real is not None and v.get("unit") in UNITS:
            fmi_name = UNITS[v["unit"]][0]
            real.set("unit", fmi_name)
            used[v["unit"]] = fmi_name
    _enumerations(root, mv, by_name)
    if used:
        cs = root.find("CoSimulation")
        root.insert(list(root).index(cs) + 1 if cs is not None else 0, unit_definitions(used))
    ms = root.find("ModelStructure")
    if ms is None:
        ms = ET.SubElement(root, "ModelStructure")
    # no direct feedthrough: outputs are computed from the state at doStep (and at
    # exitInitializationMode) only, so setting an input changes no output before the next step
    out_list = ms.find("Outputs")
    for unknown in [] if out_list is None else out_list.findall("Unknown"):
        unknown.set("dependencies", "")
    if outputs and ms.find("InitialUnknowns") is None:
        iu = ET.SubElement(ms, "InitialUnknowns")
        for index in outputs:
            ET.SubElement(iu, "Unknown", {"index": str(index)})


def _enumerations(root: ET.Element, mv: ET.Element, by_name: dict[str, Any]) -> None:
    """Turn the Integer stand-ins of choice parameters into FMI Enumerations with their
    TypeDefinitions (item k = choice k), so a master offers the choices."""
    types = ET.Element("TypeDefinitions")
    for sv in mv.findall("ScalarVariable"):
        v = by_name.get(sv.get("name", ""))
        typed = next(iter(sv), None)
        if v is None or v["type"] != "Enumeration" or typed is None:
            continue
        type_name = f"{v['name']}.choices"
        typed.tag = "Enumeration"
        typed.set("declaredType", type_name)
        simple = ET.SubElement(types, "SimpleType", {"name": type_name})
        enum = ET.SubElement(simple, "Enumeration")
        for k, choice in enumerate(v["choices"], start=1):
            ET.SubElement(enum, "Item", {"name": choice, "value": str(k)})
    if len(types):
        anchor = root.find("CoSimulation")
        root.insert(list(root).index(anchor) + 1 if anchor is not None else 0, types)


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
