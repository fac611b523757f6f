"""Build and validate the FMUs of the packaged example scenes (the documented entry point of fmu/).

Usage: python fmu/build_packaged_fmus.py [OUTDIR]      (default OUTDIR: ./fmus)

Writes OUTDIR/helicopter_tail.fmu (the helicopter tail drive of Jiang et al. 2018, single-DOF
model) and OUTDIR/eccentric_helical.fmu (the eccentric helical pair of Liu et al. 2017, torsional
model with friction), each checked with fmpy's validator. The same as
``gear-dyn fmu build SCENE --out FILE.fmu`` per scene.
"""

from __future__ import annotations

import sys
from pathlib import Path

from fmpy.validation import validate_fmu

from gear_dyn.fmu.build import build_fmu

#: the packaged scenes built here, one per model kind
SCENES = ("helicopter_tail", "eccentric_helical")


def main(argv: list[str]) -> int:
    out = Path(argv[0]) if argv else Path("fmus")
    status = 0
    for name in SCENES:
        built = build_fmu(name, out / f"{name}.fmu")
        problems = validate_fmu(str(built.path))
        print(f"{built.path}: {built.spec['model']} model, identifier {built.model_identifier}, "
              f"fmpy validation: {'; '.join(problems) if problems else 'no problems'}")
        status |= bool(problems)
    return status


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
