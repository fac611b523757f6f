"""The build of the pythonfmu FMU, FMI 2 and FMI 3 alike: the scene to build, the private copy
of the sources, the staging folder and the completed modelDescription.xml.

An FMU carries everything it runs: the generated slave script, a private copy of the gear_dyn
sources under a name unique to the build (its absolute imports and module-name strings are
rewritten to that name, so two FMUs in one process, or an FMU next to an installed gear_dyn,
never share modules), the scene in SI values and the build interpreter's facts.
:func:`gear_dyn.fmu.build.build_fmu` (FMI 2 with pythonfmu, FMI 3 with pythonfmu3) stages its
build here and completes the modelDescription.xml the exporter writes.
"""

from __future__ import annotations

import contextlib
import importlib
import io
import json
import re
import secrets
import shutil
import sys
import sysconfig
import tempfile
import zipfile
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any
from xml.etree import ElementTree as ET

from gear_dyn.errors import InputError
from gear_dyn.fmu.variables import SPEC_FILE, UNITS, fmu_spec
from gear_dyn.io import write_bytes
from gear_dyn.scene import Scene, load_scene
from gear_dyn.scene.packaged import scene_path

PACKAGE_ROOT = Path(__file__).resolve().parent.parent
#: ``gear-dyn fmu build MODEL``: the packaged scene each model name stands for
MODEL_SCENES = {"sdof": "helicopter_tail", "torsional": "eccentric_helical"}

#: the build interpreter's facts in the FMU's resources (the Python the FMU needs)
PYTHON_FILE = "gear_dyn_python.json"


def python_info() -> dict[str, Any]:
    """The build interpreter: executable, version, libpython and the import path."""
    libdir = sysconfig.get_config_var("LIBDIR") or ""
    soname = sysconfig.get_config_var("INSTSONAME") or ""
    return {"executable": sys.executable, "version": list(sys.version_info[:2]),
            "prefix": sys.prefix, "base_prefix": sys.base_prefix,
            "libpython": str(Path(libdir, soname)) if libdir and soname else None,
            "path": [p for p in sys.path if p and Path(p).is_dir()]}


_IMPORT_RE = re.compile(r"^([ \t]*)(from|import)([ \t]+)gear_dyn\b", re.MULTILINE)
_STRING_RE = re.compile(r"""(["'])gear_dyn\.""")


@dataclass(frozen=True)
class BuiltFmu:
    """What :func:`gear_dyn.fmu.build.build_fmu` made."""

    path: Path
    model_identifier: str
    package: str
    spec: dict[str, Any]


def load_fmu_scene(target: str | Path) -> Scene:
    """A scene from a file, a packaged scene name or a model name (``sdof``, ``torsional``).

    Raises
    ------
    SceneError / InputError
        No such file, scene or model; or an invalid scene.
    """
    p = Path(target)
    if p.suffix == ".toml" or p.exists():
        return load_scene(p)
    name = MODEL_SCENES.get(str(target), str(target))
    candidate = scene_path(name)
    if candidate.exists():
        return load_scene(candidate)
    raise InputError(f"{target}: not a scene file, packaged scene or model name "
                     f"(models: {', '.join(MODEL_SCENES)})")


#: gear_dyn sources the FMU never runs (the slim FMU leaves them out): the CLI, plots, the FMU
#: build and co-simulation side, file output, and the studies beyond a run's own checks
NOT_IN_FMU = ("cli/", "plots/", "fmu/build.py", "fmu/staging.py",
              "fmu/check.py", "fmu/cosim.py", "fmu/export", "io.py",
              "scene/packaged.py", "scene/sweep.py", "scenes/", "analysis/sweep/",
              "solvers/linear_maps.py", "solvers/kernel/linear.py",
              "analysis/bench.py", "analysis/chart.py", "analysis/excitation.py",
              "analysis/report.py", "analysis/spectrum.py", "analysis/spectrum_labels.py",
              "analysis/stiffness.py", "analysis/tolerance.py", "scene/tolerance.py",
              "analysis/compare.py", "scene/compare.py", "analysis/relief_study.py",
              "analysis/continuation/", "analysis/motion/", "scene/bifurcation.py")


