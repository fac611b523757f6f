"""ISO 6336-1 method B K_v: a worked example in the standard's own units, the speed-range
boundaries, the ISO 1328-1 tables, and n_E1 against the single-DOF model's natural frequency."""

from __future__ import annotations

import math

import numpy as np
import pytest

import gear_dyn as gd
from gear_dyn.errors import InputError
from gear_dyn.stiffness.iso6336 import iso6336_stiffness
from gear_dyn.stiffness.iso_kv import (
    FORMULAS,
    cv_coefficients,
    iso1328_deviations,
    kv_method_b,
    lower_resonance_limit,
    reduced_mass_solid_wheels,
    running_in_allowance,
    running_in_tip_relief,
)

RPM = 2 * math.pi / 60


@pytest.fixture(scope="module")
def tail() -> gd.Scene:
    return gd.load_scene("helicopter_tail")  # z 23/64, m 6 mm, 22.5 deg, b 50 mm, 1474.4 N m


def _by_hand(n1_rpm: float) -> tuple[float, float, str]:
    """(K_v, N, range) of the helicopter tail pair, computed in ISO units (mm, um, N/mm, kg/mm)
    from the printed formulas, with the same c' (ISO 6336-1 method B, tested on its own)."""
    from gear_dyn.scene import build_pair

    pair = build_pair(gd.load_scene("helicopter_tail"))
    z1, z2, mn, b = 23, 64, 6.0, 50.0
    alpha_t = math.radians(22.5)  # spur: a_t = a_n
    d1, d2 = mn * z1, mn * z2                       # 138, 384 mm
    db1, db2 = d1 * math.cos(alpha_t), d2 * math.cos(alpha_t)
    ft = 2000 * 1474.4 / d1                         # N
    w = ft / b                                      # K_A F_t / b, N/mm (K_A = 1), >= 100
    c1 = iso6336_stiffness(pair).c_single / 1e9     # c' in N/(mm um), no load correction
    cg = c1 * (0.75 * pair.contact_ratio + 0.25)    # c_gamma_alpha
    rho = 7850e-9                                   # kg/mm^3
    j1, j2 = math.pi * rho * d1**4 / 32, math.pi * rho * d2**4 / 32  # per mm face, solid blanks
    m1, m2 = j1 / (db1 / 2) ** 2, j2 / (db2 / 2) ** 2
    m_red = m1 * m2 / (m1 + m2)                     # kg/mm
    n_e1 = 30000 / (math.pi * z1) * math.sqrt(cg / m_red)  # eq. 6, min^-1
    n = n1_rpm / n_e1
    step = 1.0  # grade 5; the larger wheel has the larger tolerances
    f_pt = (0.3 * (mn + 0.4 * math.sqrt(d2)) + 4) * step
    f_fa = (2.5 * math.sqrt(mn) + 0.17 * math.sqrt(d2) + 0.5) * step
    f_pb = f_pt * math.cos(alpha_t)
    bp, bf, bk = c1 * f_pb / w, c1 * f_fa / w, 1.0  # no relief, no running-in
    eps = pair.contact_ratio                        # 1.585: 1 < eps_gamma <= 2, spur
    cv7 = 0.125 * math.sin(math.pi * (eps - 2)) + 0.875
    if n <= 0.85:
        return n * (0.32 * bp + 0.34 * bf + 0.23 * bk) + 1, n, "subcritical"
    main = 0.32 * bp + 0.34 * bf + 0.90 * bk + 1
    sup = 0.47 * bp + 0.47 * bf + cv7
    if n <= 1.15:
        return main, n, "main resonance"
    if n < 1.5:
        return sup + (main - sup) * (1.5 - n) / 0.35, n, "intermediate"
    return sup, n, "supercritical"


@pytest.mark.parametrize("rpm", [3319.0, 7000.0, 9500.0, 15000.0])  # N 0.44, 0.92, 1.25, 1.97
def test_worked_example_in_iso_units(tail: gd.Scene, rpm: float) -> None:
    from gear_dyn.scene.iso import scene_iso_kv

    kv, src = scene_iso_kv(tail, [rpm * RPM])
    expected, n, rng = _by_hand(rpm)
    assert kv.ratio[0] == pytest.approx(n, rel=1e-12)
    assert kv.speed_range[0] == rng
    assert kv.k_v[0] == pytest.approx(expected, rel=1e-12)
    assert "grade 5 (assumed" in src["deviations"]


