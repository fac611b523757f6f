"""Property-based tests: scene loading and model construction driven by random and mutated
inputs end in a result or a documented error (InputError, incl. SceneError; SolverError),
never another exception. pytest turns warnings into errors, so a numpy overflow or a
divide-by-zero warning on the way fails these tests too."""

from __future__ import annotations

import math
import random
from pathlib import Path
from typing import Any

import hypothesis.strategies as st
import numpy as np
from hypothesis import HealthCheck, example, given, settings
from scene_cases import dump_toml, example_scenes, load

from gear_dyn.errors import InputError, SceneError, SolverError
from gear_dyn.geometry import GearPair
from gear_dyn.models.sdof import sdof_from_pair
from gear_dyn.scene import SECTIONS, build_plan, load_scene, parse_scene
from gear_dyn.scene.fields import Field
from gear_dyn.solvers import SolverSettings
from gear_dyn.stiffness.periodic import rectangular_stiffness

FUZZ = settings(max_examples=60, deadline=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])

UNITS = ["", "mm", "m", "um", "deg", "rad", "rpm", "Hz", "rad/s", "N*m", "kN*m", "kg", "kg*m^2",
         "g*cm^2", "GPa", "MPa", "kg/m^3", "N/m", "N/um", "s", "furlong", "1/0", "%", "m/s^2"]

numbers = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=-1e3, max_value=1e3),
    st.integers(min_value=-10**20, max_value=10**20),
    st.sampled_from([0, 1, -1, 0.5, 1e-300, 1e300, 5, 23, 64]),
)
quantities = st.builds(lambda x, u: f"{x} {u}".strip(), numbers, st.sampled_from(UNITS))
scalars = st.one_of(numbers, quantities, st.booleans(), st.text(max_size=12),
                    st.sampled_from(["auto", "exact", "DOP853", "iso6336", "sdof", "torsional"]))
values = st.one_of(scalars, st.lists(scalars, max_size=4), st.dictionaries(
    st.text(max_size=5), scalars, max_size=2))

#: every documented outcome of loading + building
DOCUMENTED = (InputError, SolverError)


def _known_keys() -> dict[str, list[str]]:
    return {name: [f.name for f in sec.fields] for name, sec in SECTIONS.items()}


def _load_and_build(data: Any, source: str = "fuzz.toml") -> None:
    """parse + build; SceneErrors must name the source."""
    try:
        scene = parse_scene(data, source)
    except SceneError as exc:
        assert source in str(exc), str(exc)
        return
    try:
        plan = build_plan(scene)
    except DOCUMENTED:
        return
    assert plan.t_end > 0 and math.isfinite(plan.t_end)
    assert math.isfinite(plan.model.mesh_frequency) and plan.model.mesh_frequency > 0


@st.composite
def random_scenes(draw: st.DrawFn) -> dict[str, Any]:
    """Scenes made of known tables and keys (mostly) with random values, some junk keys."""
    known = _known_keys()
    tables = draw(st.lists(st.sampled_from(sorted(known)), min_size=0, max_size=6, unique=True))
    data: dict[str, Any] = {}
    for t in tables:
        keys = draw(st.lists(st.sampled_from(known[t]), max_size=len(known[t]), unique=True))
        data[t] = {k: draw(values) for k in keys}
        if draw(st.integers(0, 9)) == 0:
            data[t][draw(st.text(min_size=1, max_size=8))] = draw(values)
    if draw(st.integers(0, 9)) == 0:
        data[draw(st.text(min_size=1, max_size=8))] = draw(values)
    return data


@FUZZ
@given(random_scenes())
def test_random_scenes_load_and_build_or_raise_documented_errors(data: dict[str, Any]) -> None:
    _load_and_build(data)


@st.composite
def mutated_example(draw: st.DrawFn) -> tuple[str, dict[str, Any]]:
    """An example scene with 1-3 keys replaced by random values or deleted."""
    path = draw(st.sampled_from(example_scenes()))
    data = load(path)
    for _ in range(draw(st.integers(1, 3))):
        table = draw(st.sampled_from(sorted(data)))
        if not isinstance(data[table], dict) or not data[table]:
            continue
        key = draw(st.sampled_from(sorted(data[table])))
        if draw(st.integers(0, 4)) == 0:
            del data[table][key]
        else:
            data[table][key] = draw(values)
    return path.name, data