def _vendor(dest: Path, package: str, skip: tuple[str, ...] = ("fmu/slave3.py",)) -> None:
    """Copy the gear_dyn sources the FMU runs (all but :data:`NOT_IN_FMU` and ``skip``, the
    other FMI version's slave) to ``dest/package`` with imports renamed to ``package``."""
    target = dest / package
    for src in PACKAGE_ROOT.rglob("*"):
        rel = src.relative_to(PACKAGE_ROOT)
        if "__pycache__" in rel.parts or src.is_dir():
            continue
        if rel.as_posix().startswith(NOT_IN_FMU + skip):
            continue
        if src.suffix not in (".py", ".toml", ".typed"):
            continue
        out = target / rel
        out.parent.mkdir(parents=True, exist_ok=True)
        if src.suffix == ".py":
            text = src.read_text("utf-8")
            text = _IMPORT_RE.sub(lambda m: f"{m[1]}{m[2]}{m[3]}{package}", text)
            text = _STRING_RE.sub(lambda m: f"{m[1]}{package}.", text)
            out.write_text(text, "utf-8")
        else:
            shutil.copy2(src, out)


def slave_script(package: str, class_name: str, spec: dict[str, Any], fmi: int) -> str:
    """The generated slave script: the class ``class_name`` over the private copy's FMI 2
    (:class:`~gear_dyn.fmu.slave.GearDynSlave`) or FMI 3 slave, with a one-line reason on
    stderr when the importing Python lacks numpy or scipy."""
    if fmi == 3:
        # pythonfmu3 finds the class by a regex that wants ``Fmi3Slave`` among its bases
        imports = f"    from pythonfmu3 import Fmi3Slave\n    from {package}.fmu.slave3 import " \
                  "GearDynSlave3\n"
        bases, extra = "GearDynSlave3, Fmi3Slave", "\n"
    else:
        imports = f"    from {package}.fmu.slave import GearDynSlave\n"
        bases = "GearDynSlave"
        extra = ("# pythonfmu's loader releases one reference to this module's dict per "
                 "instantiation\n# that it never took; GearDynSlave.__init__ gives one back, "
                 "these cover the gap\n_REFERENCES = [globals()] * 8\n\n\n")
    option = " --fmi 3" if fmi == 3 else ""
    return (
        f'"""gear_dyn FMI {fmi} FMU slave of scene {spec["scene_name"]!r} ({spec["model"]} '
        f"model).\n\nGenerated by `gear-dyn fmu build{option}`; the physics is in the private "
        f"gear_dyn copy {package!r}.\n" + '"""\n\n'
        "import sys\n\n"
        "try:\n"
        "    import numpy  # noqa: F401\n"
        "    import scipy.integrate  # noqa: F401\n" + imports +
        "except ImportError as _exc:  # pythonfmu shows the reason only with debug logging on\n"
        "    sys.stderr.write(f'gear_dyn FMU: cannot instantiate: Python package '\n"
        "                     f'{_exc.name or _exc!r} is missing in the Python at {sys.prefix} '\n"
        "                     '(the FMU needs numpy and scipy)\\n')\n"
        "    raise\n\n" + extra +
        f"class {class_name}({bases}):\n"
        f'    """gear_dyn {spec["model"]} model as an FMI {fmi}.0 co-simulation slave."""\n'
    )


