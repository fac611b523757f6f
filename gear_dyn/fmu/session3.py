"""Drive an FMI 3.0 co-simulation FMU through fmpy, as :class:`~gear_dyn.fmu.cosim.FmuSession`
does for FMI 2 (same method names, so checks and tests run either).

:func:`open_session` picks the session class from the FMU's ``fmiVersion``.
"""

from __future__ import annotations

import shutil
import zipfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any
from xml.etree import ElementTree as ET

from gear_dyn.errors import InputError, SolverError


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


class Fmu3Session:
    """One FMI 3 co-simulation instance driven through fmpy, its log messages collected.

    Raises
    ------
    InputError
        Not a readable FMI 3 co-simulation FMU.
    """

    def __init__(self, fmu: str | Path, instance_name: str = "gear_dyn") -> None:
        from fmpy import extract, read_model_description

        self.path = Path(fmu)
        try:
            self.dir = Path(extract(str(self.path)))
            self.md = read_model_description(str(self.dir))
        except Exception as exc:  # fmpy raises plain exceptions for unreadable FMUs
            raise InputError(f"{self.path}: not a readable FMU ({exc})") from None
        if self.md.coSimulation is None or not self.md.fmiVersion.startswith("3"):
            raise InputError(f"{self.path}: not an FMI 3 co-simulation FMU")
        self.vars = {v.name: v for v in self.md.modelVariables}
        self.instance_name = instance_name
        self.messages: list[tuple[int, str]] = []
        self._fmu: Any = None

    def _log(self, env: Any, status: int, category: Any, message: Any) -> None:
        text = message.decode("utf-8", "replace") if isinstance(message, bytes) else str(message)
        self.messages.append((int(status), text))

    def _call(self, what: str, func: Any, *args: Any, error: type[Exception] = SolverError) -> Any:
        from fmpy.fmi1 import FMICallException

        n = len(self.messages)
        try:
            return func(*args)
        except FMICallException as exc:
            new = self.messages[n:]
            logged = ("; ".join(m for s, m in new if s == 3)
                      or "; ".join(m for s, m in new if s >= 2) or "no message logged")
            raise error(f"FMU {what} failed ({exc}): {logged}") from None

    def instantiate(self, logging_on: bool = True) -> None:
        """Load the binary and create the instance."""
        from fmpy.fmi3 import FMU3Slave

        self._fmu = FMU3Slave(guid=self.md.guid, unzipDirectory=str(self.dir),
                              modelIdentifier=self.md.coSimulation.modelIdentifier,
                              instanceName=self.instance_name)
        try:
            self._fmu.instantiate(loggingOn=logging_on, logMessage=self._log)
        except Exception as exc:
            logged = "; ".join(m for _, m in self.messages) or "no message logged"
            raise SolverError(f"{self.path.name}: instantiation failed ({exc}): {logged}") from None

    @property
    def fmu(self) -> Any:
        if self._fmu is None:
            raise InputError("the FMU is not instantiated")
        return self._fmu

    def set(self, values: dict[str, Any]) -> None:
        """Set variables by name; refused values raise InputError with the FMU's message."""
        for name, value in values.items():
            v = self.vars.get(name)
            if v is None:
                raise InputError(f"{self.path.name}: no variable {name!r}")
            setter = {"Float64": self.fmu.setFloat64, "Int32": self.fmu.setInt32,
                      "Int64": self.fmu.setInt64, "Enumeration": self.fmu.setInt64,
                      "Boolean": self.fmu.setBoolean, "String": self.fmu.setString}[v.type]
            value = host_value(name, v, value)
            self._call(f"set {name}", setter, [v.valueReference], [value], error=InputError)

    def get(self, names: Sequence[str]) -> list[float]:
        """Float64 values by name."""
        vrs = []
        for n in names:
            if n not in self.vars:
                raise InputError(f"{self.path.name}: no variable {n!r}")
            vrs.append(int(self.vars[n].valueReference))
        return list(self.fmu.getFloat64(vrs))

    def initialize(self, start: float = 0.0, stop: float | None = None,
                   tolerance: float | None = None, values: dict[str, Any] | None = None) -> None:
        """enterInitializationMode (start, stop time and tolerance announced), set ``values``,
        exitInitializationMode."""
        self._call("enterInitializationMode", self.fmu.enterInitializationMode, tolerance,
                   start, stop, error=InputError)
        if values:
            self.set(values)
        self._call("exitInitializationMode", self.fmu.exitInitializationMode, error=InputError)

    def step(self, t: float, h: float) -> None:
        """One communication step from ``t`` (s) by ``h`` (s)."""
        self._call(f"doStep at t = {t:.6g} s", self.fmu.doStep, t, h)

    def terminate(self) -> None:
        self._call("terminate", self.fmu.terminate)

    def close(self) -> None:
        """Free the instance and remove the extracted copy."""
        if self._fmu is not None:
            self._fmu.freeInstance()
            self._fmu = None
        shutil.rmtree(self.dir, ignore_errors=True)

    def __enter__(self) -> Fmu3Session:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


#: fmpy's names of the integer-valued variable types (FMI 2 and FMI 3)
INTEGER_TYPES = ("Integer", "Int32", "Int64", "Enumeration")


def host_value(name: str, variable: Any, value: Any) -> Any:
    """``value`` as the FMU takes it for ``variable`` (an fmpy model variable), FMI 2 and 3: an
    enumeration item by name becomes its number; an integer type takes whole numbers only
    (InputError naming the variable and the valid choices otherwise)."""
    if variable.type == "Enumeration" and isinstance(value, str):
        items = {i.name: int(i.value) for i in variable.declaredType.items}
        if value not in items:
            raise InputError(f"{name} = {value!r}: valid choices are {', '.join(items)}")
        return items[value]
    if variable.type in INTEGER_TYPES:
        if isinstance(value, float) and not value.is_integer():
            raise InputError(f"{name} = {value!r}: expected a whole number")
        return int(value)
    return value


def open_session(fmu: str | Path) -> Any:
    """An :class:`Fmu3Session` for an FMI 3 FMU, a :class:`~gear_dyn.fmu.cosim.FmuSession`
    for an FMI 2 one."""
    if fmi_version(fmu).startswith("3"):
        return Fmu3Session(fmu)
    from gear_dyn.fmu.cosim import FmuSession

    return FmuSession(fmu)