@settings(max_examples=50, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated_example())
def test_mutated_example_scenes_load_and_build_or_raise_documented_errors(
    case: tuple[str, dict[str, Any]],
) -> None:
    name, data = case
    _load_and_build(data, name)


@FUZZ
@given(st.binary(max_size=300) | st.text(max_size=300).map(str.encode))
def test_any_file_content_is_a_scene_or_a_scene_error(tmp_path_factory: Any,
                                                      content: bytes) -> None:
    """Random bytes and text as a scene file (including a truncated example scene)."""
    path = Path(tmp_path_factory.mktemp("f")) / "junk.toml"
    path.write_bytes(content)
    try:
        scene = load_scene(path)
    except SceneError as exc:
        assert "junk.toml" in str(exc)
        return
    _load_and_build(scene.raw, "junk.toml")


@FUZZ
@given(st.integers(min_value=1, max_value=2000), st.integers(0, 10**6))
def test_truncated_example_scenes_are_scene_errors_or_valid(tmp_path_factory: Any, cut: int,
                                                             seed: int) -> None:
    """A scene file cut off at any byte (an interrupted copy) is a clean SceneError or, when
    the cut happens to fall between tables, a valid shorter scene."""
    src = random.Random(seed).choice(example_scenes())
    text = src.read_bytes()
    path = Path(tmp_path_factory.mktemp("t")) / src.name
    path.write_bytes(text[: min(cut, len(text))])
    try:
        scene = load_scene(path)
    except SceneError as exc:
        assert src.name in str(exc)
        return
    _load_and_build(scene.raw, src.name)


@FUZZ
@given(scalars | st.lists(scalars, max_size=3) | st.none(),
       st.sampled_from(["m", "rad", "rad/s", "N*m", "kg*m**2", "Pa", "N/m", ""]),
       st.sampled_from(["float", "int", "str", "bool", "floatlist"]))
def test_field_parse_only_raises_scene_errors(raw: Any, unit: str, kind: str) -> None:
    """pint parse errors, dimensionality errors, overflow in int(): all become SceneError."""
    f = Field("x", unit, kind=kind, default=None, low=0.0, high=1e6)
    try:
        v = f.parse(raw, "f.toml: t.x")
    except SceneError as exc:
        assert "t.x" in str(exc)
        return
    if kind in ("float", "int"):
        assert math.isfinite(v) and 0.0 <= v <= 1e6


finite = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False)
anything = st.one_of(finite, numbers, st.none(), st.text(max_size=3), st.booleans())


@FUZZ
@example({"z1": math.inf, "z2": 64, "module": 6e-3, "pressure_angle": 0.39, "face_width": 0.05})
@example({"z1": 23, "z2": math.nan, "module": 6e-3, "pressure_angle": 0.39, "face_width": 0.05})
@given(st.fixed_dictionaries({
    "z1": st.one_of(st.integers(-5, 200), anything), "z2": st.one_of(st.integers(-5, 400),
                                                                      anything),
    "module": st.one_of(st.floats(1e-4, 0.05), anything),
    "pressure_angle": st.one_of(st.floats(0.05, 0.8), anything),
    "face_width": st.one_of(st.floats(1e-3, 0.5), anything),
    "helix_angle": st.one_of(st.floats(0, 0.8), anything),
    "x1": st.one_of(st.floats(-1.2, 1.6), anything), "x2": st.one_of(st.floats(-1.2, 1.6),
                                                                     anything),
    "addendum_coef": st.one_of(st.floats(0.4, 1.6), anything),
    "center_distance": st.one_of(st.none(), st.floats(0.0, 2.0), anything),
}))
def test_gear_pair_construction_is_a_pair_or_an_input_error(kw: dict[str, Any]) -> None:
    """GearPair from random parameters: an InputError, or a pair whose derived quantities are
    finite and meshing (contact ratio >= 1, non-negative backlash)."""
    try:
        pair = GearPair(**kw)
    except InputError:
        return
    assert pair.contact_ratio >= 1.0
    assert pair.backlash >= -1e-12 * pair.module
    for v in (pair.a_w, pair.rb1, pair.ra2, pair.base_pitch, pair.overlap_ratio):
        assert math.isfinite(v)