def build_with(builder: Any, target: str | Path | Scene, out: str | Path, fmi: int,
               **options: bool) -> BuiltFmu:
    """Build the FMU of ``target`` with pythonfmu's (``fmi=2``) or pythonfmu3's (``fmi=3``)
    ``FmuBuilder`` (``options``: its FMU-state flags), complete its modelDescription.xml
    (:func:`complete_model_description`, after the gear_dyn version is added to its
    generationTool) and write it to ``out`` whole or not at all. pythonfmu3's C++ loader
    sources are left out (the FMI 2 FMU carries none either).

    Raises
    ------
    InputError
        Bad target or output name, invalid scene, or no builder binary for this platform.
    """
    out = fmu_target(out)
    if not builder.has_binary():
        raise InputError(f"{builder.__module__.split('.')[0]} has no binary for this platform; "
                         "install a wheel that ships one")
    spec = fmu_spec(target if isinstance(target, Scene) else load_fmu_scene(target))
    token = secrets.token_hex(5)  # fresh names: every FMU loads its own private copy
    tag = "3" if fmi == 3 else ""
    package = f"gear_dyn_fmu_{token}"
    module = f"gear_dyn_slave{tag}_{spec['model']}_{token}"
    class_name = f"GearDyn{tag}_{spec['model']}_{token}"
    out.parent.mkdir(parents=True, exist_ok=True)
    other = "fmu/slave.py" if fmi == 3 else "fmu/slave3.py"
    with staged_build(spec, package, module, slave_script(package, class_name, spec, fmi),
                      skip=(other,)) as (tmp, script, files):
        raw = builder.build_FMU(script, dest=tmp / "raw.fmu", project_files=files, **options)
        src = zipfile.ZipFile(io.BytesIO(Path(raw).read_bytes()))
    root = ET.fromstring(src.read("modelDescription.xml"))
    from gear_dyn import __version__

    root.set("generationTool", f"gear_dyn {__version__} ({root.get('generationTool', '')})")
    mv = root.find("ModelVariables")
    if mv is None:
        raise InputError("modelDescription.xml without ModelVariables")
    by_name = {v["name"]: v for v in spec["variables"]}
    complete_model_description(root, mv, by_name, fmi)
    ET.indent(root, space="  ")
    xml = ET.tostring(root, encoding="UTF-8", xml_declaration=True)
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as dst:
        for info in src.infolist():
            if not info.filename.startswith("sources/"):
                name = info.filename
                dst.writestr(info, xml if name == "modelDescription.xml" else src.read(name))
    write_bytes(out, buf.getvalue())
    return BuiltFmu(out, class_name, package, spec)


def complete_model_description(root: ET.Element, mv: ET.Element, by_name: dict[str, Any],
                               fmi: int) -> None:
    """Add what pythonfmu (``fmi=2``) and pythonfmu3 (``fmi=3``) leave out of their
    modelDescription.xml (``root``, its ModelVariables ``mv``; ``by_name``: the spec's
    variables by name): UnitDefinitions and units, ``min``/``max``/``nominal`` from the scene
    fields, the Integer stand-ins of choice parameters turned into Enumerations with their
    types (item k = choice k, so a master offers the choices), ``dependencies=""`` on every
    output and, for FMI 2, the InitialUnknowns.
    """
    real, integer = ("Real", "Integer") if fmi == 2 else ("Float64", "Int64")
    used: dict[str, str] = {}
    types = ET.Element("TypeDefinitions")
    outputs: list[int] = []
    for index, el in enumerate(mv, start=1):
        v = by_name.get(el.get("name", ""))
        typed = next(iter(el), None) if fmi == 2 else el  # FMI 2: the ScalarVariable's type
        if v is None or typed is None:
            continue
        if el.get("causality") == "output":
            outputs.append(index)
        if v["type"] == "Enumeration" and typed.tag == integer:
            type_name = f"{v['name']}.choices"
            typed.tag = "Enumeration"
            typed.set("declaredType", type_name)
            if fmi == 2:
                simple = ET.SubElement(types, "SimpleType", {"name": type_name})
                items = ET.SubElement(simple, "Enumeration")
            else:
                items = ET.SubElement(types, "EnumerationType", {"name": type_name})
            for k, choice in enumerate(v["choices"], start=1):
                ET.SubElement(items, "Item", {"name": choice, "value": str(k)})
            continue
        for key in ("min", "max", "nominal"):
            if key in v and (key != "nominal" or typed.tag == real):
                typed.set(key, repr(v[key]))
        if typed.tag == real and v.get("unit") in UNITS:
            typed.set("unit", UNITS[v["unit"]][0])
            used[v["unit"]] = UNITS[v["unit"]][0]
    if mv.find("Float64[@name='time']") is not None:  # FMI 3's independent variable
        used["s"] = UNITS["s"][0]
    cs = root.find("CoSimulation")
    if cs is None:
        raise InputError("modelDescription.xml without CoSimulation")
    # the slave takes any step size; pythonfmu3 0.3.4 writes this flag from the wrong option
    # (pythonfmu writes it right: for FMI 2 this sets what is there)
    cs.set("canHandleVariableCommunicationStepSize", "true")
    pos = list(root).index(cs) + 1
    if used:
        root.insert(pos, unit_definitions(used))
        pos += 1
    if len(types):
        old = root.find("TypeDefinitions")
        if old is not None:
            root.remove(old)
        root.insert(pos, types)
    ms = root.find("ModelStructure")
    if ms is None:
        ms = ET.SubElement(root, "ModelStructure")
    # no direct feedthrough: outputs are computed from the state at doStep (and at
    # exitInitializationMode) only, so setting an input changes no output before the next step
    for unknown in ms.findall("Outputs/Unknown" if fmi == 2 else "Output"):
        unknown.set("dependencies", "")
    if fmi == 2 and outputs and ms.find("InitialUnknowns") is None:
        iu = ET.SubElement(ms, "InitialUnknowns")
        for index in outputs:
            ET.SubElement(iu, "Unknown", {"index": str(index)})


