"""Build the native FMU of a scene: model description, C sources and the Linux binary in a zip.

``build_native_fmu(scene, out)`` exports the single-DOF model (:mod:`gear_dyn.fmu.export`) or
the torsional model (:mod:`gear_dyn.fmu.export_torsional`) as tables, writes ``model_data.c``
(:mod:`gear_dyn.fmu.export_c`), compiles it with the fixed kernel and the FMI 2.0 or 3.0 glue by
the system compiler and zips the FMU with its sources (FMI 2 ``<SourceFiles>``, FMI 3
``sources/buildDescription.xml``), so that an importer can rebuild it for its own platform.
``resources/gear_dyn_native.json`` records the scene it was built from (SI tables and the
default experiment; :mod:`gear_dyn.fmu.fmu_info`): `gear-dyn cosim` runs it as the reference.
"""

from __future__ import annotations

import json
import re
import tempfile
import uuid
import zipfile
import zlib
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import quoteattr

from gear_dyn.errors import InputError
from gear_dyn.fmu.export import EXACT_ERROR, NativeModel, NotNativeError, native_model
from gear_dyn.fmu.export_c import (
    GLUE_HEADERS,
    GLUE_SOURCES,
    HEADERS,
    KERNEL_DIR,
    KERNEL_SOURCES,
    KERNEL_VERSION,
    NATIVE_DIR,
    OUTPUTS,
    PARAMS,
    TORSIONAL_OUTPUTS,
    direct_feedthrough,
    model_data_c,
    outputs_of,
    start_values,
)
from gear_dyn.fmu.export_drive import PORTS, DriveSpec, drive_c, drive_spec
from gear_dyn.fmu.export_torsional import TorsionalNative, torsional_native
from gear_dyn.fmu.fmu_info import NATIVE_FILE
from gear_dyn.fmu.toolchain import compile_binaries
from gear_dyn.fmu.variables import scene_record
from gear_dyn.io import write_bytes

#: SI base-unit exponents of the units the FMU uses
BASE_UNITS = {"m": 'm="1"', "rad": 'rad="1"', "m/s": 'm="1" s="-1"', "rad/s": 'rad="1" s="-1"',
              "kg.m2": 'kg="1" m="2"', "N": 'kg="1" m="1" s="-2"',
              "N.m": 'kg="1" m="2" s="-2"', "N/m": 'kg="1" s="-2"'}
#: largest FMU the build accepts, bytes
MAX_SIZE = 500_000


@dataclass(frozen=True)
class NativeFMU:
    """A built native FMU: its path, model identifier and the exported model."""

    path: Path
    model_identifier: str
    model: NativeModel | TorsionalNative
    scene_name: str
    fmi: int
    drive: DriveSpec | None = None


def _description(nm: NativeModel | TorsionalNative, scene_name: str) -> str:
    """The FMU's description: what is fixed at build and what the parameters change."""
    if isinstance(nm, TorsionalNative):
        return _torsional_description(nm, scene_name)
    t = nm.table
    method = ("closed form on every piece" if nm.stated_error == EXACT_ERROR else
              "Dormand-Prince 5(4) at solver.tolerance <= 1e-10")
    kind = "exact (piecewise-linear coefficients)" if t.exact else (
        f"fitted, max relative error k {t.max_error['k']:.1e}, e {t.max_error['e']:.1e}")
    return (f"gear_dyn single-DOF mesh model of scene {scene_name}, native C kernel. The gear "
            "geometry and the tables of k(p), e(p) over one mesh cycle are fixed at build "
            f"({t.breaks.size - 1} pieces, {kind}); the parameters are what the kernel applies "
            f"without geometry. Stated error of the DTE: {nm.stated_error:.0e} of the static "
            f"deflection W/k_m ({method}).{_load_note(nm)}")


def _torsional_description(nm: TorsionalNative, scene_name: str) -> str:
    t = nm.table
    err = max(t.max_error.values())
    span = (f"the hunting period ({t.period} mesh cycles)" if t.period > 1 else
            "one mesh cycle")
    form = (f"the tables of e_ecc, k, phi1, phi2 over {span} in the mesh phase are fixed at "
            f"build ({t.breaks.size - 1} pieces between the switching instants, degree "
            f"{t.degree}, max relative table error {err:.1e})" if t.lines is None else
            f"the eccentric kinematics over {span} as Fourier series in the mesh phase "
            f"({t.lines.fourier.shape[0] - 1} harmonics), from which the kernel evaluates the "
            f"contact lines, k, phi1 and phi2, are fixed at build ({t.breaks.size - 1} pieces "
            f"between the switching instants, max relative error {err:.1e})")
    return (f"gear_dyn torsional model (two DOF{', friction' if nm.friction else ''}) of scene "
            f"{scene_name}, native C kernel. The gear geometry and {form}; the parameters are "
            "what the kernel applies without geometry. Stated "
            f"error of the DTE: {nm.stated_error:.0e} of the static deflection W/k_m "
            "(Dormand-Prince 5(4) at solver.tolerance <= 1e-10).")