@FUZZ
@given(speed=st.one_of(st.floats(1e-3, 2e4), anything),
       torque=st.one_of(st.floats(0, 1e5), anything),
       i1=st.one_of(st.floats(1e-8, 1e3), anything), i2=st.one_of(st.floats(1e-8, 1e3), anything),
       xi=st.one_of(st.floats(0, 12), anything),
       backlash=st.one_of(st.none(), st.floats(-1e-3, 2e-3), anything),
       k=st.one_of(st.floats(1e5, 1e10), anything))
def test_sdof_model_construction_is_a_model_or_an_input_error(
    heli_pair: GearPair, speed: Any, torque: Any, i1: Any, i2: Any, xi: Any, backlash: Any,
    k: Any,
) -> None:
    """sdof_from_pair from random operating points, inertias, damping, backlash, stiffness:
    an InputError, or a model whose right-hand side at the initial state is finite."""
    try:
        stiff = rectangular_stiffness(heli_pair.contact_ratio, k, 1.5 * k if isinstance(
            k, float) else k)
        m = sdof_from_pair(heli_pair, speed, torque, stiff, damping_ratio=xi, inertias=(i1, i2),
                           backlash=backlash)
    except InputError:
        return
    y0 = m.initial_state()
    assert all(math.isfinite(v) for v in m.rhs(0.0, y0))


@FUZZ
@given(method=st.one_of(st.sampled_from(["auto", "exact", "RK45", "LSODA", "Euler", ""]),
                        anything),
       rtol=st.one_of(st.floats(1e-14, 1.0), anything),
       atol=st.one_of(st.none(), st.floats(-1, 1), anything),
       spp=st.one_of(st.integers(-5, 5000), anything))
def test_solver_settings_are_valid_or_an_input_error(method: Any, rtol: Any, atol: Any,
                                                     spp: Any) -> None:
    try:
        s = SolverSettings(method=method, rtol=rtol, atol=atol, samples_per_period=spp)
    except InputError:
        return
    assert 1e-13 <= s.rtol <= 1e-2 and 4 <= s.samples_per_period <= 4096


def test_the_toml_writer_handles_every_fuzz_value() -> None:
    """Guard for the helpers: a random scene written as TOML reads back (NaN aside)."""
    import tomllib

    rng = random.Random(1)
    for path in example_scenes():
        data = load(path)
        table = rng.choice(sorted(data))
        data[table] = {**data[table], "extra": [1, "a", 2.5]}
        assert tomllib.loads(dump_toml(data)) == data


def _in_range(f: Field) -> st.SearchStrategy[Any]:
    """Values of one field inside its declared range (log-spaced for wide ranges)."""
    if f.kind == "str":
        return st.sampled_from(f.choices) if f.choices else st.text(max_size=8)
    if f.kind == "bool":
        return st.booleans()
    lo = f.low if f.low is not None else -1e3
    hi = f.high if f.high is not None else 1e3
    if f.kind == "int":
        return st.integers(int(math.ceil(lo)), int(min(hi, lo + 500)))
    if f.kind == "floatlist":
        return st.lists(st.floats(-1e-5, 1e-5), min_size=1, max_size=3)
    if lo > 0 and hi / lo > 100:
        return st.floats(math.log10(lo), math.log10(hi)).map(lambda e: 10.0**e).filter(
            lambda v: lo < v < hi)
    return st.floats(lo, hi).filter(lambda v: (v > lo or not f.low_open)
                                    and (v < hi or not f.high_open))


@st.composite
def in_range_scenes(draw: st.DrawFn) -> dict[str, Any]:
    """An example scene with 1-4 keys of its own or other tables set to random values inside
    their declared ranges: every such scene passes the key checks and reaches the physics
    (pair geometry, stiffness, model), where impossible combinations must be InputErrors."""
    known = _known_keys()
    data = load(draw(st.sampled_from(example_scenes())))
    for _ in range(draw(st.integers(1, 4))):
        table = draw(st.sampled_from(sorted(known)))
        f = draw(st.sampled_from(SECTIONS[table].fields))
        data.setdefault(table, {})[f.name] = draw(_in_range(f))
    return data


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(in_range_scenes())
def test_in_range_values_build_a_model_or_raise_documented_errors(data: dict[str, Any]) -> None:
    _load_and_build(data)


