"""What driving an FMU through fmpy needs whatever its FMI version: reading and extracting it,
variables by name, setting values the FMU refuses with its own message, calls whose failure
becomes a gear_dyn error carrying the FMU's log, the life cycle.

:class:`~gear_dyn.fmu.cosim.FmuSession` (FMI 2) and :class:`~gear_dyn.fmu.session3.Fmu3Session`
(FMI 3) add what differs: the version they accept, how the instance is made, the setter of each
variable type, FMI 2's setupExperiment.
"""

from __future__ import annotations

import shutil
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from gear_dyn.errors import InputError, SolverError

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


class FmpySession:
    """One co-simulation FMU instance driven through fmpy, its log messages collected.

    Parameters
    ----------
    fmu : str or Path
        The .fmu file.
    instance_name : str
        FMI instance name.
    unzipdir : Path or None
        An already extracted copy to use (None: extract into a temporary folder, removed by
        :meth:`close`).

    Raises
    ------
    InputError
        Not a readable co-simulation FMU, or one of an FMI version the subclass does not run.
    """

    def __init__(self, fmu: str | Path, instance_name: str = "gear_dyn",
                 unzipdir: str | Path | None = None) -> None:
        from fmpy import extract, read_model_description

        self.path = Path(fmu)
        self._own_dir = unzipdir is None
        try:
            self.dir = Path(extract(str(self.path)) if unzipdir is None else unzipdir)
            self.md = read_model_description(str(self.dir))
        except Exception as exc:  # fmpy raises plain exceptions for unreadable FMUs
            raise InputError(f"{self.path}: not a readable FMU ({exc})") from None
        if self.md.coSimulation is None:
            raise InputError(f"{self.path}: not a co-simulation FMU")
        self._check_version(self.md.fmiVersion)
        self.vars = {v.name: v for v in self.md.modelVariables}
        self.instance_name = instance_name
        self.messages: list[tuple[int, str]] = []
        self._fmu: Any = None

    # ------------------------------------------------------------------ what versions differ in
    #: the name of fmpy's setter of each variable type, and of its getter of float values
    SETTERS: dict[str, str] = {}
    GET_FLOATS = ""

    def _check_version(self, version: str) -> None:
        """Raise InputError for an FMI version this session does not run."""
        raise NotImplementedError

    # ------------------------------------------------------------------ plumbing
    def _record(self, status: int, message: Any) -> None:
        text = message.decode("utf-8", "replace") if isinstance(message, bytes) else str(message)
        self.messages.append((int(status), text))

    def _call(self, what: str, func: Any, *args: Any, error: type[Exception] = SolverError) -> Any:
        from fmpy.fmi1 import FMICallException

        n = len(self.messages)
        try:
            return func(*args)
        except FMICallException as exc:
            new = self.messages[n:]
            # the FMU's own reason (status error) first; pythonfmu's generic fatal note else
            logged = ("; ".join(m for s, m in new if s == 3)
                      or "; ".join(m for s, m in new if s >= 2) or "no message logged")
            raise error(f"FMU {what} failed ({exc}): {logged}") from None

    def _instantiated(self, instantiate: Callable[[], Any]) -> None:
        """Run fmpy's instantiate; its failure is a SolverError with everything logged."""
        try:
            instantiate()
        except Exception as exc:
            logged = "; ".join(m for _, m in self.messages) or "no message logged"
            raise SolverError(f"{self.path.name}: instantiation failed ({exc}): {logged}") from None

    def vr(self, name: str) -> int:
        """Value reference of a variable (InputError naming the variable if unknown)."""
        v = self.vars.get(name)
        if v is None:
            raise InputError(f"{self.path.name}: no variable {name!r}")
        return int(v.valueReference)

    @property
    def fmu(self) -> Any:
        """The fmpy slave (after ``instantiate``)."""
        if self._fmu is None:
            raise InputError("the FMU is not instantiated")
        return self._fmu

    # ------------------------------------------------------------------ values
    def set(self, values: dict[str, Any]) -> None:
        """Set variables by name; refused values raise InputError with the FMU's message."""
        for name, value in values.items():
            self.vr(name)  # InputError naming an unknown variable
            v = self.vars[name]
            self._call(f"set {name}", getattr(self.fmu, self.SETTERS[v.type]),
                       [v.valueReference], [host_value(name, v, value)], error=InputError)

    def get(self, names: Sequence[str]) -> list[float]:
        """Float values by name."""
        return list(getattr(self.fmu, self.GET_FLOATS)([self.vr(n) for n in names]))

    # ------------------------------------------------------------------ life cycle
    def initialize(self, start: float = 0.0, stop: float | None = None,
                   tolerance: float | None = None, values: dict[str, Any] | None = None) -> None:
        """Enter initialization mode (start, stop time and tolerance announced), set ``values``,
        exit initialization mode."""
        self.enter_init(start, stop, tolerance)
        if values:
            self.set(values)
        self.exit_init()

    def enter_init(self, start: float = 0.0, stop: float | None = None,
                   tolerance: float | None = None) -> None:
        """enterInitializationMode, announcing the start, stop time and tolerance (FMI 3)."""
        self._call("enterInitializationMode", self.fmu.enterInitializationMode, tolerance,
                   start, stop, error=InputError)

    def exit_init(self) -> None:
        """exitInitializationMode: the FMU builds its model (InputError if it refuses)."""
        self._call("exitInitializationMode", self.fmu.exitInitializationMode, error=InputError)

    def step(self, t: float, h: float) -> None:
        """One communication step from ``t`` (s) by ``h`` (s)."""
        self._call(f"doStep at t = {t:.6g} s", self.fmu.doStep, t, h)

    def terminate(self) -> None:
        self._call("terminate", self.fmu.terminate)

    def free(self) -> None:
        """Free the instance and unload the binary."""
        if self._fmu is not None:
            self._fmu.freeInstance()
            self._fmu = None

    def close(self) -> None:
        """Free the instance and remove the extracted copy (if this session made it)."""
        self.free()
        if self._own_dir:
            shutil.rmtree(self.dir, ignore_errors=True)

    def __enter__(self) -> Any:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


__all__ = ["INTEGER_TYPES", "FmpySession", "host_value"]
