"""The example scenes shipped inside the package (``gear_dyn/scenes/*.toml``), found by name.

``load_scene("helicopter_tail")`` and ``gear-dyn run helicopter_tail`` work from any folder: a
name that is not an existing file is looked up here. :data:`STARTER_SCENE` is the commented
scene that ``gear-dyn init`` writes.
"""

from __future__ import annotations

import difflib
import tomllib
from pathlib import Path

from gear_dyn.errors import SceneError

#: folder of the packaged scenes
SCENES_DIR = Path(__file__).resolve().parent.parent / "scenes"


def scene_path(name: str) -> Path:
    """Path of a scene shipped with the package (gear_dyn/scenes/NAME.toml)."""
    return SCENES_DIR / f"{name}.toml"


def packaged_names() -> list[str]:
    """Names of the packaged scenes, sorted."""
    return sorted(p.stem for p in SCENES_DIR.glob("*.toml"))


def packaged_scenes() -> list[tuple[str, str]]:
    """(name, description) of every packaged scene (the ``[scene] description`` line)."""
    tables = {name: tomllib.loads(scene_path(name).read_text(encoding="utf-8"))
              for name in packaged_names()}
    return [(name, str(t.get("scene", {}).get("description", ""))) for name, t in tables.items()]


def resolve_scene(target: str | Path) -> Path:
    """The file of ``target``: an existing path, else the packaged scene of that name.

    ``"helicopter_tail"`` and ``"helicopter_tail.toml"`` both find the packaged scene when no
    such file exists in the current folder.

    Raises
    ------
    SceneError
        Neither a file nor a packaged scene (the message lists the packaged names, with a
        did-you-mean).
    """
    p = Path(target)
    if p.exists():
        return p
    name = p.name[:-5] if p.name.endswith(".toml") else p.name
    if p.parent == Path(".") and name in packaged_names():
        return scene_path(name)
    names = packaged_names()
    hint = difflib.get_close_matches(name, names, n=1)
    mean = f"; did you mean {hint[0]!r}?" if hint else ""
    raise SceneError(f"{p}: scene file not found, and no packaged scene of that name{mean} "
                     f"(packaged scenes: {', '.join(names)}; see gear-dyn scenes)")


#: the commented starter scene written by ``gear-dyn init`` (loads and runs as it is)
STARTER_SCENE = '''\
# gear_dyn scene: one TOML table per part of the model. Every dimensional value carries its unit
# ("3 mm", "1500 rpm", "20 deg", "120 Nm"); a plain number there is refused. Dimensionless values
# (teeth, coefficients, ratios, tolerances) are plain numbers.
# Reference of every table and key: docs/scenes.md, or `gear-dyn scene keys [TABLE]`.
# Run it:  gear-dyn run {name} --out out     (plots, timeseries.csv, summary.json in ./out)

[scene]
name = "{stem}"
description = "my gear pair (starter scene written by gear-dyn init)"
model = "sdof"              # "sdof": single-DOF mesh model; "torsional": two-DOF torsional

[gear]                      # the involute pair (pinion = driver)
teeth_pinion = 20
teeth_gear = 40
module = "3 mm"             # normal module
pressure_angle = "20 deg"
helix_angle = "0 deg"       # 0 = spur; negative = left-hand pinion
face_width = "30 mm"
# profile_shift_pinion = 0.0
# profile_shift_gear = 0.0
# youngs_modulus = "206 GPa"
# density = "7850 kg/m^3"

[operating]
speed = "1500 rpm"          # pinion speed
torque = "120 Nm"           # pinion torque (Nm = newton-metre)

# [stiffness]               # left out, the toolkit chooses the mesh stiffness that fits:
#                           #   no [tip_relief]: iso6336 for a spur pair (rectangular wave,
#                           #   ISO 6336-1 method B), contact_line for a helical pair (k_l L(t))
#                           #   with [tip_relief]: the loaded contact of tip_relief.pair_stiffness
#                           #   (potential_energy unless set); a [stiffness] table there must name
#                           #   that same method
# method = "iso6336"        # or rectangular, potential_energy, weber, contact_line
#                           # to compare a relief with no relief like for like, give the pair
#                           # without relief method = "potential_energy" (the relief's baseline)

# [tip_relief]              # tip relief: single-DOF on the loaded contact (docs/modification.md)
# rule = "wang2024"         # or handbook, dudley, niemann, custom
# pair_stiffness = "potential_energy"

[damping]
ratio = 0.06                # mesh damping ratio xi

# [inertia]                 # default: solid blanks of width B at the pitch radii
# pinion = "0.01 kg*m^2"
# gear = "0.1 kg*m^2"

# [backlash]                # dead-zone backlash: the teeth may separate
# half_gap = "50 um"

# [iso]                     # ISO 6336-1 method B K_v printed beside the simulated dynamic factor
# accuracy_grade = 6        # ISO 1328-1 grade (default 5, stated as assumed), or explicit:
# f_pb = "8 um"             #   base pitch deviation
# f_falpha = "7 um"         #   profile form deviation
# running_in = "case_hardened"   # none (default), case_hardened, through_hardened
# sigma_hlim = "1500 MPa"

[solver]
method = "auto"             # exact propagator for linear models, else LSODA
rtol = 1e-8
periods = 200               # mesh periods simulated
'''