arrays = st.one_of(
    st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=4),
    st.lists(st.floats(-1e-3, 1e-3), min_size=1, max_size=4),
    anything, st.lists(anything, max_size=3),
)


@FUZZ
@given(mean=anything, a=arrays, b=arrays, phase=arrays, values=arrays)
def test_excitation_signals_are_valid_or_an_input_error(mean: Any, a: Any, b: Any, phase: Any,
                                                        values: Any) -> None:
    """HarmonicSignal / SampledSignal from junk: InputError, or finite values at any phase."""
    from gear_dyn.excitation import HarmonicSignal, SampledSignal

    for make in (lambda: HarmonicSignal(mean, a, b), lambda: SampledSignal(phase, values)):
        try:
            sig = make()
        except InputError:
            continue
        v = sig.value(np.linspace(-1.5, 2.5, 7))
        assert np.all(np.isfinite(v))


@FUZZ
@example(method="contact_line", options={"line_load": 0.0}, terms=None)  # found: zero mean
@given(method=st.sampled_from(["iso6336", "rectangular", "contact_line", "weber", "nope", ""]),
       options=st.dictionaries(st.sampled_from(["single", "double", "line_load", "bogus"]),
                               anything, max_size=2),
       terms=st.one_of(st.none(), st.integers(-2, 300), anything))
def test_stiffness_selector_is_a_stiffness_or_an_input_error(
    heli_pair: GearPair, method: str, options: dict[str, Any], terms: Any
) -> None:
    """build_stiffness with junk options: an InputError, or a stiffness with a finite positive
    mean. (potential_energy is left out: seconds per call.)"""
    from gear_dyn.stiffness.select import build_stiffness

    try:
        k = build_stiffness(heli_pair, method, fourier_terms=terms, **options)
    except InputError:
        return
    assert math.isfinite(k.mean) and k.mean > 0


@FUZZ
@given(t_end=st.one_of(st.floats(1e-6, 0.05), anything),
       steady=st.one_of(st.none(), st.floats(-1, 1), anything))
def test_simulate_time_span_is_valid_or_an_input_error(heli_pair: GearPair, t_end: Any,
                                                       steady: Any) -> None:
    from gear_dyn.analysis.study import simulate

    k = rectangular_stiffness(heli_pair.contact_ratio, 1e9, 1.75e9)
    m = sdof_from_pair(heli_pair, 300.0, 1000.0, k)
    try:
        r = simulate(m, t_end, SolverSettings(method="exact", samples_per_period=8), steady)
    except InputError:
        return
    assert np.all(np.isfinite(r.y)) and r.t[-1] <= t_end * (1 + 1e-9)


@FUZZ
@given(edges=arrays, samples=st.one_of(anything, st.lists(st.tuples(arrays, arrays),
                                                           max_size=3)),
       k0=anything, a=arrays, b=arrays, line_load=anything)
def test_stiffness_constructors_are_valid_or_an_input_error(
    heli_pair: GearPair, edges: Any, samples: Any, k0: Any, a: Any, b: Any, line_load: Any
) -> None:
    """PiecewiseStiffness, FourierStiffness and the ISO 6336 estimate from junk."""
    from gear_dyn.stiffness.iso6336 import iso6336_stiffness
    from gear_dyn.stiffness.periodic import FourierStiffness, PiecewiseStiffness

    for make in (lambda: PiecewiseStiffness(edges, samples), lambda: FourierStiffness(k0, a, b)):
        try:
            k = make()
        except InputError:
            continue
        assert np.all(np.isfinite(k(np.linspace(0, 1, 5))))
    try:
        iso = iso6336_stiffness(heli_pair, line_load=line_load)
    except InputError:
        return
    assert math.isfinite(iso.k_single) and iso.k_single >= 0