def _load_note(nm: NativeModel | TorsionalNative) -> str:
    """The sentence that says the loaded-contact tables belong to the build torque."""
    if not nm.load_tables:
        return ""
    return (f" The loaded-contact tables (tangent stiffness k_t(p) and the relief's e(p)) are "
            f"those of the build torque {nm.torque!r} N.m: the torque input changes the load "
            "W = T1/r_b1 only (the model is linearised about the build load); rebuild the FMU "
            "for another operating torque.")


def _drive_description(nm: NativeModel | TorsionalNative, scene_name: str,
                       speed_in: bool = False) -> str:
    """The drivetrain FMU's description: the model, its ports and what is fixed at build."""
    t = nm.table
    span = (f"{nm.table.period} mesh cycles"
            if isinstance(nm, TorsionalNative) and nm.table.period > 1 else "one mesh cycle")
    kind = "torsional" if isinstance(nm, TorsionalNative) else "single-DOF"
    ports = ("the pinion driven by speed (pinion.speed in, held over a step; out the torque "
             "pinion.torque its shaft delivers; both it and the mesh force depend directly on "
             "pinion.speed, through the mesh damping), a "
             "torque input on the gear (gear.torque, positive in its sense of rotation); the "
             "angles, the gear speed, the mesh force and the DTE out" if speed_in else
             "a torque input on each (pinion.torque, gear.torque, positive in the shaft's "
             "sense of rotation), the angle and speed of each shaft, the mesh force and the "
             "DTE out; no output depends directly on an input")
    return (f"gear_dyn drivetrain interface of scene {scene_name} ({kind} tables), native C "
            f"kernel: the two-DOF torsional mesh between two shafts, {ports}. Fixed at build: "
            f"the gear geometry (base radii r_b1 = {nm.rb1!r} m, r_b2 = {nm.rb2!r} m, ratio "
            f"z2/z1 = {nm.rb2 / nm.rb1!r}; the calculated parameters base_radius.* and ratio) "
            f"and the tables over {span} in the mesh phase ({t.breaks.size - 1} pieces), which "
            "follows the pinion angle. The inertias, damping ratio, backlash and tolerance are "
            "parameters. Dormand-Prince 5(4) with absolute error control at solver.tolerance, "
            f"piece edges located on the pinion angle.{_load_note(nm)}")


def _units() -> str:
    from gear_dyn.fmu.export_drive import DRIVE_CONSTANTS, DRIVE_OUTPUTS, DRIVE_PARAMS

    units = sorted({p.unit for p in PARAMS + DRIVE_PARAMS}
                   | {o[1] for o in OUTPUTS + TORSIONAL_OUTPUTS + DRIVE_OUTPUTS
                      + DRIVE_CONSTANTS} - {"1"})
    return "\n".join(f'    <Unit name="{u}"><BaseUnit {BASE_UNITS[u]}/></Unit>'
                     for u in units if u in BASE_UNITS)


def _variables(nm: NativeModel | TorsionalNative) -> list[tuple[int, str, dict[str, str]]]:
    """(value reference, kind, attributes) of every variable; kind is "par" or "out"."""
    rows: list[tuple[int, str, dict[str, str]]] = []
    for vr, (p, start) in enumerate(zip(PARAMS, start_values(nm), strict=True), start=1):
        if p.name == "backlash.half_gap" and nm.half_gap is None:
            continue
        doc = p.description
        if p.name == "operating.torque" and nm.load_tables:
            doc += (f"; changes W only: the loaded-contact tables are fixed at the build "
                    f"torque {nm.torque!r} N.m")
        attrs = {"name": p.name, "causality": p.causality,
                 "variability": "continuous" if p.causality == "input" else "fixed",
                 "description": doc, "start": repr(start),
                 "min": repr(p.low), "max": repr(p.high),
                 "nominal": repr(abs(start) if start else 1.0)}
        if p.unit != "1":
            attrs["unit"] = p.unit
        rows.append((vr, "par", attrs))
    for k, (name, unit, doc) in enumerate(outputs_of(nm)):
        rows.append((len(PARAMS) + 1 + k, "out",
                     {"name": name, "causality": "output", "variability": "continuous",
                      "description": doc, "unit": unit}))
    return rows


