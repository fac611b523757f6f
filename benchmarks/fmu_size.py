"""Sizes of the native FMUs, member by member (what the zip holds, deflated).

Run:  python benchmarks/fmu_size.py [--record]

Builds the native FMI 2 FMU of every packaged scene without a size limit: a summary of the
FMU's file size against the 500 KB target (``gear_dyn.fmu.export_fmu.MAX_SIZE``) and of its
binaries' lengths (linked with ``-s``: stripped), then, for each scene, each member of the zip:
its length and its deflated size (what counts in the file). Only the binaries this machine can
compile are in the FMUs (the x86_64 Linux one always; the Windows one where MinGW-w64 is
installed).

Writes ``fmu_size.md`` into ``benchmarks/out/``; ``--record`` into ``benchmarks/results/``.
"""

from __future__ import annotations

import argparse
import tempfile
import zipfile
from pathlib import Path

from gear_dyn.fmu.export_fmu import MAX_SIZE, build_native_fmu
from gear_dyn.fmu.toolchain import windows_compiler
from gear_dyn.scene.packaged import resolve_scene

HERE = Path(__file__).resolve().parent
SCENES = tuple(p.stem for p in sorted(resolve_scene("helicopter_tail").parent.glob("*.toml")))


def member_rows(path: Path) -> list[tuple[str, int, int]]:
    """(name, length, deflated size) in bytes of each member of the zip ``path``."""
    with zipfile.ZipFile(path) as z:
        return [(i.filename, i.file_size, i.compress_size) for i in z.infolist()]


def report() -> str:
    """The markdown report: one table per scene and the file sizes against the target."""
    mingw = windows_compiler()
    out = ["# Native FMUs: size by member", "",
           "Command: `python benchmarks/fmu_size.py --record` (FMI 2, built without a size "
           "limit; the binaries this machine compiles: x86_64 Linux"
           + (", x86_64 Windows with MinGW-w64)." if mingw else "; no MinGW-w64 here)."), "",
           "| scene | FMU | within 500 KB | Linux .so (stripped) | Windows .dll (stripped) |",
           "|---|---:|---|---:|---:|"]
    details: list[str] = []
    with tempfile.TemporaryDirectory() as tmp:
        for scene in SCENES:
            built = build_native_fmu(scene, Path(tmp) / f"{scene}.fmu", max_size=None)
            size = built.path.stat().st_size
            rows = member_rows(built.path)
            lib = {ext: next((n for name, n, _ in rows if name.endswith(ext)), None)
                   for ext in (".so", ".dll")}
            cells = [f"{n / 1000:.1f} KB" if n is not None else "-" for n in lib.values()]
            out.append(f"| {scene} | {size / 1000:.0f} KB | "
                       f"{'yes' if size <= MAX_SIZE else 'no'} | {cells[0]} | {cells[1]} |")
            verdict = "within" if size <= MAX_SIZE else "over"
            details += [f"## {scene}: {size / 1000:.0f} KB ({verdict} the {MAX_SIZE // 1000} KB "
                        "target)", "", "| member | length | deflated |", "|---|---:|---:|"]
            details += [f"| {name} | {n / 1000:.1f} KB | {c / 1000:.1f} KB |"
                        for name, n, c in rows]
            details.append("")
    return "\n".join([*out, "", *details])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--record", action="store_true", help="write into benchmarks/results/")
    args = ap.parse_args()
    text = report()
    dest = HERE / ("results" if args.record else "out")
    dest.mkdir(exist_ok=True)
    (dest / "fmu_size.md").write_text(text + "\n")
    print(text)


if __name__ == "__main__":
    main()
