"""The compiled kernel (gear_dyn.solvers.kernel) against plain numpy loops, under AddressSanitizer
and UBSan, and the exact route that uses it against the Python expm reference and solve_ivp.

Tolerances: the kernel does the same floating-point products as the numpy loops in another
order of summation (n = 2 terms), so they agree to a few ulps of the values (1e-13 relative
over a few thousand chained maps of norm <= 1). The exact route has no truncation error: against
the step-by-step expm reference, 1e-12 of the static deflection (as in test_exact.py); against
DOP853 at rtol 1e-12, DOP853's own global error, 1e-9.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import textwrap
import threading
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from test_exact import stepwise_reference

from gear_dyn.errors import SolverError
from gear_dyn.models.sdof import SDOFModel
from gear_dyn.solvers import SolverSettings, integrate, kernel, time_grid
from gear_dyn.solvers.exact import propagate_exact, propagate_pieces
from gear_dyn.stiffness.periodic import rectangular_stiffness

SRC = kernel.SOURCE_DIR


def random_maps(count: int, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Affine maps with spectral norm 0.99 (a damped response: chains stay bounded)."""
    rng = np.random.default_rng(seed)
    f = rng.standard_normal((count, n, n))
    f *= 0.99 / np.linalg.norm(f, 2, axis=(1, 2))[:, None, None]
    return f, rng.standard_normal((count, n))


def numpy_fill(f: np.ndarray, h: np.ndarray, y0: np.ndarray, n_samples: int) -> np.ndarray:
    """Every sample from the one before: y_{i+1} = f[i mod S] y_i + h[i mod S]."""
    out = np.empty((y0.size, n_samples))
    y = y0.copy()
    for i in range(n_samples):
        out[:, i] = y
        y = f[i % f.shape[0]] @ y + h[i % f.shape[0]]
    return out


@pytest.mark.parametrize("n", [1, 2, 4])
def test_products_chain_and_fill_match_numpy(n: int) -> None:
    """Products, chain and the periodic fill against numpy loops: 16 maps per period over 40
    periods, and a span shorter than one period."""
    f, h = random_maps(16, n, n)
    y0 = np.linspace(-1.0, 1.0, n)
    q, r = kernel.products(f, h)
    qq, rr = np.eye(n), np.zeros(n)
    for j in range(16):
        qq, rr = f[j] @ qq, f[j] @ rr + h[j]
        assert np.allclose(q[j + 1], qq, rtol=0, atol=1e-14)
        assert np.allclose(r[j + 1], rr, rtol=0, atol=1e-13)
    ys = kernel.chain(f, h, y0)
    assert np.allclose(ys, numpy_fill(f, h, y0, 17).T, rtol=0, atol=1e-13)
    for n_samples in (641, 650, 9):
        y, finite = kernel.fill_periodic(q, r, y0, n_samples, 16)
        assert finite
        assert np.max(np.abs(y - numpy_fill(f, h, y0, n_samples))) < 1e-13


def test_compose_matches_numpy() -> None:
    """Steps composed of their parts in time order (one step has none: identity), against
    numpy products; an owner list out of order is refused."""
    rng = np.random.default_rng(5)
    parts = rng.standard_normal((9, 3, 3))
    owner = np.array([0, 0, 1, 1, 1, 3, 4, 4, 4])
    total = kernel.compose(parts, owner, 5)
    for step in range(5):
        ref = np.eye(3)
        for i in np.flatnonzero(owner == step):
            ref = parts[i] @ ref
        assert np.allclose(total[step], ref, rtol=0, atol=1e-13)
    with pytest.raises(ValueError, match="non-decreasing"):
        kernel.compose(parts, owner[::-1], 5)


def test_grid_error_matches_numpy() -> None:
    """The distance of a grid from the uniform one, against numpy; NaN propagates."""
    t = np.arange(1000) * 1e-5 + 0.25
    t[400] += 3e-12
    assert kernel.grid_error(t, 0.25, 1e-5) == np.max(np.abs(t - (0.25 + np.arange(1000) * 1e-5)))
    t[7] = np.nan
    assert np.isnan(kernel.grid_error(t, 0.25, 1e-5))