def _drive_variables(nm: NativeModel | TorsionalNative, drive: DriveSpec
                     ) -> list[tuple[int, str, dict[str, str]]]:
    """The drivetrain interface's variables, as :func:`_variables` ("calc": a calculated
    parameter)."""
    from gear_dyn.fmu.export_drive import DRIVE_CONSTANTS, drive_variables

    rows: list[tuple[int, str, dict[str, str]]] = []
    backlash = isinstance(nm, NativeModel) and nm.half_gap is not None
    params, outputs = drive_variables(drive.speed_in)
    for vr, (p, start) in enumerate(zip(params, drive.start, strict=True), start=1):
        if (p.name == "backlash.half_gap" and not backlash) or (
                p.name == "pinion.speed_start" and drive.speed_in):
            continue
        attrs = {"name": p.name, "causality": p.causality,
                 "variability": "continuous" if p.causality == "input" else "fixed",
                 "description": p.description, "start": repr(float(start)),
                 "min": repr(p.low), "max": repr(p.high),
                 "nominal": repr(abs(start) if start else 1.0)}
        if p.unit != "1":
            attrs["unit"] = p.unit
        rows.append((vr, "par", attrs))
    n = len(params)
    for k, (name, unit, doc) in enumerate(outputs):
        rows.append((n + 1 + k, "out", {"name": name, "causality": "output",
                                        "variability": "continuous", "description": doc,
                                        "unit": unit}))
    n += len(outputs)
    for k, (name, unit, doc) in enumerate(DRIVE_CONSTANTS):
        a = {"name": name, "causality": "calculatedParameter", "variability": "fixed",
             "description": doc}
        if unit != "1":
            a["unit"] = unit
        rows.append((n + 1 + k, "calc", a))
    return rows


def _attr(a: dict[str, str], keys: tuple[str, ...]) -> str:
    return " ".join(f"{k}={quoteattr(a[k])}" for k in keys if k in a)


def model_description(nm: NativeModel | TorsionalNative, ident: str, scene_name: str,
                      stop_time: float, step: float, fmi: int = 2, token: str = "",
                      drive: DriveSpec | None = None) -> str:
    """The FMI 2.0 or 3.0 ``modelDescription.xml`` of a native model, with the instantiation
    token (FMI 2 guid) ``token`` (the one in its ``model_data.c``); ``drive``: the drivetrain
    interface's (None: the pinion-speed interface)."""
    rows = _variables(nm) if drive is None else _drive_variables(nm, drive)
    head = ("name", "valueReference", "causality", "variability")
    # the drive's: none but the speed-driven pinion's torque (gd_drive.c)
    feed = (direct_feedthrough(nm) if drive is None else
            {"pinion.torque": ("pinion.speed",), "mesh_force": ("pinion.speed",)}
            if drive.speed_in else {})
    about = (_description(nm, scene_name) if drive is None
             else _drive_description(nm, scene_name, drive.speed_in))
    if fmi == 2:
        lines, outs, index = [], [], {}
        for vr, kind, a in rows:
            a = {**a, "valueReference": str(vr)}
            if kind in ("out", "calc"):
                a["initial"] = "calculated"
            real = _attr(a, ("start", "unit", "min", "max", "nominal"))
            lines.append(f'    <ScalarVariable {_attr(a, (*head, "initial", "description"))}>'
                         f'<Real {real}/></ScalarVariable>')
            index[a["name"]] = len(lines)
            if kind == "out":
                outs.append(a["name"])
        initial = [a["name"] for _vr, k, a in rows if k in ("out", "calc")]
        structure = ("    <Outputs>\n" + "\n".join(
            f'      <Unknown index="{index[o]}" dependencies='
            f'"{" ".join(str(index[d]) for d in feed.get(o, ()))}"/>' for o in outs) +
            "\n    </Outputs>\n    <InitialUnknowns>\n" +
            "\n".join(f'      <Unknown index="{index[o]}"/>' for o in initial) +
            "\n    </InitialUnknowns>")
        sources = "".join(f'<File name="{f}"/>' for f in _sources(2))
        version = f'fmiVersion="2.0" guid="{token}" numberOfEventIndicators="0"'
        cosim = (f'canGetAndSetFMUstate="true" canSerializeFMUstate="true">\n'
                 f"    <SourceFiles>{sources}</SourceFiles>\n  </CoSimulation>")
    else:
        lines = ['    <Float64 name="time" valueReference="0" causality="independent" '
                 'variability="continuous" description="simulation time" unit="s"/>']
        for vr, _kind, a in rows:
            a = {**a, "valueReference": str(vr)}
            keys = (*head, "description", "start", "unit", "min", "max", "nominal")
            lines.append(f"    <Float64 {_attr(a, keys)}/>")
        vrs = {a["name"]: vr for vr, _k, a in rows}
        structure = "\n".join(
            [f'    <Output valueReference="{vr}" dependencies='
             f'"{" ".join(str(vrs[d]) for d in feed.get(a["name"], ()))}"/>'
             for vr, k, a in rows if k == "out"] +
            [f'    <InitialUnknown valueReference="{vr}"/>' for vr, k, _ in rows
             if k in ("out", "calc")])
        version = f'fmiVersion="3.0" instantiationToken="{token}"'
        cosim = 'canGetAndSetFMUState="true" canSerializeFMUState="true"/>'
    variables = "\n".join(lines)
    s_unit = '    <Unit name="s"><BaseUnit s="1"/></Unit>\n' if fmi == 3 else ""
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription {version} modelName="{ident}"
  description={quoteattr(about)}
  generationTool="gear_dyn native kernel {KERNEL_VERSION}" variableNamingConvention="structured">
  <CoSimulation modelIdentifier="{ident}" canHandleVariableCommunicationStepSize="true"
    {cosim}
  <UnitDefinitions>
{s_unit}{_units()}
  </UnitDefinitions>
  <DefaultExperiment startTime="0" stopTime="{stop_time!r}" stepSize="{step!r}"/>
  <ModelVariables>
{variables}
  </ModelVariables>
  <ModelStructure>
{structure}
  </ModelStructure>
