"""``gear-dyn fmu build SCENE --out FILE.fmu`` and ``gear-dyn fmu validate FILE.fmu``."""

from __future__ import annotations

import argparse
from collections import Counter
from pathlib import Path
from typing import Any

from gear_dyn.cli.progress import Stages, add_quiet_flag


def register(sub: Any) -> None:
    p = sub.add_parser(
        "fmu", help="export a scene as an FMI 2.0 (or 3.0) co-simulation FMU, or check one",
        description="Build an FMI 2.0 (pythonfmu) or 3.0 (pythonfmu3, --fmi 3) co-simulation "
        "FMU that carries gear_dyn and "
        "the scene inside it, or validate an FMU with fmpy. See docs/fmu.md.",
    )
    fsub = p.add_subparsers(dest="fmu_command", metavar="ACTION")
    fsub.required = True
    b = fsub.add_parser(
        "build", help="build the FMU of a scene",
        description="Build FILE.fmu from SCENE: a scene file, a packaged scene name "
        "(helicopter_tail, eccentric_helical, ...) or a model name (sdof, torsional). By "
        "default a native FMU (compiled C, needs no Python on the importing side; "
        "docs/native_fmu.md); a torsional scene with backlash or TE, or --backend python, the "
        "pythonfmu FMU (needs Python with numpy and scipy on the importing side).",
    )
    b.add_argument("scene", help="scene file (TOML), packaged scene name or model name")
    b.add_argument("--out", type=Path, required=True, help="FMU file to write (.fmu)")
    b.add_argument("--fmi", type=int, default=2, choices=(2, 3),
                   help="FMI version: 2 (default) or 3 (the pythonfmu backend needs pythonfmu3: "
                   "pip install 'gear_dyn[fmi3]')")
    b.add_argument("--backend", default=None, choices=("native", "python"),
                   help="native (the default, FMI 2 and 3): C kernel compiled now, needs no "
                   "Python on the importing machine; python: the pythonfmu FMU, every scene "
                   "key a parameter (the default, with a note, where no native FMU can be "
                   "built: a torsional model with backlash or TE)")
    b.add_argument("--ports", default="speed", choices=("speed", "torque", "shaft-speed"),
                   help="native FMU interface: speed (default: speed and torque inputs on the "
                   "pinion), torque (the drivetrain interface: a torque input on each shaft, "
                   "the shafts' angles and speeds out) or shaft-speed (its variant with the "
                   "pinion driven by speed, its torque out; docs/fmu.md)")
    b.add_argument("--no-validate", action="store_true",
                   help="skip the fmpy validation of the built FMU")
    add_quiet_flag(b)
    b.set_defaults(func=run_build)
    v = fsub.add_parser("validate", help="validate an FMU's modelDescription with fmpy",
                        description="Run fmpy's validation (schema, variable names, "
                        "start values, causality/variability, units, model structure).")
    v.add_argument("fmu", type=Path, help="FMU file")
    v.set_defaults(func=run_validate)
    c = fsub.add_parser(
        "check", help="check an FMU built by gear_dyn: validation, fmpy, C host, stop time",
        description="Validate FILE.fmu (FMI 2 or 3) with fmpy, run it in fmpy and in a plain C "
        "host "
        "(compiled with the system compiler, loading the binary RTLD_LOCAL in an empty "
        "environment), and check that its outputs do not depend on the announced stop time. "
        "Exit code 0 when every check passes, 3 when one fails.")
    c.add_argument("fmu", type=Path, help="FMU file built by gear-dyn fmu build")
    c.add_argument("--steps", type=int, default=64,
                   help="communication steps of the DefaultExperiment step size (default 64)")
    add_quiet_flag(c)
    c.set_defaults(func=run_check)


def _problems(path: Path) -> list[str]:
    from fmpy.validation import validate_fmu

    from gear_dyn.errors import InputError

    if not path.is_file():
        raise InputError(f"{path}: FMU file not found")
    import zipfile

    if not zipfile.is_zipfile(path):
        raise InputError(f"{path}: not an FMU (an FMU is a zip archive)")
    try:
        return list(validate_fmu(str(path)))
    except (zipfile.BadZipFile, KeyError, OSError) as exc:  # broken archive, no description
        raise InputError(f"{path}: not a readable FMU ({exc.__class__.__name__}: {exc})") from None


