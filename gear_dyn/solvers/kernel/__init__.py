"""gear_dyn's compiled kernel: one C99 library (libm only) for the sequential loops of the solvers.

The sources here (``gd_flow.c``: products and applications of affine step maps, and the
exact contact walk of the backlash model, :mod:`gear_dyn.solvers.kernel.contact`;
``gd_linear.c``: the step maps of the linear single-DOF model and their products over one mesh
period for many speeds per call, :mod:`gear_dyn.solvers.kernel.linear`;
``gd_kernel.c``, ``gd_torsional.c``: the native FMU's steppers, which the FMU compiles with its
glue; ``gd_run.c``: those steppers over an output grid, the solvers' ``kernel`` method,
:mod:`.run`) are built at install into one shared library (``setup.py``) and loaded with ctypes, not
the Python C API: a call releases the GIL, so threads run kernel calls in parallel. Python
computes the other maps (matrix exponentials of n-state pieces, collocation) and the kernel
applies them.

The library is looked up beside these sources, then in the installed gear_dyn distribution
(:func:`library_path`); where neither has one, the first use raises
:class:`~gear_dyn.errors.SolverError` naming the install command.
"""

from __future__ import annotations

import ctypes
import functools
import importlib.machinery
import re
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gear_dyn.errors import SolverError

FloatArray = NDArray[np.float64]

#: the folder of the kernel's C sources (package data; the native FMU compiles them too)
SOURCE_DIR = Path(__file__).parent
_NAME = "_gd_kernel"
_LONG = np.dtype(f"i{ctypes.sizeof(ctypes.c_long)}")  # C long (4 bytes on Windows)
_DP = ctypes.c_void_p  # arrays go in by address (ndarray.ctypes.data): float64, C order
#: the C type of the function :func:`gear_dyn.solvers.kernel.contact.find_root` closes on
ROOT_FUNCTION = ctypes.CFUNCTYPE(ctypes.c_double, ctypes.c_double, ctypes.c_void_p)


@functools.cache
def flow_version() -> int:
    """The interface version the library must report (``GD_FLOW_VERSION`` in ``gd_flow.h``),
    read on first use: a copy of the Python sources without the C ones (the pythonfmu FMU's)
    imports this module without needing the kernel."""
    text = (SOURCE_DIR / "gd_flow.h").read_text("utf-8")
    return int(re.search(r"#define GD_FLOW_VERSION (\d+)", text)[1])  # type: ignore[index]


def library_path() -> Path | None:
    """The built library: beside these sources (an installed package, or a source checkout
    built in place by ``pip install -e .``), else that of the installed gear_dyn distribution
    (a source checkout whose tests import its own tree after ``pip install .``: in its files,
    or in the source tree of an editable install, PEP 610 ``direct_url.json``); None if none
    exists. :func:`library` checks that the one found matches these sources' interface."""
    beside = _library_in(SOURCE_DIR)
    if beside is not None:  # the usual case: no need to read the distributions' metadata
        return beside
    import importlib.metadata  # only here: reading metadata and urllib cost ~50 ms to import
    import json
    import urllib.parse
    import urllib.request

    folders = []
    # every gear_dyn distribution on the path: a build in a source checkout leaves its
    # gear_dyn.egg-info there, found first when the checkout is the working directory
    for dist in importlib.metadata.distributions(name="gear_dyn"):
        folders.append(Path(str(dist.locate_file("gear_dyn/solvers/kernel"))))
        try:
            url = json.loads(dist.read_text("direct_url.json") or "{}")
        except ValueError:
            url = {}
        if url.get("dir_info", {}).get("editable") and str(url.get("url")).startswith("file:"):
            tree = Path(urllib.request.url2pathname(urllib.parse.urlparse(url["url"]).path))
            folders.append(tree / "gear_dyn" / "solvers" / "kernel")
    for folder in folders:
        found = _library_in(folder)
        if found is not None:
            return found
    return None


def _library_in(folder: Path) -> Path | None:
    """The kernel library in ``folder`` (any of this interpreter's extension suffixes)."""
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        p = folder / f"{_NAME}{suffix}"
        if p.is_file():
            return p
    return None


