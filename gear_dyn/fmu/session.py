"""What driving an FMU through fmpy needs whatever its FMI version: reading and extracting it,
variables by name, setting values the FMU refuses with its own message, calls whose failure
becomes a gear_dyn error carrying the FMU's log, the life cycle.

:class:`FmuSession` (FMI 2, here) and :class:`~gear_dyn.fmu.session3.Fmu3Session`
(FMI 3) add what differs: the version they accept, how the instance is made, the setter of each
variable type, FMI 2's setupExperiment.
"""

from __future__ import annotations

import math
import shutil
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import InputError, SolverError

FloatArray = NDArray[np.float64]

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

    def instantiate(self, logging_on: bool = True) -> None:
        """Load the binary and create the instance (debug logging on: messages are kept)."""
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

    # ------------------------------------------------------------------ a run
    def run(self, step: float, stop: float, outputs: Sequence[str],
            values: dict[str, Any] | None = None, tolerance: float | None = None,
            stop_time: float | None = None) -> tuple[FloatArray, FloatArray, float]:
        """Instantiate, run from 0 to ``stop`` with communication step ``step``, terminate.

        ``stop_time`` (default: the last communication point) is the stop time announced in
        setupExperiment; the FMU finds the switching instants up to it at once.

        Returns
        -------
        t : ndarray (n,)
        y : ndarray (len(outputs), n)
        run_time : float
            Wall time in s from instantiation to termination (extraction excluded).
        """
        n = int(math.floor(stop / step + 1e-9))
        if n < 1:
            raise InputError(f"communication step = {step:.6g} s is longer than the run "
                             f"({stop:.6g} s)")
        t = np.arange(n + 1, dtype=np.float64) * float(step)
        y = np.empty((len(outputs), n + 1))
        vrs = [self.vr(o) for o in outputs]
        start = time.perf_counter()
        self.instantiate()
        self.initialize(0.0, float(t[-1]) if stop_time is None else stop_time, tolerance,
                        values)
        y[:, 0] = getattr(self.fmu, self.GET_FLOATS)(vrs)
        for k in range(n):
            self.step(float(t[k]), float(t[k + 1] - t[k]))
            y[:, k + 1] = getattr(self.fmu, self.GET_FLOATS)(vrs)
        self.terminate()
        run_time = time.perf_counter() - start
        self.free()
        return t, y, run_time


class FmuSession(FmpySession):
    """One FMI 2.0 co-simulation instance driven through fmpy, with its log messages collected
    (the parameters and the common methods: :class:`~gear_dyn.fmu.session.FmpySession`).

    Raises
    ------
    InputError
        Not a readable FMI 2.0 co-simulation FMU.
    """

    _callbacks: Any = None  # the C callbacks of the instance, kept alive as long as it
    SETTERS = {"Real": "setReal", "Integer": "setInteger", "Enumeration": "setInteger",
               "Boolean": "setBoolean", "String": "setString"}
    GET_FLOATS = "getReal"

    def _check_version(self, version: str) -> None:
        if version != "2.0":
            raise InputError(f"{self.path}: an FMI {version} FMU, not FMI 2.0 (open_session in "
                             "gear_dyn.fmu.session3 picks the session of either version)")

    def _logger(self, env: Any, name: Any, status: int, category: Any, message: Any) -> None:
        self._record(status, message)

    def instantiate(self, logging_on: bool = True) -> None:
        """Load the binary and create the instance (debug logging on: messages are kept)."""
        from fmpy.fmi2 import FMU2Slave, defaultCallbacks, fmi2CallbackFunctions
        from fmpy.fmi2 import fmi2CallbackLoggerTYPE as LoggerType

        cb = fmi2CallbackFunctions()
        cb.logger = LoggerType(self._logger)
        cb.allocateMemory = defaultCallbacks.allocateMemory
        cb.freeMemory = defaultCallbacks.freeMemory
        self._callbacks = cb
        self._fmu = FMU2Slave(guid=self.md.guid, unzipDirectory=str(self.dir),
                              modelIdentifier=self.md.coSimulation.modelIdentifier,
                              instanceName=self.instance_name)
        self._instantiated(lambda: self._fmu.instantiate(callbacks=cb, loggingOn=logging_on))

    def enter_init(self, start: float = 0.0, stop: float | None = None,
                   tolerance: float | None = None) -> None:
        """setupExperiment (start, stop time and tolerance) and enterInitializationMode."""
        self._call("setupExperiment", self.fmu.setupExperiment, tolerance, start, stop)
        self._call("enterInitializationMode", self.fmu.enterInitializationMode,
                   error=InputError)

    def reset(self) -> None:
        self._call("reset", self.fmu.reset)


__all__ = ["INTEGER_TYPES", "FmpySession", "FmuSession", "host_value"]
