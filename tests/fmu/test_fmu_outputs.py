"""The FMU's per-step output writer against the models' own vectorised outputs."""

from __future__ import annotations

import numpy as np
import pytest
from scene_cases import edited_scene

from gear_dyn.fmu.inputs import driven_speed
from gear_dyn.fmu.outputs import output_writer
from gear_dyn.scene import build_pair, build_plan

pytestmark = pytest.mark.fmu

CASES = {
    "plain": lambda: edited_scene("helicopter_tail"),
    "transmission error": lambda: edited_scene("helicopter_tail",
                                               transmission_error={"cos": [20e-6], "sin": [5e-6]}),
    "backlash": lambda: edited_scene("helicopter_tail_backlash"),
    "backlash + transmission error": lambda: edited_scene("helicopter_tail_backlash",
                                                          transmission_error={"cos": [20e-6]}),
    "torsional": lambda: edited_scene("eccentric_helical"),
    "relief": lambda: edited_scene("helicopter_tail_relief"),
}


@pytest.mark.parametrize("case", list(CASES))
def test_writer_matches_model_outputs(case: str) -> None:
    """At 50 instants over two mesh periods and states around the static deflection (inside
    and outside the backlash gap), every output the writer gives equals the model's
    vectorised output (and driven_speed its formula) to rounding: 1e-12 of the output's
    largest magnitude (the scalar stiffness path differs from np.interp in the last digits,
    and the torsional DTE r_b1 q1 - r_b2 q2 cancels digits; a wrong term is off by O(1)).
    The torsional model's eccentric terms take 1e-11: sines of phases of many radians, which
    numpy rounds differently for one sample and for an array."""
    scene = CASES[case]()
    model = build_plan(scene).model
    pair = build_pair(scene)
    speed = float(scene.get("operating")["speed"])
    labels = [f"state.{s}" for s in model.state_labels]
    y0 = np.asarray(model.initial_state(), dtype=float)
    names = [*labels, *model.outputs(np.zeros(1), y0[:, None])]
    if len(y0) == 2:
        names.append("driven_speed")
    write = output_writer(model, pair, speed, names)
    rng = np.random.default_rng(7)
    t = np.sort(rng.uniform(0, 2 / model.mesh_frequency, 50))
    scale = np.asarray(model.state_scale, dtype=float)
    ys = y0[:, None] + scale[:, None] * rng.uniform(-3, 3, (len(y0), 50))
    ref = {k: np.broadcast_to(np.asarray(v, dtype=float), t.shape)
           for k, v in model.outputs(t, ys).items()}
    ref.update({lab: ys[i] for i, lab in enumerate(labels)})
    if "driven_speed" in names:
        ref["driven_speed"] = driven_speed(pair, speed, ys[1])
    got: dict[str, list[float]] = {n: [] for n in names}
    for k in range(t.size):
        out: dict[str, float] = {}
        write(float(t[k]), ys[:, k].copy(), out)
        assert set(out) >= set(names)
        for n in names:
            got[n].append(out[n])
    for n in names:
        tol = (1e-11 if case == "torsional" else 1e-12) * max(float(np.max(np.abs(ref[n]))), 1e-300)
        assert np.max(np.abs(np.array(got[n]) - ref[n])) <= tol, n


def test_single_dof_writer_is_the_float_path() -> None:
    """The single-DOF model gets the float path (the one the speed target relies on), other
    models the generic one."""
    for name, fast in (("helicopter_tail", True), ("eccentric_helical", False)):
        scene = edited_scene(name)
        model = build_plan(scene).model
        write = output_writer(model, build_pair(scene), 100.0, ["dte"])
        assert ("_sdof_writer" in write.__qualname__) is fast