def test_run_summary_states_kv_beside_the_simulated_factor(tail: gd.Scene) -> None:
    result = gd.run_scene(tail, periods=20)
    iso = gd.summarize(result)["iso_6336_kv"]
    expected, n, rng = _by_hand(3319.0)
    assert iso["k_v"] == pytest.approx(expected, rel=1e-12)
    assert iso["resonance_ratio_n"] == pytest.approx(n, rel=1e-12)
    assert iso["speed_range"] == rng == "subcritical"
    assert iso["formula"] == FORMULAS["subcritical"]
    # the figures docs/dynamic_factor.md quotes
    assert (round(iso["k_v"], 4), round(iso["resonance_ratio_n"], 3),
            round(iso["resonance_speed_rpm"])) == (1.1844, 0.437, 7599)
    assert "ISO 6336-1 K_v" in repr(result)


def test_resonance_speed_is_the_single_dof_natural_frequency(tail: gd.Scene) -> None:
    """Second method: n_E1 (eq. 6) is the speed at which f_m = z1 n1/60 equals f_n of the
    single-DOF model built with the same mass and mean stiffness c_gamma_alpha b."""
    from gear_dyn.scene import build_model
    from gear_dyn.scene.iso import scene_iso_kv

    model = build_model(tail)  # stiffness "iso6336": rectangular wave of mean c_gamma_alpha b
    kv, _ = scene_iso_kv(tail)
    assert kv.c_gamma_alpha * 0.05 == pytest.approx(model.mean_stiffness, rel=1e-12)
    assert kv.resonance_speed_rpm * 23 / 60 == pytest.approx(model.natural_frequency, rel=1e-12)


@pytest.fixture
def cv() -> object:
    return cv_coefficients(1.6)


def test_boundaries_of_the_speed_ranges(cv: object) -> None:
    bp, bf, bk, ns = 0.25, 0.33, 0.6, 0.85
    eps = 1e-9
    n = np.array([ns, ns + eps, 1.15 - eps, 1.15, 1.15 + eps, 1.5 - eps, 1.5, 1.5 + eps])
    k, names = kv_method_b(n, cv, bp, bf, bk, ns)
    assert list(names) == ["subcritical", "main resonance", "main resonance", "main resonance",
                           "intermediate", "intermediate", "supercritical", "supercritical"]
    # continuous at N = 1.15 and 1.5 (eq. 22 interpolates linearly between the two plateaus)
    assert k[3] == pytest.approx(k[4], abs=1e-8) and k[5] == pytest.approx(k[6], abs=1e-8)
    # the jump at N_S is the standard's: N_S K + 1 below, the resonance plateau above
    c = cv_coefficients(1.6)
    assert k[0] == pytest.approx(ns * (0.32 * bp + 0.34 * bf + 0.23 * bk) + 1, rel=1e-14)
    assert k[1] == pytest.approx(0.32 * bp + 0.34 * bf + 0.90 * bk + 1, rel=1e-14)
    assert k[7] == pytest.approx(0.47 * bp + 0.47 * bf + c.cv7, rel=1e-12)
    # linear in N inside the intermediate range: the midpoint is the mean of the ends
    mid, _ = kv_method_b([1.325], cv, bp, bf, bk, ns)
    assert mid[0] == pytest.approx(0.5 * (k[3] + k[6]), rel=1e-12)


def test_cv_table() -> None:
    low, high = cv_coefficients(1.8), cv_coefficients(3.0)
    assert (low.cv1, low.cv2, low.cv3, low.cv4, low.cv5, low.cv6) == (0.32, 0.34, 0.23, 0.90,
                                                                      0.47, 0.47)
    assert high.cv2 == pytest.approx(0.57 / 2.7) and high.cv3 == pytest.approx(0.096 / 1.44)
    assert high.cv4 == pytest.approx(0.42 / 1.56) and high.cv6 == pytest.approx(0.12 / 1.26)
    # C_v7 is continuous where its formula changes (0.75 at 1.5, 1 at 2.5)
    assert cv_coefficients(1.5 + 1e-12).cv7 == pytest.approx(0.75, abs=1e-9)
    assert cv_coefficients(2.5).cv7 == pytest.approx(1.0, abs=1e-12)
    assert cv_coefficients(1.4).cv7 == 0.75 and cv_coefficients(2.6).cv7 == 1.0
    with pytest.raises(InputError, match="eps_gamma"):
        cv_coefficients(1.0)


