"""The Python API runs on one BLAS thread, as the CLI does, scoped to the call.

Checked through threadpoolctl's view of the loaded BLAS libraries: inside
``one_blas_thread`` (and inside a sweep, from its model factory) every BLAS library runs one
thread, and the thread counts before the call are back after it. Where the user chose the
threads (OPENBLAS_NUM_THREADS & co. set, as CI's second run does) they are left alone.
"""

from __future__ import annotations

import os

import numpy as np
import pytest

from gear_dyn.analysis.threads import USER_CHOICE, one_blas_thread

threadpoolctl = pytest.importorskip("threadpoolctl")


def _blas_threads() -> list[int]:
    import scipy.linalg

    scipy.linalg.inv(np.eye(3))  # numpy's and scipy's BLAS loaded
    return [i["num_threads"] for i in threadpoolctl.threadpool_info()
            if i["user_api"] == "blas"]


def test_one_thread_inside_restored_after() -> None:
    from gear_dyn import SDOFModel, rectangular_stiffness
    from gear_dyn.analysis.continuation import sdof_family
    from gear_dyn.analysis.sweep import sweep

    user = any(os.environ.get(v) for v in USER_CHOICE)
    before = _blas_threads()
    assert before
    with one_blas_thread():
        inside = _blas_threads()
        with one_blas_thread():  # nested: the same limit, kept when the inner block ends
            pass
        assert _blas_threads() == inside
    assert _blas_threads() == before
    assert inside == (before if user else [1] * len(before))
    seen: list[list[int]] = []
    model = SDOFModel(1.0, rectangular_stiffness(1.6, 1e8, 1.5e8), 0.05, 1000.0, 1000.0)
    fam = sdof_family(model, "speed", teeth=20)

    def factory(speed: float):  # type: ignore[no-untyped-def]
        seen.append(_blas_threads())
        return fam(speed)

    sweep(factory, [100.0, 110.0])
    assert seen and all(s == inside for s in seen)
    assert _blas_threads() == before