</fmiModelDescription>
"""


def _too_large(nm: TorsionalNative, size: str, max_size: int) -> NotNativeError:
    """The refusal of a torsional FMU over ``max_size`` bytes (asked for by the caller)."""
    return NotNativeError(f"its table ({nm.table.breaks.size - 1} pieces over {nm.table.period} "
                          f"mesh cycles) makes a native FMU of {size}, over the "
                          f"{max_size // 1000} kB limit")


def _sources(fmi: int) -> tuple[str, ...]:
    """The C sources of an FMU, compiled together (headers beside them)."""
    return (*KERNEL_SOURCES, *GLUE_SOURCES[fmi], "model_data.c")


def build_description(ident: str) -> str:
    """FMI 3.0 ``sources/buildDescription.xml``: one C99 source set, libm."""
    files = "\n".join(f'      <SourceFile name="{f}"/>' for f in _sources(3))
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<fmiBuildDescription fmiVersion="3.0">
  <BuildConfiguration modelIdentifier="{ident}" description="C99, link with libm">
    <SourceFileSet language="C99">
{files}
      <IncludeDirectory name="."/>
    </SourceFileSet>
    <Library name="m"/>
  </BuildConfiguration>
</fmiBuildDescription>
"""


def build_native_fmu(target: str | Path, out: Path, fmi: int = 2,
                     tolerance: float = 1e-10, max_size: int | None = None,
                     ports: str = "speed") -> NativeFMU:
    """Build the native FMU of a scene.

    Parameters
    ----------
    target : str or Path
        Scene file, packaged scene name or model name (``sdof``).
    out : Path
        FMU file to write.
    fmi : int
        FMI version, 2 or 3.
    tolerance : float
        Start value of ``solver.tolerance`` (relative tolerance of the Runge-Kutta pieces).
    max_size : int or None
        Largest FMU accepted, bytes (None, the default: no limit). Every packaged scene is
        built natively: a native FMU runs on any machine, the pythonfmu one only beside its
        build interpreter, so a large native FMU is preferred to a small one that does not
        start. ``MAX_SIZE`` (500 kB) is the size target of the benchmark
        (benchmarks/results/native_fmu.md), which the eccentric scene's table exceeds.
    ports : str
        ``speed`` (the default): the pinion-speed interface (speed and torque inputs on the
        pinion, the load fixed by the model); ``torque``: the drivetrain interface
        (:mod:`gear_dyn.fmu.export_drive`: a torque input on each shaft, the angles and speeds
        out); ``shaft-speed``: its speed-driven variant (the pinion driven by speed, the
        torque its shaft delivers out).

    Raises
    ------
    NotNativeError
        A scene whose model has no native kernel (backlash or TE in the torsional model), or a
        torsional table that makes the FMU larger than ``max_size``.
    InputError
        Bad scene or output name, an FMI version other than 2 and 3, no C compiler, a
        single-DOF FMU over ``max_size``.
    SolverError
        The C compiler failed.
    """
    from gear_dyn.fmu.staging import fmu_target, load_fmu_scene
    from gear_dyn.scene import build_pair, build_plan
    from gear_dyn.scene.build import scene_inertias

    if fmi not in (2, 3):
        raise InputError(f"--fmi {fmi}: valid FMI versions are 2 and 3")
    if ports not in PORTS:
        raise InputError(f"--ports {ports}: valid choices are {', '.join(PORTS)}")
    out = fmu_target(out)
    scene = load_fmu_scene(target)
    plan = build_plan(scene)
    op = scene.get("operating")
    nm: NativeModel | TorsionalNative
    if "deviations" in scene.tables:
        raise InputError("[deviations]: the FMU carries a transmission error of mesh harmonics "
                         "only; deviations repeat over the hunting period: remove the table")
    if not plan.model.mesh_periodic:  # the torsional model (Model protocol: not one mesh eq.)
        nm = torsional_native(plan.model, build_pair(scene), tolerance)
    else:
        nm = native_model(plan.model, build_pair(scene), op["speed"], op["torque"], tolerance,
                          load_tables="tip_relief" in scene.tables)
    ident = "gd_" + re.sub(r"\W", "_", scene.name)
    f_m = plan.model.mesh_frequency
    step = 1.0 / (f_m * plan.settings.samples_per_period)
    drive = None
    if ports != "speed":
        inertias = (nm.inertias if isinstance(nm, TorsionalNative) else
                    scene_inertias(scene) or build_pair(scene).blank_inertias())
        drive = drive_spec(nm, inertias, speed_in=ports == "shaft-speed")
        ident += "_drive" if ports == "torque" else "_speed_drive"
    token = f"{{{uuid.uuid4()}}}"  # the modelDescription's and the binary's: checked by the glue
    xml = model_description(nm, ident, scene.name, float(plan.t_end), step, fmi, token, drive)
    data = model_data_c(nm, scene.name, token, "" if drive is None else drive_c(drive))
    if max_size is not None and isinstance(nm, TorsionalNative):
        # the zip holds model_data.c deflated: a lower bound of the FMU, known before compiling
        least = len(zlib.compress(data.encode(), 6))
        if least > max_size:
            raise _too_large(nm, f"at least {least // 1000} kB (its model_data.c alone)",
                             max_size)
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        (d / "model_data.c").write_text(data)
        srcs = [*(KERNEL_DIR / s for s in KERNEL_SOURCES),
                *(NATIVE_DIR / s for s in GLUE_SOURCES[fmi])]
        srcs.append(d / "model_data.c")
        # x86_64 Linux always; x86_64 Windows too where MinGW-w64 is installed
        binaries = compile_binaries(srcs, d / "binaries", ident, fmi,
                                    include_dirs=[KERNEL_DIR, NATIVE_DIR])
        buf = d / "fmu.zip"
        with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
            z.writestr("modelDescription.xml", xml)
            # the scene it was built from: what `gear-dyn cosim` runs as its reference
            z.writestr(f"resources/{NATIVE_FILE}", json.dumps(scene_record(scene, plan),
                                                             indent=1))
            for folder, library in binaries.items():
                z.write(library, f"binaries/{folder}/{library.name}")
            for s in srcs:
                z.write(s, f"sources/{s.name}")
            for name in HEADERS:
                z.write(KERNEL_DIR / name, f"sources/{name}")
            for name in GLUE_HEADERS:
                z.write(NATIVE_DIR / name, f"sources/{name}")
            for hdr in sorted((NATIVE_DIR / f"fmi{fmi}").iterdir()):
                z.write(hdr, f"sources/fmi{fmi}/{hdr.name}")
            if fmi == 3:
                z.writestr("sources/buildDescription.xml", build_description(ident))
        payload = buf.read_bytes()
    if max_size is not None and len(payload) > max_size:
        if isinstance(nm, TorsionalNative):
            raise _too_large(nm, f"{len(payload) // 1000} kB", max_size)
        raise InputError(f"native FMU: {len(payload)} bytes, valid range <= {max_size} bytes")
    write_bytes(out, payload)
    return NativeFMU(Path(out), ident, nm, scene.name, fmi, drive)

