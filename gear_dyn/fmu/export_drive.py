"""The drivetrain interface of the native FMU (``gear-dyn fmu build SCENE --ports torque``).

The FMU is the two-DOF torsional mesh between two shafts (``gear_dyn/fmu/native/gd_drive.c``):
a torque input on each shaft, the angle and speed of each shaft out, with the mesh force and
the DTE, so that it sits between two compliant shaft FMUs. It steps the same tables as the
pinion-speed interface (the single-DOF model's k, e, de/dp over a mesh cycle; the torsional
model's e_ecc, de/dp, k, phi1, phi2 over its table period), with the mesh phase following the
pinion angle. The base radii and the ratio are calculated parameters (fixed at build); the
inertias, the damping ratio, the backlash and the tolerance are parameters.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from gear_dyn.fmu.export import NativeModel
from gear_dyn.fmu.export_c import Param
from gear_dyn.fmu.export_torsional import TorsionalNative

#: the ``--ports`` choices: the pinion-speed interface (speed and torque on the pinion), the
#: drivetrain one (a torque port on each shaft) and its speed-driven variant (the pinion shaft
#: driven by speed: speed in, torque out; a torque port on the gear)
PORTS = ("speed", "torque", "shaft-speed")

#: parameters and inputs, in the order of GV_T1 .. GV_W0 (gd_drive.h): value references 1..8
DRIVE_PARAMS = (
    Param("pinion.torque", "N.m", -1e8, 1e8, False, "input",
          "torque on the pinion shaft, positive in its sense of rotation"),
    Param("gear.torque", "N.m", -1e8, 1e8, False, "input",
          "torque on the gear shaft, positive in its sense of rotation (a load is negative)"),
    Param("damping.ratio", "1", 0.0, 10.0, False, "parameter",
          "mesh damping ratio xi, c = 2 xi sqrt(m_e k_m), m_e = I1 I2 / (I1 r_b2^2 + I2 r_b1^2)"),
    Param("backlash.half_gap", "m", 0.0, 0.1, True, "parameter",
          "backlash half gap along the line of action"),
    Param("solver.tolerance", "1", 1e-14, 1e-3, False, "parameter",
          "tolerance of the Runge-Kutta steps, relative to the state scales of the static "
          "deflection"),
    Param("inertia.pinion", "kg.m2", 0.0, 1e6, True, "parameter", "polar inertia I1 of the pinion"),
    Param("inertia.gear", "kg.m2", 0.0, 1e6, True, "parameter", "polar inertia I2 of the gear"),
    Param("pinion.speed_start", "rad/s", -1e5, 1e5, False, "parameter",
          "pinion speed at the start (the gear at z1/z2 of it, the mesh at its static "
          "deflection under pinion.torque)"),
)
#: outputs, value references 9..14 (GV_A1 .. GV_DTE)
DRIVE_OUTPUTS = (
    ("pinion.angle", "rad", "pinion angle th1"),
    ("pinion.speed", "rad/s", "pinion speed w1"),
    ("gear.angle", "rad", "gear angle th2"),
    ("gear.speed", "rad/s", "gear speed w2"),
    ("mesh_force", "N", "dynamic mesh force F along the line of action (on the gear: r_b2 F, "
     "on the pinion: -r_b1 F)"),
    ("dte", "m", "dynamic transmission error r_b1 th1 - r_b2 th2 along the line of action"),
)
#: the speed-driven variant's pinion port: value reference 1 is its speed input, 10 the torque
#: its shaft delivers (in place of pinion.torque and pinion.speed)
SPEED_INPUT = Param("pinion.speed", "rad/s", -1e5, 1e5, False, "input",
                    "pinion speed: the pinion turns at it (held over a step)")
TORQUE_OUTPUT = ("pinion.torque", "N.m",
                 "torque the pinion shaft delivers to turn the pinion at its speed: "
                 "r_b1 F - max(F, 0) phi1 (like the mesh force, it depends directly on "
                 "pinion.speed, through the mesh damping)")


def drive_variables(speed_in: bool) -> tuple[tuple[Param, ...], tuple[tuple[str, str, str], ...]]:
    """The parameters and inputs (value references 1..8) and the outputs (9..14) of the
    drivetrain interface, or of its speed-driven variant."""
    if not speed_in:
        return DRIVE_PARAMS, DRIVE_OUTPUTS
    return ((SPEED_INPUT, *DRIVE_PARAMS[1:]),
            (DRIVE_OUTPUTS[0], TORQUE_OUTPUT, *DRIVE_OUTPUTS[2:]))


#: calculated parameters (fixed at build), value references 15..17
DRIVE_CONSTANTS = (
    ("base_radius.pinion", "m", "base radius r_b1 of the pinion (fixed at build)"),
    ("base_radius.gear", "m", "base radius r_b2 of the gear (fixed at build)"),
    ("ratio", "1", "gear ratio z2/z1 = r_b2/r_b1 (fixed at build)"),
)


@dataclass(frozen=True)
class DriveSpec:
    """What the drivetrain interface adds to a native model: start values of
    :data:`DRIVE_PARAMS` and the C constants."""

    start: tuple[float, ...]
    speed_in: bool
    nq: int
    idx: tuple[int, int, int, int, int]
    sign_e: float
    period: float
    q_scale: tuple[float, float, float, float]

    def values(self) -> dict[str, float]:
        """The start value of each parameter and input, by name."""
        params = drive_variables(self.speed_in)[0]
        return {p.name: v for p, v in zip(params, self.start, strict=True)}


def drive_spec(nm: NativeModel | TorsionalNative, inertias: tuple[float, float],
               speed_in: bool = False) -> DriveSpec:
    """The drivetrain interface of native model ``nm`` with polar inertias (kg m^2), or with
    ``speed_in`` its speed-driven variant.

    Start values: the build torque on the pinion (speed-driven: the build speed), the gear
    loaded by the balancing torque -T1 z2/z1 (steady rotation at the build speed), the build
    speed.
    """
    i1, i2 = (float(v) for v in inertias)
    rb1, rb2 = nm.rb1, nm.rb2
    tors = isinstance(nm, TorsionalNative)
    gap = 1e-5 if tors or nm.half_gap is None else nm.half_gap
    start = (nm.speed if speed_in else nm.torque, -nm.torque * rb2 / rb1, nm.damping_ratio,
             gap, nm.tolerance, i1, i2, nm.speed)
    m_e = i1 * i2 / (i1 * rb2 ** 2 + i2 * rb1 ** 2)
    w_n = math.sqrt(nm.mean_stiffness / m_e)
    x = nm.x_scale
    scale = (x / rb1, x / rb2, x / rb1 * w_n, x / rb2 * w_n)
    if isinstance(nm, TorsionalNative):  # [e, de/dp, k, phi1, phi2]
        return DriveSpec(start, speed_in, 5, (0, 1, 2, 3, 4), 1.0, float(nm.table.period),
                         scale)
    return DriveSpec(start, speed_in, 3, (1, 2, 0, -1, -1), -1.0, 1.0, scale)  # [k, e, de/dp]


def drive_c(spec: DriveSpec) -> str:
    """The drivetrain block of ``model_data.c``: its parameters and the ``gd_drive`` struct."""
    params = ",\n    ".join(
        f'{{"{p.name}", "{p.unit}", {p.low!r}, {p.high!r}, {int(p.low_open)}}}'
        for p in drive_variables(spec.speed_in)[0])
    start = ", ".join(repr(float(v)) for v in spec.start)
    idx = ", ".join(str(i) for i in spec.idx)
    scale = ", ".join(repr(float(v)) for v in spec.q_scale)
    return f"""/* the drivetrain interface (gd_drive.h) */
#include "gd_drive.h"
static const gd_param drive_params[GV_NPAR] = {{
    {params}
}};
static const gd_drive drive = {{
    {int(spec.speed_in)}, {spec.nq}, {{{idx}}}, {spec.sign_e!r}, {spec.period!r}, drive_params,
    {{{start}}},
    {{{scale}}}
}};
const gd_drive *const gd_drive_data = &drive;"""
