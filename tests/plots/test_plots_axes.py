"""The plot layer chooses no backend, never loads pyplot, and draws into the caller's axes."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from matplotlib.figure import Figure

import gear_dyn as gd
from gear_dyn.plots import run, stiffness, sweep
from gear_dyn.stiffness.potential_energy import PairCompliance

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "gear_dyn" / "scenes" / "helicopter_tail.toml"
MODULES = ["gear_dyn.plots", "gear_dyn.plots._axes", "gear_dyn.plots._decimate",
           "gear_dyn.plots.run", "gear_dyn.plots.bench", "gear_dyn.plots.contact",
           "gear_dyn.plots.excitation", "gear_dyn.plots.stiffness", "gear_dyn.plots.sweep",
           "gear_dyn.plots.cosim"]

# Run in a fresh interpreter: records matplotlib.use calls and the backend setting before and
# after importing the module given as argv[1], and whether pyplot got loaded.
_PROBE = """
import importlib, json, sys
import matplotlib

calls = []
matplotlib.use = lambda *a, **k: calls.append(repr(a))

def backend():
    try:
        return matplotlib.get_backend(auto_select=False)  # matplotlib >= 3.10
    except TypeError:
        return dict.__getitem__(matplotlib.rcParams, "backend")

before = backend()
importlib.import_module(sys.argv[1])
after = backend()
print(json.dumps({"use_calls": calls, "backend_unchanged": after is before or after == before,
                  "pyplot": "matplotlib.pyplot" in sys.modules}))
"""

_SAVE = """
import sys
from matplotlib.figure import Figure
from gear_dyn.io import save_figure
fig = Figure(figsize=(2, 1))
fig.subplots().plot([0, 1], [1, 0])
path = save_figure(fig, sys.argv[1], dpi=50)
print("matplotlib.pyplot" in sys.modules, path.read_bytes()[:8] == b"\\x89PNG\\r\\n\\x1a\\n")
"""


def _python(code: str, *args: str) -> str:
    env = {k: v for k, v in os.environ.items() if k != "MPLBACKEND"}
    proc = subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True,
                          cwd=ROOT, env=env, timeout=120, check=False)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout.strip().splitlines()[-1]


@pytest.mark.parametrize("module", MODULES)
def test_import_chooses_no_backend_and_no_pyplot(module: str) -> None:
    out = json.loads(_python(_PROBE, module))
    assert out["use_calls"] == [], f"{module} calls matplotlib.use{out['use_calls']}"
    assert out["backend_unchanged"], f"{module} sets the matplotlib backend"
    assert not out["pyplot"], f"{module} imports matplotlib.pyplot"


def test_save_figure_renders_a_pyplot_free_figure(tmp_path: Path) -> None:
    assert _python(_SAVE, str(tmp_path / "f.png")) == "False True"


@pytest.fixture(scope="module")
def result() -> Any:
    return gd.run_scene(gd.load_scene(SCENE), periods=40)


@pytest.fixture(scope="module")
def chart() -> Any:
    from gear_dyn.analysis.chart import stability_chart
    from gear_dyn.scene import build_model

    model = build_model(gd.load_scene(SCENE))
    return stability_chart(model, np.linspace(0.2, 2.5, 30), np.linspace(0.0, 0.5, 12))


def _drawn(ax: Any) -> bool:
    return bool(ax.lines or ax.collections or ax.patches)


def test_run_plots_draw_into_given_axes(result: Any) -> None:
    fig = Figure()
    ax = fig.subplots()
    assert run.plot_spectrum(result, ax=ax) is fig
    assert ax.lines
    fig = Figure()
    axes = fig.subplots(2, 2)
    assert run.plot_time_history(result, ax=axes) is fig
    assert all(a.lines for a in axes.flat)
    fig = Figure()
    axes = fig.subplots(2, 1)
    assert run.plot_time_history(result, periods=None, ax=list(axes)) is fig
    assert all(a.lines for a in axes)


def test_run_plots_make_their_own_figure(result: Any) -> None:
    fig = run.plot_time_history(result)
    assert isinstance(fig, Figure) and len(fig.axes) == 4
    fig = run.plot_spectrum(result)
    assert isinstance(fig, Figure) and len(fig.axes) == 1


def test_wrong_number_of_axes_names_the_function(result: Any) -> None:
    axes = Figure().subplots(1, 3)
    with pytest.raises(ValueError, match=r"plot_time_history: expected 2 Axes .* or 4"):
        run.plot_time_history(result, ax=axes)


def test_stiffness_plots_draw_into_given_axes() -> None:
    k = gd.rectangular_stiffness(1.6, 1.0e8, 1.7e8)
    fig = Figure()
    ax = fig.subplots()
    assert stiffness.plot_stiffness_curves({"rectangular": k}, 1.6, ax=ax) is fig
    assert ax.lines and ax.patches  # the curve and the shaded double-contact zones
    one = np.full(1, 1e-11)
    comp = PairCompliance(hertz=one, bending=np.full((2, 1), 2e-11), shear=np.full((2, 1), 1e-11),
                          axial=np.full((2, 1), 1e-12), fillet=np.full((2, 1), 3e-11))
    fig = Figure(layout="constrained")  # the caller's layout engine is kept, no warning
    ax = fig.subplots()
    assert stiffness.plot_components(comp, ax=ax) is fig
    assert len(ax.patches) == 9


def test_stability_charts_draw_into_given_axes(chart: Any) -> None:
    fig = Figure()
    ax = fig.subplots()
    assert sweep.plot_stability_chart(chart, ax=ax, sweep_range=(0.5, 1.5)) is fig
    assert ax.collections and ax.lines
    fig = Figure()
    axes = fig.subplots(2, 1)
    assert sweep.plot_stability_charts([chart, chart], sweep_range=(0.5, 1.5), ax=axes) is fig
    assert all(_drawn(a) for a in axes)
    fig = sweep.plot_stability_charts([chart, chart], title="two charts")
    assert tuple(fig.get_size_inches()) == pytest.approx((8, 8.4))
    assert [a.get_title() for a in fig.axes if a.get_title()] == ["two charts"] * 2


def test_tidy_leaves_no_layout_engine_so_saving_draws_once(tmp_path: Path) -> None:
    """tight_layout leaves a placeholder engine, with which savefig lays the figure out in a
    draw pass of its own: tidy removes it (the figure then draws once when saved), and keeps
    a caller's constrained layout."""
    from gear_dyn.plots._axes import tidy

    fig = Figure(figsize=(4, 3))
    fig.subplots().plot([0, 1], [0, 1])
    tidy(fig)
    assert fig.get_layout_engine() is None
    draws = []
    fig.canvas.mpl_connect("draw_event", lambda _e: draws.append(1))
    fig.savefig(tmp_path / "a.png", dpi=50)
    assert len(draws) == 1
    constrained = Figure(figsize=(4, 3), layout="constrained")
    constrained.subplots()
    tidy(constrained)
    assert constrained.get_layout_engine() is not None
