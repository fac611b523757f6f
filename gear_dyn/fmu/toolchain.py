"""Compile an FMU's C sources into its platform binaries (Linux always, Windows where MinGW-w64 is).

The native FMUs and the benchmarks' trivial FMU are built the same way: C99 sources compiled
with the system compiler into one shared library per platform, linked against libm only.

- x86_64 Linux: ``cc`` (or ``$CC``), ``-shared -fPIC -fvisibility=hidden``: only the FMI
  functions (marked ``FMI2_Export`` / ``FMI3_Export`` by the standard's headers) are exported,
  so two FMUs in one process do not share each other's internal functions.
- Both binaries are linked with ``-s`` (stripped: no symbol table or debug sections; the
  exported FMI functions are dynamic symbols and stay).
- x86_64 Windows: ``x86_64-w64-mingw32-gcc`` when it is on PATH (Debian/Ubuntu:
  ``apt-get install gcc-mingw-w64-x86-64``), ``-static-libgcc``: the DLL needs only Windows'
  own C runtime (msvcrt.dll / KERNEL32.dll), not the compiler's runtime libraries.

The folder names are the standard's: FMI 2 ``binaries/linux64``, ``binaries/win64``; FMI 3
``binaries/x86_64-linux``, ``binaries/x86_64-windows``.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from collections.abc import Iterable, Mapping
from pathlib import Path

from gear_dyn.errors import InputError

#: the binaries folder of each platform, by FMI version
PLATFORMS = {2: {"linux": "linux64", "windows": "win64"},
             3: {"linux": "x86_64-linux", "windows": "x86_64-windows"}}
#: file name ending of the shared library on each platform
SUFFIX = {"linux": ".so", "windows": ".dll"}
#: the MinGW-w64 cross compiler looked up on PATH
MINGW = "x86_64-w64-mingw32-gcc"
#: the flags both compilers get: C99, optimized, warnings that catch a wrong FMI signature
COMMON_FLAGS = ("-std=c99", "-O2", "-Wall", "-Wextra", "-shared", "-s")


def fmi_headers(fmi: int = 2) -> Path:
    """The folder with the FMI 2 (``fmi=2``) or FMI 3 headers of the Modelica Association
    (``fmi2Functions.h`` ..., ``fmi3Functions.h`` ...): gear_dyn's own copy (package data),
    ``gear_dyn/fmu/native/fmi2`` (``fmi3``)."""
    return Path(__file__).with_name("native") / f"fmi{fmi}"


def linux_compiler() -> str | None:
    """The C compiler for the Linux binary: ``$CC`` if set and found, else cc, gcc or clang
    on PATH (None: none found)."""
    names = [os.environ["CC"]] if os.environ.get("CC") else []
    for name in names + ["cc", "gcc", "clang"]:
        found = shutil.which(name)
        if found:
            return found
    return None


def windows_compiler() -> str | None:
    """The MinGW-w64 cross compiler for x86_64 Windows, if it is on PATH."""
    return shutil.which(MINGW)


def compile_binaries(sources: Iterable[str | Path], out_dir: str | Path,
                     model_identifier: str, fmi: int = 2,
                     include_dirs: Iterable[str | Path] = (),
                     defines: Mapping[str, str] | None = None,
                     windows: bool = True) -> dict[str, Path]:
    """Compile C99 sources into ``out_dir/<platform folder>/<model_identifier>.so|.dll``.

    Parameters
    ----------
    sources : iterable of str or Path
        The C files (compiled and linked together in one command).
    out_dir : str or Path
        Folder that receives the platform folders (the FMU's ``binaries/``).
    model_identifier : str
        File name of the library, without ending.
    fmi : int
        2 or 3: selects the platform folder names (:data:`PLATFORMS`).
    include_dirs : iterable of str or Path
        Header folders (``-I``): the FMI headers and the sources' own.
    defines : mapping of str to str, optional
        Preprocessor definitions (``-DNAME=VALUE``).
    windows : bool
        Also build the Windows binary when :func:`windows_compiler` finds MinGW-w64.

    Returns
    -------
    dict of str to Path
        The library of each platform built, keyed by its folder name (``linux64``, ...).

    Raises
    ------
    InputError
        No C compiler on PATH (the message names what to install), or ``fmi`` is not 2 or 3.
    RuntimeError
        A compiler failed (with its message).
    """
    if fmi not in PLATFORMS:
        raise InputError(f"fmi = {fmi}: valid FMI versions are 2 and 3")
    cc = linux_compiler()
    if cc is None:
        raise InputError("no C compiler found (cc, gcc or clang on PATH, or $CC): a native FMU "
                         "is compiled at build time; install one, e.g. "
                         "`apt-get install gcc` (Debian/Ubuntu) or `dnf install gcc`")
    out = Path(out_dir)
    flags = [*COMMON_FLAGS, *(f"-I{d}" for d in include_dirs),
             *(f"-D{k}={v}" for k, v in (defines or {}).items())]
    files = [str(s) for s in sources]
    built = {}
    linux = out / PLATFORMS[fmi]["linux"] / f"{model_identifier}{SUFFIX['linux']}"
    linux.parent.mkdir(parents=True, exist_ok=True)
    _run([cc, *flags, "-fPIC", "-fvisibility=hidden", "-Wl,-z,defs", *files, "-o", str(linux),
          "-lm"])
    built[PLATFORMS[fmi]["linux"]] = linux
    mingw = windows_compiler() if windows else None
    if mingw is not None:
        dll = out / PLATFORMS[fmi]["windows"] / f"{model_identifier}{SUFFIX['windows']}"
        dll.parent.mkdir(parents=True, exist_ok=True)
        _run([mingw, *flags, "-static-libgcc", *files, "-o", str(dll), "-lm"])
        built[PLATFORMS[fmi]["windows"]] = dll
    return built


def _run(cmd: list[str]) -> None:
    proc = subprocess.run(cmd, capture_output=True, text=True, env={**os.environ, "LC_ALL": "C"})
    if proc.returncode != 0:
        raise RuntimeError(f"{Path(cmd[0]).name} failed (exit {proc.returncode}): "
                           f"{proc.stderr.strip()[-1500:]}")
