"""Build an FMI 2.0 co-simulation FMU of a scene with pythonfmu.

The FMU carries everything it runs, so the importing machine needs only Python with numpy and
scipy (no gear_dyn, pint, matplotlib or pythonfmu install):

- ``resources/<script>.py``: the generated slave script, one class deriving from
  :class:`gear_dyn.fmu.slave.GearDynSlave`;
- ``resources/<package>/``: a private copy of the gear_dyn sources under a name unique to this
  build (its absolute imports and module-name strings are rewritten to that name). Two FMUs in
  one process - or an FMU next to an installed gear_dyn - therefore never share modules;
  pythonfmu finds the slave by the script's module name, which is unique as well;
- ``resources/gear_dyn_fmu.json``: the scene in SI values, the variables and the experiment;
- ``resources/pythonfmu/`` and ``binaries/<platform>/<id>.so|.dll``: pythonfmu's loader.

pythonfmu does not write units or initial unknowns, so the modelDescription.xml in the zip is
completed afterwards: UnitDefinitions (SI base units, display units such as rpm, mm, deg), a
``unit`` on every Real with one, and ModelStructure/InitialUnknowns for the outputs.
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
import tempfile
import zipfile
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any
from xml.etree import ElementTree as ET

from gear_dyn.errors import InputError
from gear_dyn.fmu.native import PYTHON_FILE, boot_binaries, python_info, unsupported_reason
from gear_dyn.fmu.variables import SPEC_FILE, UNITS, fmu_spec
from gear_dyn.io import write_bytes
from gear_dyn.scene import Scene, load_scene

PACKAGE_ROOT = Path(__file__).resolve().parent.parent
#: ``gear-dyn fmu build MODEL``: the packaged scene each model name stands for
MODEL_SCENES = {"sdof": "helicopter_tail", "torsional": "eccentric_helical"}

_IMPORT_RE = re.compile(r"^([ \t]*)(from|import)([ \t]+)gear_dyn\b", re.MULTILINE)
_STRING_RE = re.compile(r"""(["'])gear_dyn\.""")


@dataclass(frozen=True)
class BuiltFmu:
    """What :func:`build_fmu` made."""

    path: Path
    model_identifier: str
    package: str
    spec: dict[str, Any]
    #: why the FMU runs only in Python hosts (None: it runs in C hosts too, see .native)
    c_host_missing: str | None = None


def resolve_scene(target: str | Path) -> Scene:
    """A scene from a file, a packaged scene name or a model name (``sdof``, ``torsional``).

    Raises
    ------
    SceneError / InputError
        No such file, scene or model; or an invalid scene.
    """
    p = Path(target)
    if p.suffix == ".toml" or p.exists():
        return load_scene(p)
    from gear_dyn.scene.packaged import scene_path

    name = MODEL_SCENES.get(str(target), str(target))
    candidate = scene_path(name)
    if candidate.exists():
        return load_scene(candidate)
    raise InputError(f"{target}: not a scene file, packaged scene or model name "
                     f"(models: {', '.join(MODEL_SCENES)})")


#: gear_dyn sources the FMU never runs (the slim FMU leaves them out): the CLI, plots, the FMU
#: build and co-simulation side, file output, and the studies beyond a run's own checks
NOT_IN_FMU = ("cli/", "plots/", "fmu/build.py", "fmu/build3.py", "fmu/check.py",
              "fmu/cosim.py", "fmu/native.py", "io.py",
              "scene/packaged.py", "scene/sweep.py", "scenes/", "analysis/sweep/",
              "analysis/bench.py", "analysis/chart.py", "analysis/excitation.py",
              "analysis/report.py", "analysis/spectrum.py", "analysis/spectrum_labels.py",
              "analysis/stiffness.py")


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


_PATH_SETUP = f"""import sys

if getattr(sys, "gear_dyn_embedded", False):  # started by the boot library (a C host)
    import json as _json
    import os as _os

    _here = _os.path.dirname(_os.path.abspath(__file__))
    with open(_os.path.join(_here, "{PYTHON_FILE}"), encoding="utf-8") as _f:
        for _p in _json.load(_f)["path"]:  # the build interpreter's import path, as fallback
            if _p not in sys.path and _os.path.isdir(_p):
                sys.path.append(_p)

"""


def _script(package: str, class_name: str, spec: dict[str, Any]) -> str:
    return (
        f'"""gear_dyn FMU slave of scene {spec["scene_name"]!r} ({spec["model"]} model).\n\n'
        "Generated by `gear-dyn fmu build`; the physics is in the private gear_dyn copy "
        f"{package!r}.\n" + '"""\n\n' + _PATH_SETUP +
        "try:\n"
        "    import numpy  # noqa: F401\n"
        "    import scipy.integrate  # noqa: F401\n"
        f"    from {package}.fmu.slave import GearDynSlave\n"
        "except ImportError as _exc:  # pythonfmu shows the reason only with debug logging on\n"
        "    sys.stderr.write(f'gear_dyn FMU: cannot instantiate: Python package '\n"
        "                     f'{_exc.name or _exc!r} is missing in the Python at {sys.prefix} '\n"
        "                     '(the FMU needs numpy and scipy)\\n')\n"
        "    raise\n\n"
        "# pythonfmu's loader releases one reference to this module's dict per instantiation\n"
        "# that it never took; GearDynSlave.__init__ gives one back, these cover the gap\n"
        "_REFERENCES = [globals()] * 8\n\n\n"
        f"class {class_name}(GearDynSlave):\n"
        f'    """gear_dyn {spec["model"]} model as an FMI 2.0 co-simulation slave."""\n'
    )


def fmu_target(out: str | Path) -> Path:
    """``out`` as the FMU file to write: a ``.fmu`` name that is not a folder (InputError)."""
    out = Path(out)
    if out.suffix != ".fmu":
        raise InputError(f"--out {out}: an FMU file name must end in .fmu")
    if out.exists() and out.is_dir():
        raise InputError(f"--out {out}: is a folder, expected an .fmu file name")
    return out


def build_names(target: str | Path | Scene, tag: str) -> tuple[dict[str, Any], str, str, str]:
    """The FMU spec of ``target`` and the names of one build: (spec, package, slave module,
    slave class), each with a fresh token (every FMU loads its own private copy) and ``tag``
    for the FMI version ("" for 2, "3" for 3)."""
    scene = target if isinstance(target, Scene) else resolve_scene(target)
    spec = fmu_spec(scene)
    token = secrets.token_hex(5)
    kind = spec["model"]
    return (spec, f"gear_dyn_fmu_{token}", f"gear_dyn_slave{tag}_{kind}_{token}",
            f"GearDyn{tag}_{kind}_{token}")


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


def build_fmu(target: str | Path | Scene, out: str | Path, fmi: int = 2) -> BuiltFmu:
    """Build the FMU of a scene into ``out`` (a ``.fmu`` file, written whole or not at all).

    Parameters
    ----------
    target : str, Path or Scene
        Scene file, packaged scene name, model name (``sdof``, ``torsional``) or a Scene.
    out : str or Path
        FMU file to write (must end in ``.fmu``).
    fmi : int
        FMI version: 2 (pythonfmu) or 3 (pythonfmu3, :mod:`gear_dyn.fmu.build3`).

    Raises
    ------
    InputError
        Bad target or output name, invalid scene, pythonfmu without binaries for this platform,
        an FMI version other than 2 and 3, or pythonfmu3 missing for FMI 3.
    """
    if fmi not in (2, 3):
        raise InputError(f"--fmi {fmi}: valid FMI versions are 2 and 3")
    if fmi == 3:
        from gear_dyn.fmu.build3 import build_fmu3

        return build_fmu3(target, out)
    from pythonfmu import FmuBuilder

    out = fmu_target(out)
    if not FmuBuilder.has_binary():
        raise InputError("pythonfmu has no binary for this platform; install a pythonfmu wheel "
                         "that ships one")
    spec, package, module, class_name = build_names(target, "")
    out.parent.mkdir(parents=True, exist_ok=True)
    with staged_build(spec, package, module, _script(package, class_name, spec),
                      skip=("fmu/slave3.py",)) as (tmp, script, files):
        raw = tmp / "raw.fmu"
        FmuBuilder.build_FMU(script, dest=raw, project_files=files,
                             canGetAndSetFMUstate=True, canSerializeFMUstate=True)
        missing = unsupported_reason()
        data = _finish(raw.read_bytes(), spec, None if missing else class_name)
    write_bytes(out, data)
    return BuiltFmu(out, class_name, package, spec, missing)


# ---------------------------------------------------------------------- modelDescription
def _finish(fmu: bytes, spec: dict[str, Any], boot_id: str | None) -> bytes:
    """The FMU zip with units, initial unknowns and a version note in its modelDescription;
    with ``boot_id`` (the model identifier) the Linux binary also gets the boot library."""
    src = zipfile.ZipFile(io.BytesIO(fmu))
    xml = complete_model_description(src.read("modelDescription.xml"), spec)
    native: dict[str, bytes] = {}
    if boot_id is not None:
        so = f"binaries/linux64/{boot_id}.so"
        native = {f"binaries/linux64/{k}": v
                  for k, v in boot_binaries(src.read(so), boot_id).items()}
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as dst:
        for info in src.infolist():
            name = info.filename
            data = xml if name == "modelDescription.xml" else native.pop(name, None)
            dst.writestr(info, src.read(name) if data is None else data)
        for name, data in native.items():
            dst.writestr(name, data)
    return buf.getvalue()


def complete_model_description(xml: bytes, spec: dict[str, Any]) -> bytes:
    """Add UnitDefinitions, units and InitialUnknowns to pythonfmu's modelDescription.xml."""
    root = ET.fromstring(xml)
    from gear_dyn import __version__

    root.set("generationTool", f"gear_dyn {__version__} ({root.get('generationTool', '')})")
    by_name = {v["name"]: v for v in spec["variables"]}
    used: dict[str, str] = {}
    mv = root.find("ModelVariables")
    if mv is None:
        raise InputError("modelDescription.xml without ModelVariables")
    outputs: list[int] = []
    for index, sv in enumerate(mv.findall("ScalarVariable"), start=1):
        v = by_name.get(sv.get("name", ""))
        if v is None:
            continue
        if sv.get("causality") == "output":
            outputs.append(index)
        typed = next(iter(sv), None)
        if typed is not None and typed.tag in ("Real", "Integer"):
            for key in ("min", "max", "nominal"):
                if key in v and (key != "nominal" or typed.tag == "Real"):
                    typed.set(key, repr(v[key]))
        real = sv.find("Real")
        if real is not None and v.get("unit") in UNITS:
            fmi_name = UNITS[v["unit"]][0]
            real.set("unit", fmi_name)
            used[v["unit"]] = fmi_name
    _enumerations(root, mv, by_name)
    if used:
        defs = ET.Element("UnitDefinitions")
        for unit in sorted(used):
            name, base, display = UNITS[unit]
            u = ET.SubElement(defs, "Unit", {"name": name})
            ET.SubElement(u, "BaseUnit", {k: str(e) for k, e in base.items()})
            for dname, factor in display:
                ET.SubElement(u, "DisplayUnit", {"name": dname, "factor": repr(factor)})
        cs = root.find("CoSimulation")
        pos = list(root).index(cs) + 1 if cs is not None else 0
        root.insert(pos, defs)
    ms = root.find("ModelStructure")
    if ms is None:
        ms = ET.SubElement(root, "ModelStructure")
    # no direct feedthrough: outputs are computed from the state at doStep (and at
    # exitInitializationMode) only, so setting an input changes no output before the next step
    out_list = ms.find("Outputs")
    for unknown in [] if out_list is None else out_list.findall("Unknown"):
        unknown.set("dependencies", "")
    if outputs and ms.find("InitialUnknowns") is None:
        iu = ET.SubElement(ms, "InitialUnknowns")
        for index in outputs:
            ET.SubElement(iu, "Unknown", {"index": str(index)})
    ET.indent(root, space="  ")
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True)


