"""Drive an FMI 3.0 co-simulation FMU through fmpy, as :class:`~gear_dyn.fmu.session.FmuSession`
does for FMI 2 (same method names, so checks and tests run either).

:func:`open_session` picks the session class from the FMU's ``fmiVersion``.
"""

from __future__ import annotations

import zipfile
from pathlib import Path
from typing import Any
from xml.etree import ElementTree as ET

from gear_dyn.errors import InputError
from gear_dyn.fmu.session import FmpySession, FmuSession


def fmi_version(fmu: str | Path) -> str:
    """The ``fmiVersion`` of an FMU file ("2.0", "3.0", ...).

    Raises
    ------
    InputError
        Not a readable FMU.
    """
    try:
        with zipfile.ZipFile(fmu) as z:
            root = ET.fromstring(z.read("modelDescription.xml"))
    except (OSError, KeyError, zipfile.BadZipFile, ET.ParseError) as exc:
        raise InputError(f"{fmu}: not a readable FMU ({exc})") from None
    return str(root.get("fmiVersion", ""))


class Fmu3Session(FmpySession):
    """One FMI 3 co-simulation instance driven through fmpy, its log messages collected.

    Raises
    ------
    InputError
        Not a readable FMI 3 co-simulation FMU.
    """

    SETTERS = {"Float64": "setFloat64", "Int32": "setInt32", "Int64": "setInt64",
               "Enumeration": "setInt64", "Boolean": "setBoolean", "String": "setString"}
    GET_FLOATS = "getFloat64"

    def _check_version(self, version: str) -> None:
        if not version.startswith("3"):
            raise InputError(f"{self.path}: not an FMI 3 co-simulation FMU")

    def _log(self, env: Any, status: int, category: Any, message: Any) -> None:
        self._record(status, message)

    def instantiate(self, logging_on: bool = True) -> None:
        """Load the binary and create the instance."""
        from fmpy.fmi3 import FMU3Slave

        self._fmu = FMU3Slave(guid=self.md.guid, unzipDirectory=str(self.dir),
                              modelIdentifier=self.md.coSimulation.modelIdentifier,
                              instanceName=self.instance_name)
        self._instantiated(lambda: self._fmu.instantiate(loggingOn=logging_on,
                                                         logMessage=self._log))


def open_session(fmu: str | Path, instance_name: str = "gear_dyn") -> Any:
    """An :class:`Fmu3Session` for an FMI 3 FMU, a :class:`~gear_dyn.fmu.session.FmuSession`
    for an FMI 2 one."""
    if fmi_version(fmu).startswith("3"):
        return Fmu3Session(fmu, instance_name)
    return FmuSession(fmu, instance_name)