def _validate(path: Path, quiet: bool) -> None:
    """fmpy's validation of a built FMU: one line, or SolverError naming the problems."""
    from gear_dyn.errors import SolverError

    with Stages(["validate (fmpy)"], quiet):
        problems = _problems(path)
    if problems:
        raise SolverError(f"{path}: fmpy validation found {len(problems)} problem(s): "
                          + "; ".join(problems))
    print("fmpy validation: no problems")


def run_build(args: argparse.Namespace) -> int:
    from gear_dyn.fmu.build import build_fmu

    if args.ports != "speed" and args.backend == "python":
        from gear_dyn.errors import InputError

        raise InputError(f"--ports {args.ports}: the drivetrain interface is native only "
                         "(leave out --backend python)")
    if args.backend != "python":
        from gear_dyn.fmu.export import NotNativeError

        try:
            return _run_build_native(args)
        except NotNativeError as exc:
            if args.backend == "native" or args.ports != "speed":  # no pythonfmu fallback
                raise
            print(f"backend: python (pythonfmu), because {exc.reason}")
    with Stages(["build FMU"], args.quiet):
        built = build_fmu(args.scene, args.out, fmi=args.fmi)
    n = Counter(v["causality"] for v in built.spec["variables"])
    print(f"{built.spec['scene_name']}: {built.spec['model']} model -> {built.path} "
          f"(FMI {args.fmi}.0 co-simulation) (model identifier {built.model_identifier}; "
          f"{n['parameter']} parameters, {n['input']} inputs, {n['output']} outputs)")
    print("hosts: Python hosts (fmpy) on this machine's Python; for other hosts build the "
          "native FMU (docs/fmu.md)")
    if not args.no_validate:
        _validate(built.path, args.quiet)
    return 0


def _run_build_native(args: argparse.Namespace) -> int:
    from gear_dyn.fmu.export_fmu import build_native_fmu

    with Stages(["build native FMU"], args.quiet):
        built = build_native_fmu(args.scene, args.out, fmi=args.fmi, ports=args.ports)
    t = built.model.table
    kind = "native FMU" if built.drive is None else f"native drivetrain FMU ({args.ports} ports)"
    print(f"{built.scene_name}: {kind} -> {built.path} (FMI {args.fmi}.0 co-simulation, "
          f"model identifier {built.model_identifier}; {t.breaks.size - 1} table pieces, "
          f"{'exact' if t.exact else 'fitted'}; {built.path.stat().st_size // 1000} kB)")
    if not args.no_validate:
        _validate(built.path, args.quiet)
    return 0


def run_validate(args: argparse.Namespace) -> int:
    import sys

    problems = _problems(args.fmu)
    if problems:
        for p in problems:
            print(p, file=sys.stderr)
        print(f"{args.fmu}: {len(problems)} problem(s)", file=sys.stderr)
        return 3
    print(f"{args.fmu}: fmpy validation found no problems")
    return 0


def run_check(args: argparse.Namespace) -> int:
    from gear_dyn.errors import InputError
    from gear_dyn.fmu.check import check_fmu, verdict

    if not args.fmu.is_file():
        raise InputError(f"{args.fmu}: FMU file not found")
    if not 1 <= args.steps <= 100000:
        raise InputError(f"--steps {args.steps}: valid range 1 <= steps <= 100000")
    with Stages(["check FMU"], args.quiet):
        lines = check_fmu(args.fmu, n_steps=args.steps)
    print(f"gear-dyn fmu check {args.fmu}")
    for line in lines:
        mark = {True: "PASS", False: "FAIL", None: "SKIP"}[line.ok]
        print(f"  {mark}  {line.name:<24} {line.detail}")
    ok = verdict(lines)
    skipped = sum(line.ok is None for line in lines)
    print(f"verdict: {'PASS' if ok else 'FAIL'}" + (f" ({skipped} check(s) could not run here)"
                                                    if skipped else ""))
    return 0 if ok else 3
