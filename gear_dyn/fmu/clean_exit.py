"""A Python host's clean exit after a pythonfmu FMU, done from the FMU's own Python code.

pythonfmu 0.7's binary (and pythonfmu3's alike) writes into freed memory at process exit, which
aborts about 1 fmpy process in 7 to 30 ("corrupted double-linked list";
tests/fmu/test_fmu_exit.py). :func:`release_at_exit` registers, once per binary, a Python exit
handler that calls the binary's ``finalizePythonInterpreter()`` itself, before the process's C
exit handlers run; the handle opened here also keeps the binary loaded until then. The fault,
why this avoids it and the measurements: docs/fmu.md, "A clean exit of the Python host".
"""

from __future__ import annotations

import atexit
import ctypes
import functools
import os
import sys
from pathlib import Path

#: the Linux binaries folder of a pythonfmu FMU, by FMI version
LINUX_FOLDER = {2: "linux64", 3: "x86_64-linux"}


def release_at_exit(resources: str | Path, model_identifier: str, fmi: int) -> bool:
    """Register the clean-exit handler for the FMU whose resources folder is ``resources``.

    Parameters
    ----------
    resources : str or Path
        The FMU's (unzipped) ``resources`` folder, as pythonfmu hands it to the slave.
    model_identifier : str
        The binary's file name without ``.so`` (the slave's class name).
    fmi : int
        2 or 3 (the binaries folder, :data:`LINUX_FOLDER`).

    Returns
    -------
    bool
        True when the handler is registered (now or before), False where it does not apply:
        not Linux, or no such binary loaded (the slave used directly from Python).
    """
    if not sys.platform.startswith("linux") or fmi not in LINUX_FOLDER:
        return False
    binary = Path(resources).parent / "binaries" / LINUX_FOLDER[fmi] / f"{model_identifier}.so"
    return _register(str(binary))


@functools.cache
def _register(binary: str) -> bool:
    """Open ``binary`` only if it is already loaded (RTLD_NOLOAD) and register its
    ``finalizePythonInterpreter`` at exit; cached, so once per binary."""
    try:
        lib = ctypes.CDLL(binary, mode=os.RTLD_NOLOAD | os.RTLD_NOW)
        release = lib.finalizePythonInterpreter
    except (OSError, AttributeError):
        return False
    release.restype = None
    release.argtypes = []
    atexit.register(release)
    return True
