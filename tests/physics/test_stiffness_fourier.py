"""The Fourier-series stiffness against its definition, term by term."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gear_dyn.stiffness.periodic import FourierStiffness, rectangular_stiffness

RNG = np.random.default_rng(7)
N = 40
FS = FourierStiffness(1.0e9, RNG.normal(size=N) * 1e7, RNG.normal(size=N) * 1e7)


@pytest.mark.parametrize("p", [0.0, 0.25, 0.371, 0.999999, 12.5, 1234.567])
def test_value_and_derivative_match_the_series_written_out(p: float) -> None:
    """k0 + sum a_n cos(2 pi n p) + b_n sin(2 pi n p) and its p-derivative, summed with
    math.cos/math.sin of the reduced phase; the powers' rounding grows like n ulps, so 1e-13
    of the largest term is a 20x margin at N = 40."""
    q = p - math.floor(p)
    k = FS.k0 + sum(FS.a[n - 1] * math.cos(2 * math.pi * n * q)
                    + FS.b[n - 1] * math.sin(2 * math.pi * n * q) for n in range(1, N + 1))
    dk = sum(2 * math.pi * n * (-FS.a[n - 1] * math.sin(2 * math.pi * n * q)
                                + FS.b[n - 1] * math.cos(2 * math.pi * n * q))
             for n in range(1, N + 1))
    scale = float(np.max(np.abs(FS.a)) + np.max(np.abs(FS.b)))
    assert float(FS(p)) == pytest.approx(k, abs=1e-13 * FS.k0)
    assert float(FS.derivative(p)) == pytest.approx(dk, abs=1e-13 * 2 * math.pi * N * N * scale)


def test_shapes_follow_the_phase_array() -> None:
    assert np.shape(FS(0.3)) == ()
    assert FS(np.zeros((2, 3))).shape == (2, 3)
    assert FS.derivative(np.zeros(5)).shape == (5,)


def test_truncated_series_of_the_rectangular_wave_has_its_mean_and_converges() -> None:
    """The series of a rectangular wave (exact coefficients) converges to it in the mean
    (L2 error falls like N^-1/2) and keeps the mean exactly."""
    rect = rectangular_stiffness(1.6, 3.0e8, 5.25e8)
    p = (np.arange(4000) + 0.5) / 4000
    errs = []
    for n in (25, 100, 400):
        k0, a, b = rect.fourier_coefficients(n)
        series = FourierStiffness(k0, a, b)
        assert float(np.mean(series(p))) == pytest.approx(float(np.mean(rect(p))), rel=1e-3)
        errs.append(float(np.sqrt(np.mean((series(p) - rect(p)) ** 2))))
    assert errs[1] < errs[0] / 1.5 and errs[2] < errs[1] / 1.5
