"""Build the native FMU of a scene: model description, C sources and the Linux binary in a zip.

``build_native_fmu(scene, out)`` exports the single-DOF model as tables
(:mod:`gear_dyn.fmu.export`), writes ``model_data.c`` (:mod:`gear_dyn.fmu.export_c`), compiles it
with the fixed kernel and the FMI 2.0 glue by the system compiler and zips the FMU with its
sources (``<SourceFiles>``), so that an importer can rebuild it for its own platform.
"""

from __future__ import annotations

import re
import tempfile
import uuid
import zipfile
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import quoteattr

from gear_dyn.errors import InputError
from gear_dyn.fmu.export import NativeModel, native_model
from gear_dyn.fmu.export_c import (
    GLUE_SOURCES,
    HEADERS,
    KERNEL_SOURCES,
    NATIVE_DIR,
    OUTPUTS,
    PARAMS,
    compile_shared,
    model_data_c,
    start_values,
)
from gear_dyn.io import write_bytes

#: SI base-unit exponents of the units the FMU uses
BASE_UNITS = {"m": 'm="1"', "m/s": 'm="1" s="-1"', "rad/s": 'rad="1" s="-1"',
              "N": 'kg="1" m="1" s="-2"', "N.m": 'kg="1" m="2" s="-2"', "N/m": 'kg="1" s="-2"'}
#: largest FMU the build accepts, bytes
MAX_SIZE = 500_000


@dataclass(frozen=True)
class NativeFMU:
    """A built native FMU: its path, model identifier and the exported model."""

    path: Path
    model_identifier: str
    model: NativeModel
    scene_name: str


def model_description(nm: NativeModel, ident: str, scene_name: str, stop_time: float,
                      step: float) -> str:
    """The FMI 2.0 ``modelDescription.xml`` of a native model."""
    t = nm.table
    kind = "exact (piecewise-linear coefficients)" if t.exact else (
        f"fitted, max relative error k {t.max_error['k']:.1e}, e {t.max_error['e']:.1e}")
    desc = (f"gear_dyn single-DOF mesh model of scene {scene_name}, native C kernel. The gear "
            "geometry and the tables of k(p), e(p) over one mesh cycle are fixed at build "
            f"({t.flat.size} pieces, {kind}); the parameters are what the kernel applies "
            "without geometry.")
    units = sorted({p.unit for p in PARAMS} | {o[1] for o in OUTPUTS} - {"1"})
    unit_xml = "\n".join(f'    <Unit name="{u}"><BaseUnit {BASE_UNITS[u]}/></Unit>'
                         for u in units if u in BASE_UNITS)
    rows = []
    for vr, (p, start) in enumerate(zip(PARAMS, start_values(nm), strict=True), start=1):
        if p.name == "backlash.half_gap" and nm.half_gap is None:
            continue
        var = "continuous" if p.causality == "input" else "fixed"
        unit = f' unit="{p.unit}"' if p.unit != "1" else ""
        nominal = abs(start) if start else 1.0
        rows.append((vr, f'<ScalarVariable name="{p.name}" valueReference="{vr}" '
                         f'causality="{p.causality}" variability="{var}" '
                         f'description={quoteattr(p.description)}>'
                         f'<Real start="{start!r}"{unit} min="{p.low!r}" max="{p.high!r}" '
                         f'nominal="{nominal!r}"/></ScalarVariable>'))
    outs = []
    for k, (name, unit, doc) in enumerate(OUTPUTS):
        vr = len(PARAMS) + 1 + k
        rows.append((vr, f'<ScalarVariable name="{name}" valueReference="{vr}" '
                         f'causality="output" variability="continuous" initial="calculated" '
                         f'description={quoteattr(doc)}><Real unit="{unit}"/></ScalarVariable>'))
        outs.append(len(rows))
    variables = "\n".join(f"    {r}" for _, r in rows)
    unknowns = "\n".join(f'      <Unknown index="{i}"/>' for i in outs)
    sources = "".join(f'<File name="{f}"/>' for f in (*KERNEL_SOURCES, *GLUE_SOURCES[2],
                                                      "model_data.c"))
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="{ident}" guid="{{{uuid.uuid4()}}}"
  description={quoteattr(desc)} generationTool="gear_dyn native kernel"
  variableNamingConvention="structured" numberOfEventIndicators="0">
  <CoSimulation modelIdentifier="{ident}" canHandleVariableCommunicationStepSize="true"
    canGetAndSetFMUstate="true" canSerializeFMUstate="true">
    <SourceFiles>{sources}</SourceFiles>
  </CoSimulation>
  <UnitDefinitions>
{unit_xml}
  </UnitDefinitions>
  <DefaultExperiment startTime="0" stopTime="{stop_time!r}" stepSize="{step!r}"/>
  <ModelVariables>
{variables}
  </ModelVariables>
  <ModelStructure>
    <Outputs>
{unknowns}
    </Outputs>
    <InitialUnknowns>
{unknowns}
    </InitialUnknowns>
  </ModelStructure>
</fmiModelDescription>
"""


def build_native_fmu(target: str | Path, out: Path, fmi: int = 2,
                     tolerance: float = 1e-10) -> NativeFMU:
    """Build the native FMU of a scene.

    Parameters
    ----------
    target : str or Path
        Scene file, packaged scene name or model name (``sdof``).
    out : Path
        FMU file to write.
    fmi : int
        FMI version (2; 3 is not built natively yet).
    tolerance : float
        Start value of ``solver.tolerance`` (relative tolerance of the Runge-Kutta pieces).

    Raises
    ------
    NotNativeError
        A scene whose model has no native kernel (the torsional model).
    InputError
        Bad scene or output name, no C compiler, FMI 3, an FMU over :data:`MAX_SIZE`.
    SolverError
        The C compiler failed.
    """
    from gear_dyn.fmu.staging import fmu_target, load_fmu_scene
    from gear_dyn.scene import build_pair, build_plan

    if fmi != 2:
        raise InputError(f"--fmi {fmi}: the native FMU is built for FMI 2 only so far; use "
                         "--backend python for FMI 3")
    out = fmu_target(out)
    scene = load_fmu_scene(target)
    plan = build_plan(scene)
    op = scene.get("operating")
    nm = native_model(plan.model, build_pair(scene), op["speed"], op["torque"], tolerance)
    ident = "gd_" + re.sub(r"\W", "_", scene.name)
    f_m = plan.model.mesh_frequency
    step = 1.0 / (f_m * plan.settings.samples_per_period)
    xml = model_description(nm, ident, scene.name, float(plan.t_end), step)
    data = model_data_c(nm, scene.name)
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        (d / "model_data.c").write_text(data)
        srcs = [NATIVE_DIR / s for s in (*KERNEL_SOURCES, *GLUE_SOURCES[2])] + [d / "model_data.c"]
        so = compile_shared(srcs, d / f"{ident}.so")
        buf = d / "fmu.zip"
        with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
            z.writestr("modelDescription.xml", xml)
            z.write(so, f"binaries/linux64/{ident}.so")
            for s in srcs:
                z.write(s, f"sources/{s.name}")
            for name in HEADERS:
                z.write(NATIVE_DIR / name, f"sources/{name}")
            for hdr in sorted((NATIVE_DIR / "fmi2").iterdir()):
                z.write(hdr, f"sources/fmi2/{hdr.name}")
        payload = buf.read_bytes()
    if len(payload) > MAX_SIZE:
        raise InputError(f"native FMU: {len(payload)} bytes, valid range <= {MAX_SIZE} bytes")
    write_bytes(out, payload)
    return NativeFMU(Path(out), ident, nm, scene.name)

