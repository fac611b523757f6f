"""Extreme but legal inputs run correctly (checked against closed forms or a second method) or
end in a clear InputError/SolverError: never NaN output, a hang or silent nonsense."""

from __future__ import annotations

import copy
import math
from typing import Any

import numpy as np
import pytest
from scene_cases import SCENES_DIR, load

from gear_dyn.errors import InputError, SceneError
from gear_dyn.scene import build_pair, build_plan, parse_scene, run_scene
from gear_dyn.solvers import MAX_NATURAL_PERIODS, MAX_SAMPLES, Result

HELI = load(SCENES_DIR / "helicopter_tail.toml")


def _scene(base: dict[str, Any] = HELI, **changes: Any) -> Any:
    """``base`` with changes given as table__key=value (None deletes the key)."""
    d = copy.deepcopy(base)
    for path, value in changes.items():
        table, key = path.split("__")
        d.setdefault(table, {})
        if value is None:
            d[table].pop(key, None)
        else:
            d[table][key] = value
    return parse_scene(d, "extreme.toml")


def _finite(r: Result) -> None:
    assert np.all(np.isfinite(r.y))
    for arr in r.outputs.values():
        assert np.all(np.isfinite(arr))
    assert math.isfinite(r.dynamic_factor) and math.isfinite(r.rms_dte)


def _k_values(r: Result) -> tuple[float, float]:
    k = r.outputs["stiffness"]
    return float(k.min()), float(k.max())


def test_1_rpm_is_quasi_static() -> None:
    """At 1 rpm the mesh period (2.6 s) is ~7600 natural periods: the DTE follows W/k(t)
    and the peak force is the jump W k_double / k_single right after a single->double switch
    (the spring is loaded to W/k_single and stiffens instantly); both closed forms."""
    r = run_scene(_scene(operating__speed="1 rpm", solver__periods=20, solver__steady_periods=10))
    _finite(r)
    k_lo, k_hi = _k_values(r)
    # the transient after each jump decays within ~1/(xi w_n) = 0.9 ms of a 2.6 s mesh period
    assert r.peak_force_ratio == pytest.approx(k_hi / k_lo, rel=1e-6)
    # ... which the dynamic factor divides out: 1 to the quasi-static run's stated error
    assert r.dynamic_factor == pytest.approx(1.0, abs=r.extra["quasi_static"]["estimated_error"])
    quasi_static = r.static_load / r.outputs["stiffness"][r.steady]
    dte = r.outputs["dte"][r.steady]
    # samples right at a switch sit inside the fast transient: compare the median deviation
    assert np.median(np.abs(dte - quasi_static) / quasi_static) < 1e-6


def test_100000_rpm_is_far_above_resonance() -> None:
    """At 100,000 rpm f_m = 38 kHz, 13 x the natural frequency: the mass cannot follow k(t),
    x stays at W/k_mean (ripple ~ (f_n/f_m)^2 = 0.6 %) and the force follows k(t) x, so the
    dynamic factor is k_max / k_mean."""
    r = run_scene(_scene(operating__speed="100000 rpm"))
    _finite(r)
    k = r.outputs["stiffness"][r.steady]
    k_mean = float(np.mean(k))
    # mean over whole mesh periods of the sampled rectangle: exact to the 1/64 sampling
    assert r.mean_dte == pytest.approx(r.static_load / k_mean, rel=2e-2)
    assert r.peak_force_ratio == pytest.approx(k.max() / k_mean, rel=3e-2)


@pytest.mark.parametrize("inertia", ["1 kg*m^2", "1e-6 kg*m^2"])
def test_inertias_1_kg_and_1e_6_kg_agree_with_an_ode_solver(inertia: str) -> None:
    """Both inertias: the exact propagator and LSODA (tight tolerance) give the same DTE
    (LSODA's error at rtol 1e-9 is far below 1e-4 of the DTE range)."""
    sc = _scene(inertia__pinion=inertia, inertia__gear=inertia, solver__periods=10,
                solver__steady_periods=5)
    exact = run_scene(sc, method="exact")
    ode = run_scene(sc, method="LSODA", rtol=1e-9)
    _finite(exact)
    _finite(ode)
    scale = float(np.ptp(exact.outputs["dte"])) + 1e-12
    assert np.max(np.abs(exact.outputs["dte"] - ode.outputs["dte"])) < 1e-4 * scale + 1e-9 * abs(
        exact.mean_dte)


@pytest.mark.parametrize("ratio", [0.0, 10.0])
def test_damping_0_and_10(ratio: float) -> None:
    """No damping: the response never settles but stays bounded (k(t) of this pair is not
    parametrically unstable at this speed) and exact == DOP853. Damping ratio 10 (heavily
    overdamped): the steady DTE stays between W/k_max and W/k_min."""
    sc = _scene(damping__ratio=ratio, solver__periods=10, solver__steady_periods=5)
    r = run_scene(sc, method="exact")
    _finite(r)
    k_lo, k_hi = _k_values(r)
    if ratio == 0.0:
        ode = run_scene(sc, method="DOP853", rtol=1e-10)
        scale = float(np.ptp(r.outputs["dte"]))
        # DOP853 at rtol 1e-10 over 23 natural periods: error well below 1e-5 of the swing
        assert np.max(np.abs(r.outputs["dte"] - ode.outputs["dte"])) < 1e-5 * scale
    else:
        dte = r.outputs["dte"][r.steady]
        assert dte.min() >= r.static_load / k_hi * (1 - 1e-9)
        assert dte.max() <= r.static_load / k_lo * (1 + 1e-9)


