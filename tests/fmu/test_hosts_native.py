"""The native gear FMUs (C kernel, no Python) of every packaged scene in every host of
gear_dyn.fmu.hosts: fmpy validate, fmutool -check, libcosimpy (FMI 2), ecospy, the C hosts
with an empty environment (binary needs libc and libm only, no libpython in the process), and
rebuilt from the FMU's own sources with a plain `cc`.

The hosts run the same binary; they differ only in how they form the communication times
(t_k = k h or a running sum), which moves an output by far less than the FMU's stated error
(1e-9 of the static deflection where the pieces are exact): the hosts must agree with fmpy to
1e-9 of each output's largest magnitude. Skipped, with the reason, where no C compiler or a
host is installed. The eccentric torsional scene's FMU is larger than the
500 KB size target (3.2 MB) and runs in every host all the same.
"""

from __future__ import annotations

import subprocess
import zipfile
from pathlib import Path

import host_runners as runners
import numpy as np
import pytest

from gear_dyn.fmu import hosts
from gear_dyn.fmu.toolchain import fmi_headers, linux_compiler

pytestmark = pytest.mark.fmu

SCENES = sorted((Path(__file__).resolve().parents[2] / "examples" / "scenes").glob("*.toml"))
AGREE = 1e-9  # of each output's largest magnitude (module docstring)
N = 64


def _native_build():
    if linux_compiler() is None:
        pytest.skip("no C compiler (cc, gcc or clang): a native FMU cannot be built here")
    from gear_dyn.fmu.export_fmu import build_native_fmu

    return build_native_fmu


@pytest.fixture(scope="module", params=[(s, fmi) for s in SCENES for fmi in (2, 3)],
                ids=lambda p: f"{p[0].stem}-fmi{p[1]}")
def native(request: pytest.FixtureRequest,
           tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[str], float]:
    scene, fmi = request.param
    build = _native_build()
    out = tmp_path_factory.mktemp("native") / f"{scene.stem}{fmi}.fmu"
    built = build(scene, out, fmi=fmi)  # every packaged scene has a native FMU
    facts = hosts.describe(built.path)
    step = round(float(facts.step or 1e-5) * 1e9) * 1e-9  # whole nanoseconds, for libcosim
    return built.path, facts.outputs, step


def _agree(rows: np.ndarray, ref: np.ndarray) -> None:
    scale = np.max(np.abs(ref[:, 1:]), axis=0) + 1e-300
    np.testing.assert_allclose(rows[:, 0], ref[:, 0], rtol=1e-12, atol=0)
    worst = np.max(np.abs(rows[:, 1:] - ref[:, 1:]) / scale)
    assert worst <= AGREE, worst


@pytest.fixture(scope="module")
def reference(native: tuple[Path, list[str], float]) -> np.ndarray:
    fmu, names, step = native
    return hosts.fmpy_rows(fmu, names, step, N)


def test_native_validates_and_passes_fmutool(native: tuple[Path, list[str], float]) -> None:
    from fmpy.validation import validate_fmu

    fmu, _, _ = native
    assert validate_fmu(str(fmu)) == []
    try:
        ok, text = runners.fmutool_check(fmu)
    except hosts.HostMissing as exc:
        pytest.skip(str(exc))
    assert ok, text


def test_native_fmpy_simulate_and_stop_time(native: tuple[Path, list[str], float],
                                            reference: np.ndarray) -> None:
    fmu, names, step = native
    assert np.all(np.isfinite(reference))
    _agree(runners.fmpy_simulate_rows(fmu, names, step, N), reference)
    _agree(hosts.fmpy_rows(fmu, names, step, N, stop=N * step), reference)


def test_native_in_libcosimpy(native: tuple[Path, list[str], float],
                              reference: np.ndarray) -> None:
    fmu, names, step = native
    if hosts.describe(fmu).fmi != 2:
        pytest.skip("libcosim runs FMI 1 and 2 FMUs only")
    try:
        rows = runners.libcosimpy_rows(fmu, names, step, N)
    except hosts.HostMissing as exc:
        pytest.skip(str(exc))
    _agree(rows, reference[1:])


def test_native_in_ecospy(native: tuple[Path, list[str], float],
                          reference: np.ndarray) -> None:
    fmu, names, step = native
    try:
        rows = runners.ecospy_rows(fmu, names, step, N)
    except hosts.HostMissing as exc:
        pytest.skip(str(exc))
    _agree(rows, reference)


def test_native_in_c_host_without_python(native: tuple[Path, list[str], float],
                                         reference: np.ndarray, tmp_path: Path) -> None:
    fmu, names, step = native
    facts = hosts.describe(fmu)
    run = hosts.c_host_rows(fmu, names, step, N)
    assert run.returncode == 0, run.stderr
    _agree(run.rows, reference)
    assert not [m for m in run.mapped if "python" in Path(m).name.lower()], run.mapped
    binary = f"{hosts.LINUX_DIR[facts.fmi]}/{facts.model_identifier}.so"
    others = [m for m in run.mapped if not m.endswith(binary)]
    assert runners.foreign_libraries(others) == [], others
    with zipfile.ZipFile(fmu) as z:
        so = Path(z.extract(f"binaries/{binary}", tmp_path))
    assert runners.foreign_libraries(runners.binary_libraries(so)) == []


def test_native_rebuilt_from_its_sources(native: tuple[Path, list[str], float],
                                         tmp_path: Path) -> None:
    """The shipped sources compiled by a plain `cc -shared -fPIC ... -lm` give the shipped
    binary's outputs (to the hosts' agreement: another compiler's flags may contract
    differently)."""
    fmu, names, step = native
    facts = hosts.describe(fmu)
    with zipfile.ZipFile(fmu) as z:
        z.extractall(tmp_path / "u")
    src = tmp_path / "u" / "sources"
    lib = tmp_path / "u" / "binaries" / hosts.LINUX_DIR[facts.fmi] / f"{facts.model_identifier}.so"
    lib.unlink()
    cc = linux_compiler()
    assert cc is not None
    proc = subprocess.run([cc, "-shared", "-fPIC", f"-I{fmi_headers(facts.fmi)}", f"-I{src}",
                           *map(str, sorted(src.rglob("*.c"))), "-o", str(lib), "-lm"],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    rebuilt = tmp_path / "rebuilt.fmu"
    with zipfile.ZipFile(rebuilt, "w") as z:
        for f in (tmp_path / "u").rglob("*"):
            if f.is_file():
                z.write(f, f.relative_to(tmp_path / "u").as_posix())
    shipped = hosts.c_host_rows(fmu, names, step, N)
    again = hosts.c_host_rows(rebuilt, names, step, N)
    assert again.returncode == 0, again.stderr
    _agree(again.rows, shipped.rows)
