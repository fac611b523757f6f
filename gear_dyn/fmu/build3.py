"""Build an FMI 3.0 co-simulation FMU of a scene with pythonfmu3 (``gear-dyn fmu build --fmi 3``).

The same FMU as :mod:`gear_dyn.fmu.build` makes for FMI 2, with pythonfmu3 in place of
pythonfmu: the generated script's class derives from
:class:`gear_dyn.fmu.slave3.GearDynSlave3` (which steps the model with the FMI 2 slave's
:class:`~gear_dyn.fmu.stepper.Stepper`), the private gear_dyn copy leaves out the FMI 2 slave.
Like the FMI 2 FMU it runs in Python hosts only (the native FMU runs anywhere). pythonfmu3
writes neither units, bounds nor enumeration types, so the modelDescription is completed
afterwards: UnitDefinitions, ``unit``/``min``/``max``/``nominal`` from the scene fields,
Enumerations with their EnumerationTypes, and ``dependencies=""`` on every Output (no direct
feedthrough).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any
from xml.etree import ElementTree as ET

from gear_dyn.errors import InputError
from gear_dyn.fmu.staging import BuiltFmu, build_with, unit_definitions
from gear_dyn.fmu.variables import UNITS
from gear_dyn.scene import Scene


def build_fmu3(target: str | Path | Scene, out: str | Path) -> BuiltFmu:
    """Build the FMI 3.0 co-simulation FMU of a scene into ``out`` (written whole or not at
    all); arguments as :func:`gear_dyn.fmu.build.build_fmu`.

    Raises
    ------
    InputError
        Bad target or output name, invalid scene, pythonfmu3 missing or without a binary for
        this platform.
    """
    try:
        from pythonfmu3 import FmuBuilder
    except ImportError:
        raise InputError("--fmi 3 needs pythonfmu3 (pip install 'gear_dyn[fmi3]' or "
                         "pip install pythonfmu3)") from None
    return build_with(FmuBuilder, target, out, 3, complete_model_description3,
                      canGetAndSetFMUState=True, canSerializeFMUState=True)


def complete_model_description3(root: ET.Element, mv: ET.Element, by_name: dict[str, Any]
                                ) -> None:
    """Add units, bounds, enumeration types and output dependencies to pythonfmu3's
    modelDescription.xml (FMI 3.0; arguments as
    :func:`gear_dyn.fmu.build.complete_model_description`)."""
    used: dict[str, str] = {}
    enums = ET.Element("TypeDefinitions")
    for el in mv:
        v = by_name.get(el.get("name", ""))
        if v is None:
            continue
        if v["type"] == "Enumeration" and el.tag == "Int64":
            type_name = f"{v['name']}.choices"
            el.tag = "Enumeration"
            el.set("declaredType", type_name)
            et = ET.SubElement(enums, "EnumerationType", {"name": type_name})
            for k, choice in enumerate(v["choices"], start=1):
                ET.SubElement(et, "Item", {"name": choice, "value": str(k)})
            continue
        for key in ("min", "max", "nominal"):
            if key in v and (key != "nominal" or el.tag == "Float64"):
                el.set(key, repr(v[key]))
        if el.tag == "Float64" and v.get("unit") in UNITS:
            el.set("unit", UNITS[v["unit"]][0])
            used[v["unit"]] = UNITS[v["unit"]][0]
    if mv.find("Float64[@name='time']") is not None:
        used["s"] = UNITS["s"][0]
    cs = root.find("CoSimulation")
    if cs is None:
        raise InputError("modelDescription.xml without CoSimulation")
    # pythonfmu3 0.3.4 writes this flag from the wrong option; the slave takes any step size
    cs.set("canHandleVariableCommunicationStepSize", "true")
    pos = list(root).index(cs) + 1
    if used:
        root.insert(pos, unit_definitions(used))
        pos += 1
    if len(enums):
        old = root.find("TypeDefinitions")
        if old is not None:
            root.remove(old)
        root.insert(pos, enums)
    ms = root.find("ModelStructure")
    # no direct feedthrough: outputs change only at doStep and exitInitializationMode
    for output in [] if ms is None else ms.findall("Output"):
        output.set("dependencies", "")