@functools.cache
def library() -> ctypes.CDLL:
    """The loaded kernel (loaded once per process).

    Raises
    ------
    SolverError
        The library is not built, or was built from other sources (version mismatch).
    """
    path = library_path()
    if path is None:
        raise SolverError(
            "gear_dyn's compiled kernel is not built (no gear_dyn/solvers/kernel/_gd_kernel "
            "library): install gear_dyn with a C compiler present, 'pip install .' or, in a "
            "source checkout, 'pip install -e .' (docs/development.md)")
    lib = ctypes.CDLL(str(path))
    lib.gd_flow_version.restype = ctypes.c_int
    lib.gd_flow_version.argtypes = []
    if lib.gd_flow_version() != flow_version():
        raise SolverError(f"gear_dyn's compiled kernel at {path} reports interface version "
                          f"{lib.gd_flow_version()}, the sources {flow_version()}: rebuild it "
                          "('pip install -e .' in a source checkout)")
    lib.gd_flow_products.restype = None
    lib.gd_flow_products.argtypes = [ctypes.c_int, ctypes.c_long, _DP, _DP, _DP, _DP]
    lib.gd_flow_chain.restype = None
    lib.gd_flow_chain.argtypes = [ctypes.c_int, ctypes.c_long, _DP, _DP, _DP, _DP]
    lib.gd_flow_grid_error.restype = ctypes.c_double
    lib.gd_flow_grid_error.argtypes = [ctypes.c_long, _DP, ctypes.c_double, ctypes.c_double]
    lib.gd_flow_compose.restype = None
    lib.gd_flow_compose.argtypes = [ctypes.c_int, ctypes.c_long, _DP, _DP, ctypes.c_long, _DP]
    lib.gd_flow_fill_periodic.restype = ctypes.c_int
    lib.gd_flow_fill_periodic.argtypes = [ctypes.c_int, ctypes.c_long, ctypes.c_long, _DP, _DP,
                                          _DP, _DP]
    _d, _l = ctypes.c_double, ctypes.c_long
    lib.gd_contact_flow.restype = None
    lib.gd_contact_flow.argtypes = [ctypes.c_int, _d, _d, _d, _d, _d, _d, _d, _l, _DP, _DP, _DP]
    lib.gd_find_root.restype = _d
    lib.gd_find_root.argtypes = [ROOT_FUNCTION, ctypes.c_void_p, _d, _d, _d, _d, _d]
    lib.gd_contact_stays_inside.restype = ctypes.c_int
    lib.gd_contact_stays_inside.argtypes = [_DP, _DP, _l, _d, _d, _d]
    lib.gd_contact_first_crossing.restype = ctypes.c_int
    lib.gd_contact_first_crossing.argtypes = [_DP, _DP, _l, _d, _d, _d, _d, _d, _DP]
    lib.gd_contact_walk.restype = ctypes.c_int
    lib.gd_contact_walk.argtypes = [_DP, _DP, _l, _DP, _DP, _d, _d, _d, _l, _l, _DP, _DP, _DP,
                                    _DP, _DP, _DP, _DP, _DP, _DP]
    lib.gd_contact_on_grid.restype = ctypes.c_int
    lib.gd_contact_on_grid.argtypes = [_DP, _DP, _l, _DP, _DP, _l, _DP, _DP]
    lib.gd_lin_expm2.restype = None
    lib.gd_lin_expm2.argtypes = [_l, _DP, _DP]
    lib.gd_lin_maps.restype = None
    lib.gd_lin_maps.argtypes = [_l, _l, _DP, _DP, _DP, _DP, _DP]
    lib.gd_lin_period.restype = None
    lib.gd_lin_period.argtypes = [_l, _l, _DP, _DP, _DP, _l, _DP, _DP, _DP]
    lib.gd_lin_chain.restype = None
    lib.gd_lin_chain.argtypes = [_l, _l, _DP, _DP, _DP]
    # the steppers (gd_kernel.c, gd_torsional.c, gd_run.c: :mod:`.run` builds their structures)
    lib.gd_start.restype = None
    lib.gd_start.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_double]
    lib.gd_run.restype = ctypes.c_long
    lib.gd_run.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_long, ctypes.c_void_p,
                           ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p]
    return lib


def _ptr(a: NDArray[Any]) -> int:
    """The address of ``a``'s data: through the buffer protocol (a writable C-contiguous
    array, the usual case: a third of the time of ``a.ctypes``), else ``a.ctypes.data``."""
    try:
        return ctypes.addressof(ctypes.c_char.from_buffer(a))  # type: ignore[arg-type]
    except (TypeError, ValueError, BufferError):
        return int(a.ctypes.data)


