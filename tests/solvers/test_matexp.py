"""The numpy matrix exponential and balancing against scipy.linalg (a second implementation)."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from scipy.linalg import expm as scipy_expm

from gear_dyn.solvers.matexp import balance, expm


def gear_matrix(omega: float, zeta: float, g: float, dt: float) -> np.ndarray:
    """Augmented single-DOF matrix [[A, g], [0, 0]] * dt (states m and m/s: badly scaled)."""
    return np.array([[0.0, 1.0, 0.0], [-omega**2, -2 * zeta * omega, g], [0.0, 0.0, 0.0]]) * dt


CASES = [gear_matrix(3e4, 0.06, 1e4, dt) for dt in (1e-7, 1e-5, 3.9e-4, 1e-2)]
CASES += [gear_matrix(3e4, z, 1e4, 1e-3) for z in (0.0, 1.0, 3.0)]
rng = np.random.default_rng(4)
CASES += [rng.normal(size=(n, n)) * sc for n in (2, 5, 9) for sc in (0.01, 1.0, 20.0)]


def taylor_expm_longdouble(m: np.ndarray) -> np.ndarray:
    """exp(m) by a 40-term Taylor series of m / 2^k in 80-bit long double, squared k times."""
    a = m.astype(np.longdouble)
    k = int(np.ceil(np.log2(max(float(np.abs(a).sum(axis=0).max()), 1.0)))) + 4
    a = a / np.longdouble(2) ** k
    term: Any = np.eye(a.shape[0], dtype=np.longdouble)
    total = term.copy()
    for j in range(1, 40):
        term = term @ a / j
        total = total + term
    for _ in range(k):
        total = total @ total
    return total


@pytest.mark.parametrize("m", CASES)
def test_expm_matches_long_double_and_scipy(m: np.ndarray) -> None:
    ref = taylor_expm_longdouble(m)
    scale = float(np.abs(ref).max())
    ours = float(np.abs(expm(m) - ref).max()) / scale
    theirs = float(np.abs(scipy_expm(m) - ref).max()) / scale
    # forward error = u x the condition of exp at m (up to ~1e3 here, e.g. the overdamped gear
    # matrix): measured <= 5e-13 for both methods; 1e-11 is 20x that
    assert ours <= 1e-11
    assert ours <= 10 * theirs + 1e-14  # never much worse than scipy's Al-Mohy-Higham expm


def test_expm_stack_and_closed_form() -> None:
    theta = np.linspace(0.0, 30.0, 7)
    rot = np.stack([np.array([[0.0, -t], [t, 0.0]]) for t in theta])
    got = expm(rot)
    want = np.stack([np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]]) for t in theta])
    assert np.abs(got - want).max() < 1e-13
    assert np.abs(expm(np.zeros((3, 3))) - np.eye(3)).max() <= 2.3e-16


def test_balance_is_an_exact_similarity() -> None:
    m = gear_matrix(3e4, 0.06, 1e4, 1.0)
    b, d = balance(m)
    assert np.all(np.log2(d) == np.round(np.log2(d)))
    assert np.array_equal(b, m * d[None, :] / d[:, None])
    assert np.abs(b).max() < np.abs(m).max() / 100  # the rows and columns are evened out