def test_lower_limit_of_the_resonance_range() -> None:
    assert lower_resonance_limit(2e5) == 0.85
    assert lower_resonance_limit(1e5) == 0.85
    assert lower_resonance_limit(0.25e5) == pytest.approx(0.5 + 0.35 * 0.5)


def test_iso1328_grade5_table_values() -> None:
    """ISO 1328-1:1995 tabulates the formulas at the geometric means of its ranges, rounded to
    0.5 um between 5 and 10 um and to 0.1 um below 5 um: d 50..125 mm, m_n 0.5..2 / 2..3.5 /
    3.5..6 mm give f_pt 5.5 / 6.0 / 6.5 um and f_falpha 4.5 / 6.0 / 7.5 um."""
    d = math.sqrt(50 * 125) * 1e-3

    def rounded(x_um: float) -> float:
        return round(x_um * 2) / 2 if x_um >= 5 else round(x_um, 1)

    for (lo, hi), f_pt, f_fa in (((0.5, 2), 5.5, 4.5), ((2, 3.5), 6.0, 6.0),
                                 ((3.5, 6), 6.5, 7.5)):
        pt, fa = iso1328_deviations(5, math.sqrt(lo * hi) * 1e-3, d)
        assert (rounded(pt * 1e6), rounded(fa * 1e6)) == (f_pt, f_fa)
    pt6, fa6 = iso1328_deviations(6, 6e-3, 0.384)
    pt5, fa5 = iso1328_deviations(5, 6e-3, 0.384)
    assert pt6 / pt5 == pytest.approx(math.sqrt(2)) and fa6 / fa5 == pytest.approx(math.sqrt(2))


def test_running_in_allowances() -> None:
    assert running_in_allowance(20e-6, "none")[()] == 0.0
    assert running_in_allowance(20e-6, "case_hardened")[()] == pytest.approx(1.5e-6)
    assert running_in_allowance(60e-6, "case_hardened")[()] == pytest.approx(3e-6)  # capped
    y = running_in_allowance(40e-6, "through_hardened", 800e6, [4.0, 8.0, 12.0])
    # 160/800 x 40 = 8 um; caps 12800/800 = 16 um (5..10 m/s) and 6400/800 = 8 um (> 10 m/s)
    assert np.allclose(y, [8e-6, 8e-6, 8e-6])
    y = running_in_allowance(60e-6, "through_hardened", 800e6, [4.0, 8.0, 12.0])
    assert np.allclose(y, [12e-6, 12e-6, 8e-6])
    with pytest.raises(InputError, match="sigma_hlim"):
        running_in_allowance(20e-6, "through_hardened")
    # C_ay for sigma_Hlim = 1500 N/mm^2: (15.464 - 18.45)^2 / 18 + 1.5 = 1.9953 um
    assert running_in_tip_relief(1500e6) == pytest.approx(((1500 / 97 - 18.45) ** 2 / 18 + 1.5)
                                                          * 1e-6, rel=1e-12)


def test_iso_solid_wheel_mass_by_hand(tail: gd.Scene) -> None:
    """ISO eq. 30 in ISO units (kg/mm, mm): d_m1 = (d_a1 + d_f1)/2 = (150 + 123)/2 = 136.5 mm."""
    from gear_dyn.scene import build_pair

    d_m1, d_b1, u, rho = 136.5, 138 * math.cos(math.radians(22.5)), 64 / 23, 7850e-9
    m_red = math.pi / 8 * (d_m1 / d_b1) ** 2 * d_m1**2 / (1 / rho + 1 / (rho * u**2))  # kg/mm
    assert reduced_mass_solid_wheels(build_pair(tail)) == pytest.approx(m_red * 1e3, rel=1e-12)
