"""``result.plot``: figures as methods taking ``ax=None`` (notebooks), without the solver layer
importing matplotlib or the plots layer (the accessor looks the plots module up at call time)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from matplotlib.figure import Figure

import gear_dyn as gd

ROOT = Path(__file__).resolve().parents[2]

_PROBE = """
import json, sys
import gear_dyn.solvers.result
print(json.dumps(sorted(m for m in sys.modules
                        if m.split(".")[0] == "matplotlib" or m.startswith("gear_dyn.plots"))))
"""


def test_importing_result_loads_no_matplotlib_and_no_plots() -> None:
    proc = subprocess.run([sys.executable, "-c", _PROBE], capture_output=True, text=True,
                          cwd=ROOT, timeout=120, check=False)
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout.strip().splitlines()[-1]) == []


@pytest.fixture(scope="module")
def result() -> Any:
    return gd.run_scene(gd.load_scene("helicopter_tail"), periods=40)


def test_spectrum_draws_on_the_given_axes_and_returns_its_figure(result: Any) -> None:
    fig = Figure()
    ax = fig.subplots()
    assert result.plot.spectrum(ax=ax, scale="linear") is fig
    # the drawn curve is the DTE amplitude spectrum in um over the steady window
    from gear_dyn.analysis.spectrum import amplitude_spectrum

    f, amp = amplitude_spectrum(result.t[result.steady], result.outputs["dte"][result.steady])
    x, y = ax.lines[0].get_data()
    n = len(x)
    assert np.allclose(x, f[:n]) and np.allclose(y, amp[:n] * 1e6)
    assert ax.get_yscale() == "linear"


def test_time_draws_on_the_given_axes_and_returns_its_figure(result: Any) -> None:
    fig = Figure()
    axes = fig.subplots(2, 1)
    assert result.plot.time(periods=None, ax=axes) is fig
    # 40 mesh periods: the whole run is drawn as its band of per-period extremes, which
    # reaches the run's own largest and smallest DTE
    values, _, baseline = axes[0].patches[0].get_data()
    dte = result.outputs["dte"] * 1e6
    assert np.isclose(np.max(values), np.max(dte)) and np.isclose(np.min(baseline), np.min(dte))
    assert axes[1].lines or axes[1].patches


def test_methods_make_their_own_figure(result: Any) -> None:
    assert isinstance(result.plot.time(), Figure)
    assert len(result.plot.time().axes) == 4
    assert len(result.plot.spectrum().axes) == 1