def _c(a: FloatArray) -> FloatArray:
    return np.ascontiguousarray(a, dtype=np.float64)


def _maps(f: FloatArray, h: FloatArray) -> tuple[FloatArray, FloatArray, int, int]:
    f, h = _c(f), _c(h)
    count, n = f.shape[0], f.shape[1]
    if f.shape != (count, n, n) or h.shape != (count, n):
        raise ValueError(f"maps of shapes {f.shape} and {h.shape}: need (count, n, n), (count, n)")
    return f, h, count, n


def grid_error(t: FloatArray, t0: float, dt: float) -> float:
    """Largest ``|t[i] - (t0 + i dt)|`` (s): how far ``t`` is from the uniform grid (NaN where a
    time is NaN)."""
    t = _c(t)
    return float(library().gd_flow_grid_error(t.size, _ptr(t), t0, dt))


def products(f: FloatArray, h: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Partial products of the affine maps ``y -> f[j] y + h[j]``: ``y_j = q[j] y_0 + r[j]``,
    j = 0..len(f) (``q[0] = I``; ``(q[-1], r[-1])`` the map over all of them)."""
    f, h, count, n = _maps(f, h)
    q, r = np.empty((count + 1, n, n)), np.empty((count + 1, n))
    library().gd_flow_products(n, count, _ptr(f), _ptr(h), _ptr(q), _ptr(r))
    return q, r


def compose(parts: FloatArray, owner: NDArray[np.intp], n_steps: int) -> FloatArray:
    """Augmented maps of ``n_steps`` steps, each the product of its parts in time order:
    ``parts[i]`` (``(n+1) x (n+1)``, ``[[F, h], [0, 1]]``) is the next part of step
    ``owner[i]`` (non-decreasing); a step without parts is the identity. Shape
    ``(n_steps, n+1, n+1)``."""
    parts = _c(parts)
    own = np.ascontiguousarray(owner, dtype=_LONG)
    if parts.ndim != 3 or parts.shape[1] != parts.shape[2] or own.shape != parts.shape[:1] \
            or (own.size and (own[0] < 0 or own[-1] >= n_steps or np.any(np.diff(own) < 0))):
        raise ValueError(f"compose: parts {parts.shape}, owner {own.shape} not non-decreasing "
                         f"in 0..{n_steps - 1}")
    total = np.empty((n_steps, parts.shape[1], parts.shape[1]))
    library().gd_flow_compose(parts.shape[1] - 1, own.size, _ptr(parts), _ptr(own), n_steps,
                              _ptr(total))
    return total


def chain(f: FloatArray, h: FloatArray, y0: FloatArray) -> FloatArray:
    """States at the map boundaries from ``y0``: ``y[0] = y0``, ``y[j+1] = f[j] y[j] + h[j]``,
    shape ``(len(f) + 1, n)``."""
    f, h, count, n = _maps(f, h)
    y0 = _c(y0)
    out = np.empty((count + 1, n))
    library().gd_flow_chain(n, count, _ptr(f), _ptr(h), _ptr(y0), _ptr(out))
    return out


def fill_periodic(q: FloatArray, r: FloatArray, y0: FloatArray, n_samples: int, s_per: int
                  ) -> tuple[FloatArray, bool]:
    """States on a uniform grid of ``n_samples`` points, ``s_per`` per period, from ``y0`` and
    the partial products ``(q, r)`` of one period's step maps (:func:`products`; only
    ``min(s_per, n_samples - 1) + 1`` of them are needed for a span shorter than a period).

    Returns
    -------
    y : ndarray (n, n_samples)
    finite : bool
        False where a state is not finite (``y`` is then NaN from that sample on).
    """
    q, r, y0 = _c(q), _c(r), _c(y0)
    n = y0.size
    need = min(s_per, n_samples - 1) + 1
    if q.shape[0] < need or q.shape[1:] != (n, n) or r.shape != (q.shape[0], n):
        raise ValueError(f"fill_periodic: {q.shape[0]} products of shape {q.shape[1:]} for "
                         f"{n} states, need {need}")
    out = np.empty((n, n_samples))
    bad = library().gd_flow_fill_periodic(n, s_per, n_samples, _ptr(q), _ptr(r), _ptr(y0),
                                          _ptr(out))
    return out, bad == 0
