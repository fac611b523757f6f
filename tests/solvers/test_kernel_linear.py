"""The kernel's linear single-DOF steps (gear_dyn.solvers.kernel.linear, gd_linear.c) against
scipy.linalg.expm of the augmented generator built here from its definition, and a period of
Magnus steps against DOP853.

Tolerances: the closed form and scipy's Pade approximant are both exact up to rounding, so an
exponential agrees to 1e-12 of its largest entry (a few hundred ulps: the closed form loses a
few digits to cancellation in ``cosh - sinh`` of large damped arguments, scipy to scaling and
squaring). A product of 40 such maps of norm about 1 carries that relative error, 40 times at
most: 1e-11 of the largest entry. The Magnus step is fourth order: its error over a period
falls 16-fold per halving of the step (asserted between 10 and 22, the fourth-order ratio with
the next term's share); against DOP853 at rtol 1e-12 (its own error ~1e-11 of the state) the
kernel at the substep rule for rtol 1e-10 agrees to 1e-8 of the state (the rule bounds the
period's error near rtol; 100 rtol leaves margin for the growth of the error over the period).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm

from gear_dyn.solvers.kernel.linear import (
    ROW_FIELDS,
    expm2,
    period_products,
    responses,
    step_maps,
)

G = math.sqrt(3) / 6  # Gauss points at 1/2 -+ G of a step


def test_expm2_matches_scipy() -> None:
    rng = np.random.default_rng(3)
    cases = [rng.normal(size=(2, 2)) * scale for scale in (1e-6, 1e-2, 1.0, 5.0, 30.0)]
    cases += [np.array([[1.0, 1.0], [0.0, 1.0]]),  # d2 = 0: a Jordan block
              np.array([[0.0, 1e-3], [-1e-6, -2e-5]]),  # |d2| tiny: the series of S
              np.array([[0.0, 1e-4], [-4e4, -0.3]]),  # a cell of a stiff oscillator
              np.array([[0.0, 3e-4], [-1e3, -1.0]])]  # overdamped: cosh and sinh
    got = expm2(np.stack(cases))
    for b, e in zip(cases, got, strict=True):
        ref = expm(b)
        assert np.max(np.abs(e - ref)) <= 1e-12 * np.max(np.abs(ref)), b


def test_expm2_rejects_other_shapes() -> None:
    with pytest.raises(ValueError, match=r"need \(\.\.\., 2, 2\)"):
        expm2(np.zeros((3, 3)))


def augmented(row: np.ndarray, fm: float) -> np.ndarray:
    """exp of the fourth-order Magnus generator of [x, v, 1] over one step row, from its
    definition: Omega = h/2 (A_a + A_b) + sqrt(3)/12 h^2 [A_b, A_a] (3x3, by scipy)."""
    length, ka, kb, gam, g0a, g0b, g1a, g1b = row
    h = length / fm

    def a(kappa: float, g: float) -> np.ndarray:
        return np.array([[0.0, 1.0, 0.0], [-kappa, -gam, g], [0.0, 0.0, 0.0]])

    a1, a2 = a(ka, g0a + fm * g1a), a(kb, g0b + fm * g1b)
    return expm(h / 2 * (a1 + a2) + math.sqrt(3) / 12 * h * h * (a2 @ a1 - a1 @ a2))


def random_rows(n: int, seed: int) -> np.ndarray:
    """Step rows of a stiff, lightly damped oscillator (kappa ~ 4e8 1/s^2: f_n ~ 3 kHz) with a
    static load and a transmission-error slope, one mesh period cut into n steps."""
    rng = np.random.default_rng(seed)
    rows = np.empty((n, ROW_FIELDS))
    rows[:, 0] = rng.uniform(0.5, 1.5, n)
    rows[:, 0] /= rows[:, 0].sum()
    rows[:, 1:3] = 4e8 * (1 + 0.2 * rng.uniform(-1, 1, (n, 2)))
    rows[:, 3] = 150.0
    rows[:, 4:6] = 2e3 * (1 + 0.1 * rng.uniform(-1, 1, (n, 2)))
    rows[:, 6:8] = 1e-3 * rng.uniform(-1, 1, (n, 2))
    return rows


def test_step_maps_match_the_augmented_exponential() -> None:
    rows = random_rows(12, 1)
    rows[3, 2], rows[3, 5], rows[3, 7] = rows[3, 1], rows[3, 4], rows[3, 6]  # a constant cell
    fm = np.array([800.0, 2500.0, 9000.0])
    f, h = step_maps(rows, fm)
    for s, fs in enumerate(fm):
        for i, row in enumerate(rows):
            ref = augmented(row, fs)
            assert np.max(np.abs(f[s, i] - ref[:2, :2])) <= 1e-12 * np.max(np.abs(ref[:2, :2]))
            assert np.max(np.abs(h[s, i] - ref[:2, 2])) <= 1e-12 * np.max(np.abs(ref[:2, 2]))


def test_period_products_match_scipy_products() -> None:
    # two tables, four lanes: lane s uses table (0, 1, 1, 0)[s] at its own mesh frequency
    rows = np.stack([random_rows(40, 2), random_rows(40, 3)])
    table = np.array([0, 1, 1, 0])
    fm = np.array([700.0, 1900.0, 5200.0, 11000.0])
    keep = np.array([4, 17, 39])
    p, u = period_products(rows, fm, keep, table)
    assert p.shape == (4, 3, 2, 2) and u.shape == (4, 3, 2)
    for s in range(fm.size):
        total, kept = np.eye(3), []
        for i, row in enumerate(rows[table[s]]):
            total = augmented(row, fm[s]) @ total
            if i in keep:
                kept.append(total)
        for k, ref in enumerate(kept):
            scale = np.max(np.abs(ref[:2]))
            assert np.max(np.abs(p[s, k] - ref[:2, :2])) <= 1e-11 * scale
            assert np.max(np.abs(u[s, k] - ref[:2, 2])) <= 1e-11 * np.max(np.abs(ref[:2, 2]))


def test_responses_match_a_numpy_loop() -> None:
    # the kernel does the same products in the same order: equal to a few ulps
    rng = np.random.default_rng(5)
    f = rng.standard_normal((30, 2, 2)) * 0.5
    h = rng.standard_normal((3, 30, 2))
    y = responses(f, h)
    for s in range(3):
        ref = [np.zeros(2)]
        for i in range(30):
            ref.append(f[i] @ ref[-1] + h[s, i])
        assert np.allclose(y[s], ref, rtol=1e-13, atol=1e-13 * np.max(np.abs(ref)))
    with pytest.raises(ValueError, match="need"):
        responses(f, h[:, :29])


def test_period_products_check_their_inputs() -> None:
    rows = random_rows(5, 4)
    with pytest.raises(ValueError, match="not increasing"):
        period_products(rows, np.array([1e3]), np.array([3, 2]))
    with pytest.raises(ValueError, match="table indices"):
        period_products(rows, np.array([1e3]), np.array([4]), np.array([1]))
    with pytest.raises(ValueError, match="no table index per lane"):
        period_products(np.stack([rows, rows]), np.array([1e3]), np.array([4]))


def smooth_rows(n: int) -> np.ndarray:
    """Magnus rows of x'' = -kappa(p) x - gamma x' + g(p) over a period in n equal substeps,
    kappa = w2 (1 + 0.3 cos 2 pi p), g = g0 (1 + 0.5 sin 2 pi p)."""
    start = np.arange(n) / n
    rows = np.zeros((n, ROW_FIELDS))
    rows[:, 0] = 1.0 / n
    for col, p in ((1, start + (0.5 - G) / n), (2, start + (0.5 + G) / n)):
        rows[:, col] = 4e8 * (1 + 0.3 * np.cos(2 * np.pi * p))
        rows[:, col + 3] = 2e3 * (1 + 0.5 * np.sin(2 * np.pi * p))
    rows[:, 3] = 150.0
    return rows


def dop853_period(fm: float) -> tuple[np.ndarray, np.ndarray]:
    """The period map (monodromy, response from rest) by DOP853 at rtol 1e-12."""
    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        p = fm * t
        kappa = 4e8 * (1 + 0.3 * np.cos(2 * np.pi * p))
        g = 2e3 * (1 + 0.5 * np.sin(2 * np.pi * p))
        x, v = y[0::2], y[1::2]
        out = np.empty_like(y)
        out[0::2] = v
        out[1::2] = -kappa * x - 150.0 * v + g * np.array([0.0, 0.0, 1.0])
        return out

    y0 = np.array([1.0, 0.0, 0.0, 1.0, 0.0, 0.0])  # columns of I, then the response from rest
    sol = solve_ivp(rhs, (0.0, 1.0 / fm), y0, method="DOP853", rtol=1e-12, atol=1e-20)
    y = sol.y[:, -1]
    return np.array([[y[0], y[2]], [y[1], y[3]]]), y[4:6]


def test_magnus_period_is_fourth_order_and_matches_dop853() -> None:
    fm = 1500.0  # f_n / 2: near the principal parametric resonance, a demanding period
    mono, resp = dop853_period(fm)
    errs = []
    for n in (50, 100, 200):
        p, u = period_products(smooth_rows(n), np.array([fm]), np.array([n - 1]))
        errs.append(np.max(np.abs(u[0, 0] - resp)) / np.max(np.abs(resp)))
        assert np.allclose(p[0, 0], mono, rtol=1e-3, atol=1e-3 * np.max(np.abs(mono)))
    for coarse, fine in zip(errs, errs[1:], strict=False):
        assert 10 < coarse / fine < 22, errs
    # the substep rule for rtol 1e-10: (omega h / 2)^4 <= rtol
    omega = math.sqrt(4e8 * 1.3)
    n = math.ceil(omega / (2 * 1e-10 ** 0.25 * fm))
    p, u = period_products(smooth_rows(n), np.array([fm]), np.array([n - 1]))
    assert np.max(np.abs(u[0, 0] - resp)) <= 1e-8 * np.max(np.abs(resp))
    assert np.max(np.abs(p[0, 0] - mono)) <= 1e-8 * np.max(np.abs(mono))
