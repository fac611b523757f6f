"""Spectra of the eccentric pair's excitations: the peaks Liu et al. (2017) report, found in
computed spectra."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from gear_dyn.analysis.spectrum import amplitude_spectrum
from gear_dyn.analysis.spectrum_labels import Basis, label_frequency
from gear_dyn.cli.excitation import analyse
from gear_dyn.scene import load_scene, parse_scene

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"
F1 = 25.0
F2 = 25.0 * 18 / 70  # 6.4286 Hz
FM = 450.0


@pytest.fixture(scope="module")
def eccentric_case() -> dict:
    return analyse(load_scene(SCENES / "eccentric_helical.toml"))


@pytest.fixture(scope="module")
def ideal_case() -> dict:
    return analyse(load_scene(SCENES / "eccentric_helical_ideal.toml"))


def test_driven_speed_peaks_at_both_shaft_frequencies(eccentric_case: dict) -> None:
    """Seed Fig. 7: the driven-speed spectrum peaks at 25 Hz (input shaft) and ~6.4 Hz (output
    shaft). Every line falls on a bin (whole hunting period), and the peak frequency is refined by
    parabolic interpolation: 1e-6 Hz."""
    peaks = eccentric_case["peaks"]["w2"]
    assert {p["label"] for p in peaks[:2]} == {"f1", "f2"}
    found = sorted(p["frequency_hz"] for p in peaks[:2])
    assert found == pytest.approx([F2, F1], abs=1e-6)
    # the two shaft lines dominate every combination line by > 50x
    assert peaks[2]["amplitude"] < peaks[1]["amplitude"] / 50


@pytest.mark.parametrize("name", ["contact_length", "friction_force", "friction_torque_pinion",
                                  "friction_torque_gear"])
def test_mesh_harmonics_shaft_lines_and_sidebands_are_present(eccentric_case: dict,
                                                               name: str) -> None:
    """Liu et al. (2017), Figs. 8, 12, 13: 450 Hz and harmonics, both shaft frequencies, and
    sidebands 450 +- 25 and 450 +- 6.43 Hz, among the 40 largest peaks of the computed spectrum.
    Lines sit on bins; the parabolic refinement is pulled by neighbouring sidebands by < 1e-4 Hz, so
    1e-2 of the resolution (0.714 Hz) is asserted."""
    from gear_dyn.analysis.spectrum_labels import labelled_peaks

    f, a = eccentric_case["spectra"][name]
    peaks = labelled_peaks(f, a, eccentric_case["basis"], n=40)
    by_label = {p["label"]: p["frequency_hz"] for p in peaks}
    expect = {"fm": FM, "2fm": 2 * FM, "f1": F1, "f2": F2, "fm-f1": FM - F1, "fm+f1": FM + F1,
              "fm-f2": FM - F2, "fm+f2": FM + F2}
    for label, freq in expect.items():
        assert label in by_label, f"{name}: no peak {label} ({freq:.2f} Hz)"
        assert by_label[label] == pytest.approx(freq, abs=7e-3)


@pytest.mark.parametrize("name", ["contact_length", "friction_force", "friction_torque_pinion",
                                  "friction_torque_gear"])
def test_error_free_spectra_hold_only_mesh_harmonics(ideal_case: dict, name: str) -> None:
    """Without eccentricity the signals are periodic at f_m and sampled over whole periods: with
    a rectangular window every bin off a mesh harmonic is rounding noise (< 1e-10 of the largest
    line). (The Hann window of gear_dyn.analysis.spectrum is the symmetric one, whose leakage
    reaches a
    few bins at ~1e-5; the labelled peaks above 1e-4 are checked on it.)"""
    t, x = ideal_case["t"], ideal_case["series"][name]
    f, a = amplitude_spectrum(t, x, window="rect")
    harmonic = np.abs(f / FM - np.round(f / FM)) * FM <= 1e-6
    assert np.max(a[~harmonic]) < 1e-10 * np.max(a)
    assert all(p["kind"] == "mesh" for p in ideal_case["peaks"][name])
    assert ideal_case["peaks"][name][0]["label"] in ("fm", "2fm")


def test_error_free_driven_speed_is_constant(ideal_case: dict) -> None:
    w2 = ideal_case["series"]["w2"]
    np.testing.assert_allclose(w2, 50 * math.pi * 18 / 70, rtol=1e-13)
    assert ideal_case["peaks"]["w2"] == []


def test_pinion_only_eccentricity_modulates_only_at_the_pinion_frequency() -> None:
    """Seed Fig. 10a: an eccentric pinion alone gives f1 and fm +- f1, no gear-shaft lines."""
    raw = load_scene(SCENES / "eccentric_helical.toml").raw
    raw = {**raw, "eccentricity": {"pinion": "0.2 mm", "gear": "0 mm"}}
    res = analyse(parse_scene(raw, "pinion_only"))
    f, a = amplitude_spectrum(res["t"], res["series"]["contact_length"], window="rect")
    top = np.max(a)
    at = lambda freq: a[np.argmin(np.abs(f - freq))]  # noqa: E731
    for freq in (F1, FM - F1, FM + F1):
        assert at(freq) > 1e-2 * top
    for freq in (F2, FM - F2, FM + F2):  # rounding only (rectangular window, whole periods)
        assert at(freq) < 1e-10 * top


def test_labels_pick_the_simplest_combination() -> None:
    b = Basis.of_pair(18, 70, 50 * math.pi)
    assert label_frequency(450.0, b, 0.1).name == "fm"  # not 18 f1
    assert label_frequency(443.5714, b, 0.1).name == "fm-f2"
    assert label_frequency(925.0, b, 0.1).name == "2fm+f1"
    assert label_frequency(18.5714, b, 0.1).name == "f1-f2"
    assert label_frequency(0.7143, b, 0.1).name == "4f2-f1"
    assert label_frequency(7.5, b, 0.1) is None
