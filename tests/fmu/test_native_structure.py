"""What the native FMU declares about itself, checked against what it does: the dependencies in
ModelStructure (FMI 2 ``<Outputs><Unknown dependencies>``, FMI 3 ``<Output dependencies>``)
against the outputs that move when an input is changed without a step; the shipped binaries
stripped; the glibc symbol versions the Linux binary needs against the minimum docs/fmu.md
states."""

from __future__ import annotations

import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import pytest
from native_harness import Slave

pytestmark = [pytest.mark.fmu,
              pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc) on PATH")]
fmpy = pytest.importorskip("fmpy")

#: a scene without transmission error (the force does not see the speed at once), one with
#: (tip relief: de/dp in the damping force), the torsional model
BUILDS = [("helicopter_tail", 2), ("helicopter_tail_relief", 2), ("helicopter_tail_relief", 3),
          ("eccentric_helical_ideal", 2), ("eccentric_helical_ideal", 3)]
INPUTS = ("operating.speed", "operating.torque")
DOCS = Path(__file__).resolve().parents[2] / "docs" / "fmu.md"


@pytest.fixture(scope="module")
def fmus(tmp_path_factory: pytest.TempPathFactory) -> dict[tuple[str, int], Path]:
    from gear_dyn.fmu.export_fmu import build_native_fmu

    d = tmp_path_factory.mktemp("structure")
    return {(s, fmi): build_native_fmu(s, d / f"{s}{fmi}.fmu", fmi=fmi).path
            for s, fmi in BUILDS}


def _declared(path: Path) -> dict[str, set[str]]:
    """Each input's dependent outputs, from the modelDescription."""
    md = fmpy.read_model_description(str(path))
    out: dict[str, set[str]] = {name: set() for name in INPUTS}
    assert len(md.outputs) == sum(v.causality == "output" for v in md.modelVariables)
    for unknown in md.outputs:
        assert unknown.dependencies is not None  # declared, even where empty
        for dep in unknown.dependencies:
            out[dep.name].add(unknown.variable.name)
    return out


@pytest.mark.parametrize(("scene", "fmi"), BUILDS)
def test_dependencies_are_the_outputs_an_input_moves(fmus, scene: str, fmi: int) -> None:
    """Mid-run, each input is changed by 1 % without a step: exactly the outputs declared to
    depend on it change (bitwise comparison); set back, every output is as before."""
    path = fmus[scene, fmi]
    declared = _declared(path)
    run = Slave(path, fmi)
    outputs = [v.name for v in fmpy.read_model_description(str(path)).modelVariables
               if v.causality == "output"]
    run.start(None)
    run.steps(1.7e-5, 7)
    before = {o: run.get(o) for o in outputs}
    for name in INPUTS:
        value = run.get(name)
        run.set(name, 1.01 * value)
        moved = {o for o in outputs if run.get(o) != before[o]}
        run.set(name, value)
        assert moved == declared[name], f"{scene} FMI {fmi}, {name}"
        assert {o: run.get(o) for o in outputs} == before
    if scene == "helicopter_tail_relief":  # the damping force sees de/dp: a true dependency
        assert "mesh_force" in declared["operating.speed"]
    run.close()


def test_shipped_binaries_are_stripped_and_glibc_is_as_documented(fmus) -> None:
    """No symbol table in the Linux binary (``strip -s``: only the dynamic symbols are left)
    and, where MinGW-w64 built one, in the Windows DLL; the highest GLIBC_ version the Linux
    binary asks for (objdump -T) is the minimum docs/fmu.md states."""
    objdump = shutil.which("objdump")
    if objdump is None:
        pytest.skip("no objdump (binutils)")
    stated = re.search(r"needs glibc (\d+\.\d+) or newer", DOCS.read_text())
    assert stated, "docs/fmu.md states no minimum glibc"
    for path in fmus.values():
        with zipfile.ZipFile(path) as z:
            for name in z.namelist():
                if not name.startswith("binaries/") or name.endswith("/"):
                    continue
                lib = path.parent / Path(name).name
                lib.write_bytes(z.read(name))
                syms = subprocess.run([objdump, "-t", str(lib)], capture_output=True,
                                      text=True, check=True).stdout
                assert "no symbols" in syms or "SYMBOL TABLE:\n\n" in syms + "\n", name
                if name.endswith(".so"):
                    dyn = subprocess.run([objdump, "-T", str(lib)], capture_output=True,
                                         text=True, check=True).stdout
                    versions = {tuple(map(int, v.split("."))) for v in
                                re.findall(r"GLIBC_(\d+\.\d+(?:\.\d+)?)", dyn)}
                    need = ".".join(map(str, max(versions)[:2]))
                    assert need == stated[1], f"{name}: needs GLIBC_{need}"
