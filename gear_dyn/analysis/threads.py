"""One BLAS thread while the Python API works on gear_dyn's small matrices, as the CLI does.

gear_dyn's matrices are 2x2..8x8: BLAS worker threads cannot speed them up and, on a busy
machine, make every call wait for threads that have nothing to do (with OpenBLAS's default
threads an ``exact`` run cost several times the CPU from Python that it costs from the
``gear-dyn`` command, which sets one thread before numpy loads: docs/python_api.md). The entry
points of the analysis layer (:func:`gear_dyn.simulate <gear_dyn.analysis.study.simulate>`,
sweeps, continuation, fold maps,
bifurcation diagrams, motion classification) therefore run inside :func:`one_blas_thread`: a
limit scoped to the call through threadpoolctl's controller (the libraries' own thread
setting, restored on return; nested and concurrent calls share one limit, lifted when the
last of them returns). No environment variable is changed. The limit is skipped where the user
chose the threads (``OPENBLAS_NUM_THREADS``, ``OMP_NUM_THREADS`` or ``MKL_NUM_THREADS`` set) or
where threadpoolctl is not installed.
"""

from __future__ import annotations

import functools
import os
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any, TypeVar

F = TypeVar("F", bound=Callable[..., Any])

#: environment variables by which a user chooses the BLAS threads (then left alone)
USER_CHOICE = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")

_lock = threading.Lock()
_state: dict[str, Any] = {"depth": 0, "limiter": None, "controller": None}


def _controller() -> Any:
    """threadpoolctl's controller of the loaded libraries (made once: listing them costs
    milliseconds, a limit through it microseconds), or None without threadpoolctl."""
    if _state["controller"] is None:
        try:
            from threadpoolctl import ThreadpoolController
        except ImportError:
            _state["controller"] = False
        else:
            # the controller sees the libraries loaded when it is made: numpy's and scipy's
            # BLAS (wheels bundle one each), so scipy's is loaded first
            import scipy.linalg  # noqa: F401

            _state["controller"] = ThreadpoolController()
    return _state["controller"] or None


@contextmanager
def one_blas_thread() -> Iterator[None]:
    """One BLAS thread inside the block (see the module), restored when the last of the
    nested or concurrent blocks ends."""
    if any(os.environ.get(v) for v in USER_CHOICE):
        yield
        return
    with _lock:
        if _state["depth"] == 0:
            ctl = _controller()
            _state["limiter"] = None if ctl is None else ctl.limit(limits=1, user_api="blas")
        _state["depth"] += 1
    try:
        yield
    finally:
        with _lock:
            _state["depth"] -= 1
            if _state["depth"] == 0 and _state["limiter"] is not None:
                _state["limiter"].restore_original_limits()
                _state["limiter"] = None


def blas_limited(fn: F) -> F:
    """``fn`` run inside :func:`one_blas_thread`."""
    @functools.wraps(fn)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        with one_blas_thread():
            return fn(*args, **kwargs)
    return wrapper  # type: ignore[return-value]


__all__ = ["blas_limited", "one_blas_thread"]