def _enumerations(root: ET.Element, mv: ET.Element, by_name: dict[str, Any]) -> None:
    """Turn the Integer stand-ins of choice parameters into FMI Enumerations with their
    TypeDefinitions (item k = choice k), so a master offers the choices."""
    types = ET.Element("TypeDefinitions")
    for sv in mv.findall("ScalarVariable"):
        v = by_name.get(sv.get("name", ""))
        typed = next(iter(sv), None)
        if v is None or v["type"] != "Enumeration" or typed is None:
            continue
        type_name = f"{v['name']}.choices"
        typed.tag = "Enumeration"
        typed.set("declaredType", type_name)
        simple = ET.SubElement(types, "SimpleType", {"name": type_name})
        enum = ET.SubElement(simple, "Enumeration")
        for k, choice in enumerate(v["choices"], start=1):
            ET.SubElement(enum, "Item", {"name": choice, "value": str(k)})
    if len(types):
        anchor = root.find("CoSimulation")
        root.insert(list(root).index(anchor) + 1 if anchor is not None else 0, types)


def read_spec(fmu: str | Path) -> dict[str, Any]:
    """The gear_dyn spec (scene, variables, experiment) stored in an FMU built here.

    Raises
    ------
    InputError
        Not a readable FMU, or not one built by gear_dyn.
    """
    from gear_dyn.fmu.variables import check_spec

    p = Path(fmu)
    try:
        with zipfile.ZipFile(p) as z:
            text = z.read(f"resources/{SPEC_FILE}").decode("utf-8")
    except FileNotFoundError:
        raise InputError(f"{p}: FMU file not found") from None
    except (zipfile.BadZipFile, OSError):
        raise InputError(f"{p}: not a readable FMU (zip) file") from None
    except KeyError:
        raise InputError(f"{p}: not an FMU built by gear_dyn (no resources/{SPEC_FILE})") from None
    try:
        data = json.loads(text)
    except ValueError:
        raise InputError(f"{p}: resources/{SPEC_FILE} is not valid JSON") from None
    return check_spec(data)