def test_contact_ratio_just_above_1() -> None:
    """ha* = 0.61 gives eps_a = 1.008: two pairs share the load for 0.8 % of a mesh period,
    so the mean stiffness is k_s + (eps - 1)(k_d - k_s) with eps from the geometry."""
    sc = _scene(gear__addendum_coef=0.61, solver__periods=10, solver__steady_periods=5,
                solver__samples_per_period=1024)
    eps = build_pair(sc).contact_ratio
    assert eps > 1.0 and eps < 1.02
    r = run_scene(sc)
    _finite(r)
    k_lo, k_hi = _k_values(r)
    mean = float(np.mean(r.outputs["stiffness"][r.steady]))
    # 1024 samples per period resolve the double zone to 1/1024 of a period: (k_d - k_s) / k_m
    # x 1/1024 < 1e-3 relative
    assert mean == pytest.approx(k_lo + (eps - 1) * (k_hi - k_lo), rel=2e-3)


def test_contact_ratio_above_2() -> None:
    """z 40/80, 15 deg, ha* 1.3: eps_a = 2.65, two or three pairs in contact. The ISO 6336
    wave gives n pairs c' b (0.75 n + 0.25), so the levels are 1.75 and 2.5 c' b, three pairs for
    a fraction eps - 2 of the period, and the mean is c_gamma b = c' b (0.75 eps + 0.25)."""
    sc = _scene(gear__teeth_pinion=40, gear__teeth_gear=80, gear__module="3 mm",
                gear__pressure_angle="15 deg", gear__addendum_coef=1.3,
                gear__face_width="30 mm", operating__torque="200 N*m", solver__periods=10,
                solver__steady_periods=5, solver__samples_per_period=1024)
    eps = build_pair(sc).contact_ratio
    assert 2.6 < eps < 2.7
    r = run_scene(sc)
    _finite(r)
    k_lo, k_hi = _k_values(r)
    assert k_hi / k_lo == pytest.approx(2.5 / 1.75, rel=1e-12)
    mean = float(np.mean(r.outputs["stiffness"][r.steady]))
    assert mean == pytest.approx(k_lo + (eps - 2) * (k_hi - k_lo), rel=2e-3)  # as above
    assert mean == pytest.approx(k_lo / 1.75 * (0.75 * eps + 0.25), rel=2e-3)


def test_contact_ratio_below_1_is_refused_with_the_key() -> None:
    with pytest.raises(SceneError, match=r"extreme.toml: contact_ratio = 0\.99.*addendum_coef"):
        build_plan(_scene(gear__addendum_coef=0.6))


def test_eccentricity_comparable_to_backlash() -> None:
    """The eccentric pair of Liu et al. (2017) with 0.2 mm eccentricities and a 0.2 mm half gap: the
    teeth separate and could separate. The run ends in a result with finite outputs (or a clear
    error); where the load keeps the teeth in contact (no contact events), it must equal the run
    without backlash, the DTE shifted by exactly the half gap (f(u) = u - b in contact)."""
    base = load(SCENES_DIR / "eccentric_helical.toml")
    sc = _scene(base, backlash__half_gap="0.2 mm", solver__periods=20, solver__steady_periods=10)
    try:
        r = run_scene(sc)
    except (InputError, SceneError) as exc:
        assert "extreme.toml" in str(exc)
        return
    _finite(r)
    if r.extra.get("n_contact_events", 0) == 0:
        ref = run_scene(_scene(base, solver__periods=20, solver__steady_periods=10))
        f, f_ref = r.outputs["mesh_force"], ref.outputs["mesh_force"]
        # both DOP853 at rtol 1e-7 with different atol scales: agree to 1e-3 of the swing
        assert np.max(np.abs(f - f_ref)) < 1e-3 * np.ptp(f_ref)
        shift = r.outputs["dte"] - ref.outputs["dte"]
        assert np.max(np.abs(shift - 0.2e-3)) < 1e-3 * np.ptp(ref.outputs["dte"])


def test_1_rpm_with_an_ode_solver_is_refused_not_a_hang() -> None:
    """With backlash and an ODE solver 1 rpm and 200 periods would span 1.5 million natural
    periods: refused at once, naming the speed, the periods and the limit."""
    sc = _scene(operating__speed="1 rpm", backlash__half_gap="10 um", solver__method="LSODA")
    with pytest.raises(InputError, match=r"operating\.speed.*solver\.periods") as info:
        run_scene(sc)
    assert f"<= {MAX_NATURAL_PERIODS}" in str(info.value) and "extreme.toml" in str(info.value)


def test_absurd_number_of_samples_is_refused() -> None:
    """10 million periods x 64 samples would need 5 GB: refused before allocating."""
    sc = _scene(solver__periods=10_000_000, solver__steady_periods=10)
    with pytest.raises(InputError, match=r"solver\.periods x solver\.samples_per_period") as info:
        run_scene(sc)
    assert str(MAX_SAMPLES) in str(info.value)


def test_100000_rpm_with_backlash_runs() -> None:
    """Backlash (ODE solver) at 100,000 rpm: 200 mesh periods are only 15 natural periods."""
    r = run_scene(_scene(operating__speed="100000 rpm", backlash__half_gap="10 um",
                         solver__periods=40, solver__steady_periods=20))
    _finite(r)
    assert r.stats.method != "exact"
