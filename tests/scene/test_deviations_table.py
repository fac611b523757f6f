"""The [deviations] table: the scene's transmission error, K_v like for like, honest limits."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import gear_dyn as gd
from gear_dyn.errors import InputError, SceneError
from gear_dyn.excitation import SumSignal
from gear_dyn.scene import build_model, build_pair
from gear_dyn.scene.iso import iso_kv_lines, iso_kv_summary
from gear_dyn.scene.reference import scene_reference
from gear_dyn.scene.sweep import sweep_scene
from tests.scene_cases import edited_scene


def test_listed_in_the_scene_keys() -> None:
    text = scene_reference("deviations")
    for key in ("grade", "pattern", "seed", "f_pt", "F_p", "f_falpha", "F_beta"):
        assert f"`{key}`" in text


def test_deviations_excite_the_model_and_k_v_sees_the_same_grade() -> None:
    scene = edited_scene("helicopter_tail", deviations={"grade": 8, "pattern": "sine"})
    model = build_model(scene)
    te = model.transmission_error  # type: ignore[attr-defined]
    assert isinstance(te, SumSignal) and te.period == math.lcm(23, 64)
    assert not model.mesh_periodic
    kv = iso_kv_summary(scene)
    assert "[deviations]" in kv["sources"]["deviations"] and "grade 8" in kv["sources"][
        "deviations"]
    assert iso_kv_lines(kv)[-1].strip().startswith("like for like")
    # K_v grows with the grade's deviations (B_p, B_f)
    kv4 = iso_kv_summary(edited_scene("helicopter_tail", deviations={"grade": 4}))
    assert kv4["b_p"] < kv["b_p"] and kv4["b_f"] < kv["b_f"]
    plain = iso_kv_summary(gd.load_scene("helicopter_tail"))
    assert plain["like_for_like"].startswith("not like for like")
    assert "this simulation has none" in plain["like_for_like"]


def test_explicit_values_replace_the_grade() -> None:
    scene = edited_scene("helicopter_tail", deviations={"f_pt": 4e-6, "F_p": 10e-6,
                                                        "f_falpha": 0.0, "F_beta": 5e-6,
                                                        "pattern": "sine"})
    pair = build_pair(scene)
    te = build_model(scene).transmission_error  # type: ignore[attr-defined]
    p = np.arange(23.0)
    pinion = te.parts[0].value(p)
    np.testing.assert_allclose(np.ptp(pinion), 10e-6 * math.cos(pair.alpha_t),
                               rtol=1 - math.cos(math.pi / 46))
    with pytest.raises(SceneError, match="deviations.grade: missing"):
        build_model(edited_scene("helicopter_tail", deviations={"f_pt": 4e-6}))


def test_steady_sweep_and_short_windows_state_the_hunting_period() -> None:
    scene = edited_scene("helicopter_tail", deviations={"grade": 6})
    with pytest.raises(InputError, match="repeats every 1472 mesh periods"):
        sweep_scene(scene, ["3000 rpm"])
    res = gd.run_scene(scene, periods=4, rtol=1e-6, samples_per_period=16)
    assert any("shorter than the period of the transmission error (1472" in w
               for w in res.extra["warnings"])
    assert res.extra["deviations"]["hunting_period_mesh_cycles"] == 1472
    # the Floquet multipliers are k(t)'s: stated for the run as without deviations
    from gear_dyn.analysis.stability import floquet_multipliers

    plain = build_model(edited_scene("helicopter_tail"))
    rho = float(np.max(np.abs(floquet_multipliers(plain))))  # type: ignore[arg-type]
    assert res.extra["floquet"]["max_multiplier_modulus"] == pytest.approx(rho, rel=1e-8)


def test_fmu_builds_refuse_deviations(tmp_path: Path) -> None:
    """Both FMU kinds carry mesh harmonics only: refused at build time, before any compiling."""
    from gear_dyn.fmu.export_fmu import build_native_fmu
    from gear_dyn.fmu.variables import fmu_spec
    from tests.scene_cases import SCENES_DIR

    scene = edited_scene("helicopter_tail", deviations={"grade": 6})
    with pytest.raises(InputError, match=r"\[deviations\]"):
        fmu_spec(scene)
    path = tmp_path / "dev.toml"
    path.write_text((SCENES_DIR / "helicopter_tail.toml").read_text()
                    + '\n[deviations]\ngrade = 6\n')
    with pytest.raises(InputError, match=r"\[deviations\]"):
        build_native_fmu(path, tmp_path / "dev.fmu")
