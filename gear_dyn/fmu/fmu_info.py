"""What `gear-dyn cosim` needs to know about an FMU built by gear_dyn, for both kinds.

- A **pythonfmu** FMU carries ``resources/gear_dyn_fmu.json`` (:mod:`gear_dyn.fmu.build`): the
  scene in SI values, its variables (every scene key is a parameter) and the experiment. It
  states no error of its own: it runs gear_dyn's solver, whose error is estimated.
- A **native** FMU carries ``resources/gear_dyn_native.json`` (:data:`NATIVE_FILE`, written by
  :func:`gear_dyn.fmu.export_fmu.build_native_fmu`): the same record without the variables
  (:func:`gear_dyn.fmu.variables.scene_record`). Its variables (``damping.ratio``,
  ``solver.tolerance``, ...) and its stated error of the DTE come from its modelDescription.

:func:`read_fmu` returns one :class:`FmuInfo` for either kind, so the comparison has one code
path.
"""

from __future__ import annotations

import json
import re
import zipfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any
from xml.etree import ElementTree as ET

from gear_dyn.errors import InputError
from gear_dyn.fmu.variables import SPEC_FILE, check_spec

#: the native FMU's record of its scene, in ``resources/``
NATIVE_FILE = "gear_dyn_native.json"
#: the sentence of a native FMU's description that states its error
_STATED = re.compile(r"Stated error of the DTE: ([0-9.eE+-]+) of the static deflection")


@dataclass(frozen=True)
class FmuInfo:
    """An FMU built by gear_dyn, either kind.

    Attributes
    ----------
    backend : str
        ``"native"`` or ``"python"`` (pythonfmu).
    spec : dict
        ``model``, ``scene_name``, ``tables`` (SI), ``experiment``, ``mesh_frequency`` and
        ``variables`` (each with ``name`` and ``causality``).
    stated_error : float or None
        The FMU's stated error of the DTE relative to the static deflection W/k_m (native:
        from its modelDescription); None when the FMU states none (pythonfmu).
    fmi_version : str
        ``"2.0"`` or ``"3.0"``.
    """

    backend: str
    spec: dict[str, Any]
    stated_error: float | None
    fmi_version: str

    @property
    def settable(self) -> set[str]:
        """Names of the parameters and inputs."""
        return {v["name"] for v in self.spec["variables"] if v["causality"] != "output"}

    @property
    def outputs(self) -> set[str]:
        """Names of the outputs."""
        return {v["name"] for v in self.spec["variables"] if v["causality"] == "output"}


def read_fmu(fmu: str | Path) -> FmuInfo:
    """Read an FMU built by gear_dyn (native or pythonfmu).

    Raises
    ------
    InputError
        No such file, not a zip, not built by gear_dyn, or an unreadable record.
    """
    p = Path(fmu)
    try:
        with zipfile.ZipFile(p) as z:
            names = set(z.namelist())
            xml = z.read("modelDescription.xml") if "modelDescription.xml" in names else b""
            native = f"resources/{NATIVE_FILE}" in names
            record = f"resources/{NATIVE_FILE if native else SPEC_FILE}"
            text = z.read(record).decode("utf-8") if record in names else None
    except FileNotFoundError:
        raise InputError(f"{p}: FMU file not found") from None
    except (zipfile.BadZipFile, OSError):
        raise InputError(f"{p}: not a readable FMU (zip) file") from None
    if text is None:
        raise InputError(f"{p}: not an FMU built by gear_dyn (no resources/{SPEC_FILE} or "
                         f"resources/{NATIVE_FILE})")
    try:
        data = json.loads(text)
        root = ET.fromstring(xml)
    except (ValueError, ET.ParseError):
        raise InputError(f"{p}: {record} or modelDescription.xml is not readable") from None
    version = str(root.get("fmiVersion", ""))
    if not native:
        return FmuInfo("python", check_spec(data), None, version)
    spec = check_spec({**data, "variables": _variables(root)})
    found = _STATED.search(root.get("description", ""))
    if found is None:
        raise InputError(f"{p}: a native FMU whose modelDescription states no error of the DTE")
    return FmuInfo("native", spec, float(found[1]), version)


def _variables(root: ET.Element) -> list[dict[str, Any]]:
    """The variables of a modelDescription (FMI 2 or 3): name, causality, start (if any)."""
    mv = root.find("ModelVariables")
    out: list[dict[str, Any]] = []
    for v in [] if mv is None else list(mv):
        typed = v.find("Real") if v.tag == "ScalarVariable" else v
        start = None if typed is None else typed.get("start")
        if v.get("causality") == "independent":
            continue
        out.append({"name": v.get("name", ""), "causality": v.get("causality", "local"),
                    **({"start": float(start)} if start is not None else {})})
    return out