def unit_definitions(used: dict[str, str]) -> ET.Element:
    """A ``<UnitDefinitions>`` element for the scene units ``used`` (keys of
    :data:`~gear_dyn.fmu.variables.UNITS`): SI base units and display units such as rpm."""
    defs = ET.Element("UnitDefinitions")
    for unit in sorted(used):
        name, base, display = UNITS[unit]
        u = ET.SubElement(defs, "Unit", {"name": name})
        ET.SubElement(u, "BaseUnit", {k: str(e) for k, e in base.items()})
        for dname, factor in display:
            ET.SubElement(u, "DisplayUnit", {"name": dname, "factor": repr(factor)})
    return defs


def fmu_target(out: str | Path) -> Path:
    """``out`` as the FMU file to write: a ``.fmu`` name that is not a folder (InputError)."""
    out = Path(out)
    if out.suffix != ".fmu":
        raise InputError(f"--out {out}: an FMU file name must end in .fmu")
    if out.exists() and out.is_dir():
        raise InputError(f"--out {out}: is a folder, expected an .fmu file name")
    return out


@contextlib.contextmanager
def staged_build(spec: dict[str, Any], package: str, module: str, script: str,
                 skip: tuple[str, ...]) -> Iterator[tuple[Path, Path, list[Path]]]:
    """A staging folder for an exporter: the private copy of the package (``_vendor``), the
    FMU spec and build-interpreter files and the slave script ``module.py``. Yields (temporary
    folder, script path, project files). The exporter imports the script (and so the private
    copy) from the staging folder: on exit those modules are forgotten and sys.path restored,
    so the FMU loads its own copy when it is instantiated."""
    with tempfile.TemporaryDirectory(prefix="gear_dyn_fmu_") as tmp:
        stage = Path(tmp) / "stage"
        stage.mkdir()
        _vendor(stage, package, skip=skip)
        (stage / SPEC_FILE).write_text(json.dumps(spec, indent=1), "utf-8")
        (stage / PYTHON_FILE).write_text(json.dumps(python_info(), indent=1), "utf-8")
        path = stage / f"{module}.py"
        path.write_text(script, "utf-8")
        saved_path = list(sys.path)
        try:
            yield Path(tmp), path, [stage / package, stage / SPEC_FILE, stage / PYTHON_FILE]
        finally:
            sys.path[:] = saved_path
            for name in [m for m in sys.modules
                         if m == module or m == package or m.startswith(package + ".")]:
                del sys.modules[name]
            importlib.invalidate_caches()
