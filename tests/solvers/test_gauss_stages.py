"""The Gauss-Legendre step maps' stage solve (:mod:`gear_dyn.solvers.gauss`) against LAPACK and
against the exponential of a constant-coefficient system."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from scipy.linalg import expm

from gear_dyn.solvers.gauss import STAGES, _maps, _solve_stages


@pytest.mark.parametrize("size", [0.05, 0.9])  # small G: the elimination; large: the fallback
def test_stage_solve_matches_pivoted_solve(size: float) -> None:
    rng = np.random.default_rng(3)
    m = 257
    g = size * rng.standard_normal((STAGES, STAGES, m))
    rhs = rng.standard_normal((STAGES, 5, m))
    want = np.linalg.solve(np.eye(STAGES) - g.transpose(2, 0, 1), rhs.transpose(2, 0, 1))
    got = _solve_stages(g, rhs).transpose(2, 0, 1)
    cond = np.linalg.cond(np.eye(STAGES) - g.transpose(2, 0, 1))
    # backward-stable solves of the same systems agree to a few ulps times the condition
    assert np.all(np.max(np.abs(got - want), axis=(1, 2))
                  <= 1e-13 * cond * np.max(np.abs(want), axis=(1, 2)))


class _Constant:
    """``q' = v``, ``v' = u F + g_v``, ``F = f . y + f0`` with constant coefficients."""

    def __init__(self) -> None:
        self.u = np.array([-0.3, 0.5])
        self.f = np.array([-2.0e3, 3.0e3, -1.5, 2.5])
        self.f0 = 40.0
        self.gv = np.array([6.0, -12.0])

    def force_form(self, t: Any) -> tuple[Any, Any, Any, Any]:
        n = np.asarray(t).size
        return (np.tile(self.u, (n, 1)), np.tile(self.f, (n, 1)), np.full(n, self.f0),
                self.gv)

    def augmented(self) -> Any:
        a = np.zeros((5, 5))
        a[0, 2] = a[1, 3] = 1.0
        a[2:4, :4] = np.outer(self.u, self.f)
        a[2:4, 4] = self.u * self.f0 + self.gv
        return a


def test_step_map_is_the_exponential_to_order_2s() -> None:
    """For constant coefficients the s-stage Gauss map is the (s, s) Pade approximant of
    exp(A h): its error is below (s!)^2 / ((2s)! (2s+1)!) |A h|^(2s+1) (Hairer & Wanner 1996,
    IV.3) for small |A h|, far below rounding here (4e-17 at |A h| = 0.1), so the test allows
    1e3 ulps on top; a method of order 2 would miss by 1e-4."""
    model = _Constant()
    a = model.augmented()
    h = np.array([0.02, 0.05, 0.1]) / np.linalg.norm(a, 2)  # |A h| up to 0.1
    maps = _maps(model, np.zeros(h.size), h)  # type: ignore[arg-type]
    for hi, got in zip(h, maps, strict=True):
        want = expm(a * hi)
        s = STAGES
        pade = (math.factorial(s) ** 2 / (math.factorial(2 * s) * math.factorial(2 * s + 1))
                * (np.linalg.norm(a * hi, 2) ** (2 * s + 1)))
        assert np.max(np.abs(got - want)) <= (pade + 1e3 * 2.2e-16) * np.max(np.abs(want))
