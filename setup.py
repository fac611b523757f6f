"""The build step of gear_dyn's compiled kernel (everything else is configured in pyproject.toml).

The kernel is a plain C99 shared library (libm only, no Python C API) built from
``gear_dyn/solvers/kernel/*.c`` and loaded with ctypes by :mod:`gear_dyn.solvers.kernel`. It is
compiled as a setuptools extension so that ``pip install .``, ``pip install -e .`` and ``pip
wheel .`` all build it; without a C compiler the install stops with a message naming what to
install (docs/development.md, "The compiled kernel").
"""

from __future__ import annotations

import shutil

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext
from setuptools.errors import CCompilerError, CompileError, ExecError, PlatformError

KERNEL = "gear_dyn/solvers/kernel"
SOURCES = [f"{KERNEL}/{name}"
           for name in ("gd_flow.c", "gd_linear.c", "gd_kernel.c", "gd_torsional.c",
                        "gd_run.c")]
#: the library's entry points (Windows DLLs export only these)
EXPORTS = ["gd_flow_version", "gd_flow_products", "gd_flow_chain", "gd_flow_fill_periodic",
           "gd_defaults", "gd_start", "gd_advance", "gd_outputs",
           "gd_contact_flow", "gd_find_root", "gd_contact_stays_inside",
           "gd_contact_first_crossing", "gd_contact_walk", "gd_contact_on_grid", "gd_run",
           "gd_flow_compose", "gd_flow_grid_error", "gd_lin_expm2", "gd_lin_maps", "gd_lin_period",
           "gd_lin_chain"]
NO_COMPILER = (
    "gear_dyn builds its compiled kernel (C99, {sources}) at install and found no working C "
    "compiler ({why}). Install one and retry: Debian/Ubuntu 'apt-get install gcc', Fedora "
    "'dnf install gcc', macOS 'xcode-select --install', Windows the Microsoft C++ Build Tools; "
    "or name the compiler in the CC environment variable."
)


class BuildKernel(build_ext):
    """``build_ext`` for the kernel: strict C99 flags, a plain library (no ``PyInit_``
    export), and a clear error when there is no compiler."""

    def get_export_symbols(self, ext: Extension) -> list[str]:
        return EXPORTS

    def build_extension(self, ext: Extension) -> None:
        cc = getattr(self.compiler, "compiler_so", None) or getattr(self.compiler, "compiler",
                                                                    None)
        if cc and self.compiler.compiler_type != "msvc" and shutil.which(cc[0]) is None:
            raise PlatformError(NO_COMPILER.format(sources=", ".join(ext.sources),
                                                   why=f"{cc[0]!r} is not on PATH"))
        if self.compiler.compiler_type == "msvc":
            ext.extra_compile_args = ["/O2", "/W3"]
        else:
            ext.extra_compile_args = ["-std=c99", "-O2", "-Wall", "-Wextra", "-Werror",
                                      "-pedantic"]
            ext.libraries = ["m"]
        try:
            super().build_extension(ext)
        except (CCompilerError, ExecError, PlatformError) as exc:
            if isinstance(exc, CompileError):
                raise
            raise PlatformError(NO_COMPILER.format(sources=", ".join(ext.sources),
                                                   why=str(exc))) from exc


setup(
    ext_modules=[Extension("gear_dyn.solvers.kernel._gd_kernel", SOURCES,
                           include_dirs=[KERNEL], py_limited_api=False)],
    cmdclass={"build_ext": BuildKernel},
)
