"""The torsional kernel table's degree search: screening on a few pieces changes nothing."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gear_dyn.eccentricity import Eccentricity
from gear_dyn.geometry import GearPair
from gear_dyn.models.torsional import ContactLineStiffness, TorsionalModel
from gear_dyn.solvers.kernel import tables_torsional


def test_screened_degree_search_gives_the_table_of_the_full_search(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """A degree that fails on some pieces fails on all: the screen only skips work."""
    pair = GearPair(20, 40, 3e-3, math.radians(20), 0.03, math.radians(15))  # 40-cycle period
    model = TorsionalModel(pair, 150.0, 50.0, ContactLineStiffness(1.1e10), (2e-3, 0.03),
                           eccentricity=Eccentricity(1e-4, 1.5e-4, 0.3, 1.0), friction=0.05)
    screened = tables_torsional.torsional_table(model, lines=False)
    monkeypatch.setattr(tables_torsional, "SCREEN", 1)  # every piece: no screen
    full = tables_torsional.torsional_table(model, lines=False)
    assert screened.degree == full.degree > tables_torsional.MIN_DEGREE  # some degree failed
    np.testing.assert_array_equal(screened.coef, full.coef)
    assert screened.max_error == full.max_error