def test_fill_reports_divergence() -> None:
    """A growing map overflows: the fill says so and the samples from there on are NaN."""
    f = np.full((1, 1, 1), 1e10)
    q, r = kernel.products(f, np.zeros((1, 1)))
    y, finite = kernel.fill_periodic(q, r, np.ones(1), 100, 1)
    assert not finite and np.isnan(y[0, -1]) and y[0, 1] == 1e10


def test_calls_run_from_threads() -> None:
    """ctypes releases the GIL: four threads fill at once and each gets its own exact answer."""
    f, h = random_maps(64, 2, 7)
    q, r = kernel.products(f, h)
    ref = kernel.fill_periodic(q, r, np.ones(2), 20001, 64)[0]
    got: list[np.ndarray] = []
    threads = [threading.Thread(target=lambda: got.append(
        kernel.fill_periodic(q, r, np.ones(2), 20001, 64)[0])) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(got) == 4 and all(np.array_equal(g, ref) for g in got)


def test_missing_library_names_the_install(monkeypatch: pytest.MonkeyPatch) -> None:
    """No built library: the first use says how to build it."""
    monkeypatch.setattr(kernel, "library_path", lambda: None)
    kernel.library.cache_clear()
    try:
        with pytest.raises(SolverError, match="pip install"):
            kernel.products(np.eye(2)[None], np.zeros((1, 2)))
    finally:
        monkeypatch.undo()
        kernel.library.cache_clear()


def test_library_of_the_installed_distribution(monkeypatch: pytest.MonkeyPatch,
                                               tmp_path: Path) -> None:
    """A source tree without its own build (tests of a checkout after ``pip install .``) loads
    the installed distribution's library; with neither, there is none."""
    import importlib.metadata

    built = kernel.library_path()
    assert built is not None

    class Dist:
        url = "{}"

        def locate_file(self, path: str) -> Path:
            return built.parent if path == "gear_dyn/solvers/kernel" else tmp_path / path

        def read_text(self, name: str) -> str:
            return self.url

    monkeypatch.setattr(kernel, "SOURCE_DIR", tmp_path)
    monkeypatch.setattr(importlib.metadata, "distributions", lambda name: [Dist()])
    assert kernel.library_path() == built
    monkeypatch.setattr(Dist, "locate_file", lambda self, path: tmp_path / path)
    assert kernel.library_path() is None
    # an editable install: the library built in its source tree
    tree = built.parents[3]
    Dist.url = json.dumps({"url": tree.as_uri(), "dir_info": {"editable": True}})
    assert kernel.library_path() == built


def heli_model(phase0: float = 0.0, xi: float = 0.06) -> SDOFModel:
    """Helicopter-tail magnitudes, rectangular wave of contact ratio 1.58."""
    return SDOFModel(mass=3.0, stiffness=rectangular_stiffness(1.58, 0.7e9, 1.24e9),
                     damping_ratio=xi, static_load=2.0e4, mesh_frequency=1272.0, phase0=phase0)


@pytest.mark.parametrize(("phase0", "xi", "spp", "periods"),
                         [(0.0, 0.06, 32, 30), (0.137, 0.06, 64, 30), (0.61, 0.0, 7, 20),
                          (0.3, 1.0, 16, 30)])
def test_exact_periodic_route_matches_expm_reference(phase0: float, xi: float, spp: int,
                                                     periods: int) -> None:
    """The kernel's periodic fill (one period of exact step maps) against the step-by-step expm
    reference and against the whole-span piece route: switching instants on and off the grid,
    undamped, critically damped (Pade route), a grid of 7 samples per period. Undamped, the
    rounding of either side grows linearly (measured 1.3e-12 after 60 periods, peak 3.9 x_s):
    20 periods there."""
    model = heli_model(phase0, xi)
    t = time_grid(model.mesh_frequency, periods / model.mesh_frequency, spp)
    y0 = np.array([1e-5, -0.3])
    y, st = propagate_exact(model, t, None, y0)
    pieces = model.linear_segments(float(t[0]), float(t[-1]))
    assert pieces is not None and st["n_segments"] == len(pieces)
    ref = stepwise_reference(pieces, t, y0)
    whole, _ = propagate_pieces(pieces, t, y0)
    xs = model.static_load / model.mean_stiffness
    assert np.max(np.abs(y[0] - ref[0])) / xs < 1e-12
    assert np.max(np.abs(y[0] - whole[0])) / xs < 1e-12
    assert "step_maps" in st  # the period's piece maps, for the Floquet check


def test_nearly_commensurate_grid_takes_the_whole_span() -> None:
    """A grid commensurate with the mesh period to 1e-8 only (the periodic method accepts it):
    recurring step maps would drift against the switching instants (2.8e-6 of x_s measured
    after 30 periods), so exact propagates the whole span and stays at rounding level."""
    from gear_dyn.solvers.exact import _samples_per_period

    model = heli_model(0.1)
    t = time_grid(model.mesh_frequency, 30 / model.mesh_frequency, 64)
    assert _samples_per_period(model, t) == 64
    t = t * (1 + 1e-8)
    assert _samples_per_period(model, t) == 0
    y0 = np.array([1e-5, -0.3])
    y, _ = propagate_exact(model, t, None, y0)
    ref = stepwise_reference(model.linear_segments(float(t[0]), float(t[-1])), t, y0)
    assert np.max(np.abs(y[0] - ref[0])) / (model.static_load / model.mean_stiffness) < 1e-12


def test_exact_periodic_route_matches_dop853() -> None:
    """The exact route against DOP853 at rtol 1e-12 (restarted at every jump), 20 periods."""
    from gear_dyn.analysis.accuracy import relative_errors

    model = heli_model(0.2)
    t = time_grid(model.mesh_frequency, 20 / model.mesh_frequency, 64)
    y_ex, st = integrate(model, t, SolverSettings(method="exact"))
    y_ode, _ = integrate(model, t, SolverSettings(method="DOP853", rtol=1e-12))
    assert relative_errors(model, t, y_ex, y_ode)[0] < 1e-9


def test_short_span_and_diverging_response() -> None:
    """Shorter than one period: the partial products are the states; a parametrically
    unstable model (no damping, large stiffness variation at resonance) raises SolverError."""
    model = heli_model(0.1)
    t = time_grid(model.mesh_frequency, 0.5 / model.mesh_frequency, 64)
    y, _ = propagate_exact(model, t)
    pieces = model.linear_segments(float(t[0]), float(t[-1]))
    ref = stepwise_reference(pieces, t, model.initial_state())
    assert np.max(np.abs(y[0] - ref[0])) / (model.static_load / model.mean_stiffness) < 1e-12
    k = rectangular_stiffness(1.5, 0.2e9, 1.8e9)
    fn = np.sqrt(1.0e9 / 3.0) / (2 * np.pi)
    wild = replace(heli_model(xi=0.0), stiffness=k, mesh_frequency=2 * fn)
    with pytest.raises(SolverError, match="non-finite"):
        propagate_exact(wild, time_grid(wild.mesh_frequency, 20000 / wild.mesh_frequency, 8))


def _sanitizer_runtime(cc: str) -> str | None:
    """The ASan runtime library the compiler links, or None."""
    out = subprocess.run([cc, "-print-file-name=libasan.so"], capture_output=True, text=True,
                         check=False).stdout.strip()
    return out if out and os.path.isabs(out) and os.path.isfile(out) else None


def test_kernel_under_sanitizers(tmp_path: Path) -> None:
    """The library built with -fsanitize=address,undefined, loaded by ctypes in a child Python
    (the ASan runtime preloaded), runs every entry point of gd_flow.c against numpy (the
    contact walk's against DOP853), and the steppers over a grid (gd_run.c: the ``kernel``
    method) on a backlash model against ``exact_contact`` and on the eccentric torsional model
    against ``gauss``."""
    cc = shutil.which(os.environ.get("CC", "cc")) or shutil.which("gcc")
    runtime = _sanitizer_runtime(cc) if cc else None
    if cc is None or runtime is None:
        pytest.skip(f"no sanitizer runtime (compiler {cc!r}, libasan.so not found)")
    so = tmp_path / "libgd_asan.so"
    cmd = [cc, "-std=c99", "-g", "-O1", "-fPIC", "-shared", "-Wall", "-Wextra", "-Werror",
           "-pedantic", "-fsanitize=address,undefined", "-fno-sanitize-recover=all",
           f"-I{SRC}",
           *(str(SRC / s) for s in ("gd_flow.c", "gd_linear.c", "gd_kernel.c", "gd_torsional.c",
                                     "gd_run.c")),
           "-o", str(so), "-lm"]
    subprocess.run(cmd, check=True, capture_output=True)
    script = textwrap.dedent(f"""
        import numpy as np
        from pathlib import Path
        import gear_dyn.solvers.kernel as k
        k.library_path = lambda: Path({str(so)!r})
        k.library.cache_clear()
        rng = np.random.default_rng(3)
        f = rng.standard_normal((16, 2, 2)) * 0.4
        h = rng.standard_normal((16, 2))
        q, r = k.products(f, h)
        y0 = np.array([0.5, -1.0])
        ys = k.chain(f, h, y0)
        y, ok = k.fill_periodic(q, r, y0, 100, 16)
        ref = [y0]
        for i in range(99):
            ref.append(f[i % 16] @ ref[-1] + h[i % 16])
        assert ok and np.allclose(y, np.array(ref).T, rtol=1e-12, atol=1e-12)
        assert np.allclose(ys, np.array(ref[:17]), rtol=1e-12, atol=1e-12)
        tot = k.compose(rng.standard_normal((5, 3, 3)), np.array([0, 0, 2, 2, 3]), 4)
        assert tot.shape == (4, 3, 3) and np.array_equal(tot[1], np.eye(3))
        t = np.arange(50) * 0.1
        assert k.grid_error(t, 0.0, 0.1) == np.max(np.abs(t - np.arange(50) * 0.1))
        # the linear single-DOF steps (gd_linear.c), three lanes on two tables, against the
        # products of their own step maps; then every caller in linear_maps
        from scipy.linalg import expm
        from gear_dyn.solvers import linear_maps as lm
        from gear_dyn.models.sdof import SDOFModel
        from gear_dyn.solvers.kernel import linear as kl
        from gear_dyn.stiffness.periodic import FourierStiffness, rectangular_stiffness
        b = rng.standard_normal((7, 2, 2))
        assert np.allclose(kl.expm2(b), [expm(x) for x in b], rtol=1e-12, atol=1e-12)
        rows = np.zeros((2, 9, kl.ROW_FIELDS))
        rows[..., 0] = 1 / 9
        rows[..., 1:3] = 4e6 * (1 + 0.1 * rng.uniform(-1, 1, (2, 9, 2)))
        rows[..., 3], rows[..., 4:6], rows[..., 6:8] = 50.0, 10.0, 1e-3
        fm, table = np.array([300.0, 700.0, 1100.0]), np.array([0, 1, 1])
        fs, hs = kl.step_maps(rows, fm, table)
        p, u = kl.period_products(rows, fm, np.array([2, 8]), table)
        ys = kl.responses(fs[0], hs)
        for s in range(3):
            q, r = k.products(fs[s], hs[s])
            assert np.allclose(p[s], q[[3, 9]], rtol=1e-12, atol=1e-12)
            assert np.allclose(u[s], r[[3, 9]], rtol=1e-12, atol=1e-12)
            assert np.allclose(ys[s], k.products(fs[0], hs[s])[1], rtol=1e-12, atol=1e-12)
        rect = [SDOFModel(mass=3.0, stiffness=rectangular_stiffness(1.41, 1e9, 1.3e9),
                          damping_ratio=0.06, static_load=2000.0, mesh_frequency=f)
                for f in (1500.0, 2500.0)]
        y, phi = lm.piecewise_orbits(rect, np.array([1500.0, 2500.0]), 16)
        assert y.shape == (2, 2, 16) and np.all(np.isfinite(y)) and phi.shape == (2, 2, 2)
        assert np.all(np.isfinite(lm.harmonic_orbits(rect[0], np.array([1.0, 2.5]), 16)[3]))
        mono = lm.cell_monodromy(3.0, np.array([0.0, 0.41, 1.0]), np.array([1.3e9, 1e9]),
                                 np.array([[50.0], [80.0]]), np.array([[900.0, 2000.0]]))
        assert mono[0].shape == (2, 2) and np.all(np.isfinite(mono))
        four = [SDOFModel(mass=3.0, stiffness=FourierStiffness(1.2e9, np.array([1e8]),
                                                               np.array([0.0])),
                          damping_ratio=0.06, static_load=2000.0, mesh_frequency=f)
                for f in (1500.0, 2500.0)]
        y, phi = lm.magnus_orbits(four, 16, 1e-8)
        assert y.shape == (2, 2, 16) and np.all(np.isfinite(y)) and np.all(np.isfinite(phi))
        # the contact walk: a backlash model with a two-harmonic transmission error at
        # resonance (the bounded crossing search) and without one (the unforced search)
        from gear_dyn.excitation import HarmonicSignal
        from gear_dyn.models.sdof import SDOFModel
        from gear_dyn.solvers import SolverSettings, integrate
        from gear_dyn.solvers import contact_exact as ce
        from gear_dyn.solvers.kernel import contact as ck
        from gear_dyn.stiffness.periodic import rectangular_stiffness
        te = HarmonicSignal(2e-6, np.array([8e-6, 1.5e-6]), np.array([3e-6, -2e-6]))
        fn = np.sqrt(1e9 / 3.0) / (2 * np.pi)
        for sig in (te, None):
            m = SDOFModel(mass=3.0, stiffness=rectangular_stiffness(1.41, 1e9, 1.3e9),
                          damping_ratio=0.06, static_load=2000.0, mesh_frequency=fn,
                          backlash=1e-5, transmission_error=sig)
            tg = np.linspace(0.0, 8 / fn, 257)
            y, st = ce.propagate_contact_exact(m, tg)
            yd, _ = integrate(m, tg, SolverSettings(method="DOP853", rtol=1e-10))
            assert st["n_contact_events"] > 4
            assert np.max(np.abs(y - yd) / m.state_scale[:, None]) < 1e-6
            w = ce.walk(m, m.initial_state(), 8 / fn, marks=np.arange(1, 8) / fn)
            assert np.all(np.isfinite(w.mark_sensitivities())) and w.sensitivity().shape == (2, 2)
            if sig is not None:  # one piece of 30 periods: the segment table grows
                mm, pieces = w._tables
                segs = ck.walk(mm, pieces, np.array([0.0, 30 / fn]), np.array([0]),
                               *m.initial_state(), 1e-18, 1000)
                assert segs.status == ck.OK and segs.table.shape[0] > 68
            pc = ce._Piece(m, 1e9, ce.GAP)
            ce._first_crossing(pc, 0.0, 0.0, 0.02, 3 * pc.h, 1e-18)
            pc.stays_inside(0.0, 0.0)
            pc.at(0.0, 0.02, np.linspace(0.0, pc.h, 9), 1e-4)
        assert abs(ce.find_root(lambda x: x - 0.3, 0.0, 1.0, -0.3, 0.7, 1e-15) - 0.3) < 1e-14
        # the steppers over a grid: the kernel method
        from gear_dyn.scene import load_scene
        from gear_dyn.scene.build import build_plan
        from gear_dyn.solvers import time_grid
        bl = SDOFModel(mass=3.0, stiffness=rectangular_stiffness(1.58, 0.7e9, 1.24e9),
                       damping_ratio=0.06, static_load=1000.0, mesh_frequency=2900.0,
                       backlash=1e-5)
        tg = time_grid(bl.mesh_frequency, 30 / bl.mesh_frequency, 64)
        y, st = integrate(bl, tg, SolverSettings(method="kernel"))
        y_e, _ = integrate(bl, tg, SolverSettings(method="exact_contact"))
        assert st["n_events"] > 10 and np.max(np.abs(y - y_e)[0]) < 1e-6 * bl.state_scale[0]
        ecc = build_plan(load_scene("eccentric_helical")).model
        tg = time_grid(ecc.mesh_frequency, 10 / ecc.mesh_frequency, 16)
        y, _ = integrate(ecc, tg, SolverSettings(method="kernel"))
        y_g, _ = integrate(ecc, tg, SolverSettings(method="gauss", rtol=1e-9))
        assert np.max(np.abs(y - y_g) / ecc.state_scale[:, None]) < 1e-4
        print("ok")
    """)
    env = {**os.environ, "LD_PRELOAD": runtime, "ASAN_OPTIONS": "detect_leaks=0",
           "UBSAN_OPTIONS": "halt_on_error=1"}
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          env=env, cwd=Path(__file__).resolve().parents[2], check=False)
    assert proc.returncode == 0 and proc.stdout.strip() == "ok", proc.stderr[-2000:]
    assert "runtime error" not in proc.stderr and "ERROR: AddressSanitizer" not in proc.stderr
