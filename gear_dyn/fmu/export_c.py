"""The native FMU's C side: the generated ``model_data.c`` and the compiler call.

The kernel (``gear_dyn/solvers/kernel/``) and the FMI glue (``gear_dyn/fmu/native/``) are fixed
sources; only ``model_data.c`` (const arrays and constants, written here from a
:class:`~gear_dyn.fmu.export.NativeModel`) changes from one FMU to the next.
"""

from __future__ import annotations

import re
import subprocess
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from gear_dyn.errors import InputError, SolverError
from gear_dyn.fmu.export import NativeModel
from gear_dyn.fmu.export_torsional import TorsionalNative
from gear_dyn.fmu.toolchain import linux_compiler
from gear_dyn.solvers.kernel import SOURCE_DIR

#: the fixed C sources (package data): the FMI glue here, the kernel where the solvers live
NATIVE_DIR = Path(__file__).parent / "native"
KERNEL_DIR = SOURCE_DIR
KERNEL_SOURCES = ("gd_kernel.c", "gd_torsional.c")
#: the FMI glue of each version and what both share (status rules, FMU state checks, the
#: drivetrain interface)
GLUE_SOURCES = {2: ("gd_glue.c", "gd_drive.c", "gd_fmi2.c"),
                3: ("gd_glue.c", "gd_drive.c", "gd_fmi3.c")}
HEADERS = ("gd_kernel.h",)
GLUE_HEADERS = ("gd_glue.h", "gd_drive.h")
_HEADER = (KERNEL_DIR / "gd_kernel.h").read_text("utf-8")
#: the table format the kernel reads (GD_TABLE_FORMAT in gd_kernel.h)
TABLE_FORMAT = int(re.search(r"#define GD_TABLE_FORMAT (\d+)", _HEADER)[1])  # type: ignore[index]
#: the kernel's version (GD_KERNEL_VERSION in gd_kernel.h)
KERNEL_VERSION = re.search(r'#define GD_KERNEL_VERSION "([^"]+)"', _HEADER)[1]  # type: ignore[index]
CFLAGS = ("-std=c99", "-O2", "-fPIC", "-Wall", "-Wextra", "-Werror", "-pedantic")


@dataclass(frozen=True)
class Param:
    """One parameter or input of the native FMU (value reference = position + 1)."""

    name: str
    unit: str
    low: float
    high: float
    low_open: bool
    causality: str
    description: str


#: the kernel's parameters and inputs, in the order of GD_SPEED .. GD_TOL (gd_kernel.h)
PARAMS = (
    Param("operating.speed", "rad/s", 0.0, 1e5, True, "input", "pinion speed"),
    Param("operating.torque", "N.m", 0.0, 1e8, False, "input", "pinion torque T1 (W = T1/r_b1)"),
    Param("damping.ratio", "1", 0.0, 10.0, False, "parameter",
          "mesh damping ratio xi, c = 2 xi sqrt(m_e k_m)"),
    Param("backlash.half_gap", "m", 0.0, 0.1, True, "parameter",
          "backlash half gap along the line of action"),
    Param("solver.tolerance", "1", 1e-14, 1e-3, False, "parameter",
          "relative tolerance of the Runge-Kutta pieces (closed-form pieces are exact)"),
)
#: outputs, value references 6..11 (GD_X .. GD_DRIVEN)
OUTPUTS = (
    ("state.x", "m", "state: dynamic transmission error"),
    ("state.v", "m/s", "state: rate of the dynamic transmission error"),
    ("dte", "m", "dynamic transmission error r_b1 th1 - r_b2 th2 along the line of action"),
    ("mesh_force", "N", "dynamic mesh force along the line of action"),
    ("stiffness", "N/m", "mesh stiffness k(t)"),
    ("driven_speed", "rad/s", "speed of the driven gear"),
)


#: outputs of the torsional model, value references 6..18 (GT_Q1 .. GT_TF2)
TORSIONAL_OUTPUTS = (
    ("state.q1", "rad", "state: pinion vibration angle th1 - w1 t"),
    ("state.q2", "rad", "state: gear vibration angle th2 - w1 t z1 / z2"),
    ("state.q1_dot", "rad/s", "state: rate of q1"),
    ("state.q2_dot", "rad/s", "state: rate of q2"),
    ("dte", "m", "dynamic transmission error r_b1 q1 - r_b2 q2 along the line of action"),
    ("delta", "m", "mesh deflection dte + e_ecc"),
    ("mesh_force", "N", "dynamic mesh force along the line of action"),
    ("stiffness", "N/m", "mesh stiffness k(t)"),
    ("w1", "rad/s", "pinion speed"),
    ("w2", "rad/s", "gear speed"),
    ("e_ecc", "m", "eccentric kinematic transmission error (0 without eccentricity)"),
    ("friction_torque_pinion", "N.m", "friction torque on the pinion (0 without friction)"),
    ("friction_torque_gear", "N.m", "friction torque on the gear (0 without friction)"),
)


def outputs_of(nm: NativeModel | TorsionalNative) -> tuple[tuple[str, str, str], ...]:
    """The outputs (name, unit, description) of a native model, in value-reference order."""
    return TORSIONAL_OUTPUTS if isinstance(nm, TorsionalNative) else OUTPUTS


def direct_feedthrough(nm: NativeModel | TorsionalNative) -> dict[str, tuple[str, ...]]:
    """The inputs each output depends on at the same instant (FMI ``dependencies``).

    The kernel computes every output from the state and the current parameters and inputs
    (``gd_outputs``): the gear speed adds the nominal rotation of the speed input, and where the
    table has a transmission-error rate de/dp the mesh damping force holds ``f_m de/dp`` with
    ``f_m = z1 w1 / (2 pi)``, so the force (and the friction torques, proportional to it) moves
    with the speed input at once. The torque input acts through the state only (from the next
    doStep). Outputs not in the mapping depend on no input.
    """
    speed: tuple[str, ...] = ("operating.speed",)
    if not isinstance(nm, TorsionalNative):
        rate = bool(np.any(nm.table.coef[:, 2] != 0.0))
        return {"driven_speed": speed, **({"mesh_force": speed} if rate else {})}
    out = {"w1": speed, "w2": speed}
    if nm.table.has_rate:
        out["mesh_force"] = speed
        if nm.table.has_friction:
            out |= {"friction_torque_pinion": speed, "friction_torque_gear": speed}
    return out


def start_values(nm: NativeModel | TorsionalNative) -> tuple[float, ...]:
    """Start values of :data:`PARAMS` (a model without backlash carries a placeholder gap)."""
    return (nm.speed, nm.torque, nm.damping_ratio,
            nm.half_gap if nm.half_gap is not None else 1e-5, nm.tolerance)


def _arr(values: np.ndarray) -> str:
    """A C initialiser (shortest round-trip repr of each double; C has no empty arrays: an
    empty ``values`` gives one unread 0.0)."""
    items = [repr(float(v)) if np.isfinite(v) else "0.0" for v in np.ravel(values)] or ["0.0"]
    lines = [", ".join(items[i:i + 4]) for i in range(0, len(items), 4)]
    return "{\n    " + ",\n    ".join(lines) + "\n}"


def _lines_c(nm: TorsionalNative) -> tuple[str, str]:
    """The contact-line form's block of ``model_data.c`` (gd_lines) and its pointer, or no block
    and a null pointer."""
    g = nm.table.lines
    if g is None:
        return "", "0"
    lay = g.layout
    mu = -1.0 if g.friction is None else float(g.friction)
    k, q = np.nonzero(np.any(g.fourier != 0.0, axis=2))  # by rising k, then quantity
    n = max(k.size, 1)
    block = f"""static const unsigned short term_k[{n}] = {{{", ".join(map(str, k)) or "0"}}};
static const unsigned char term_q[{n}] = {{{", ".join(map(str, q)) or "0"}}};
static const double term_ab[{2 * n}] = {_arr(g.fourier[k, q])};
static const gd_lines lines = {{
    {k.size}, {float(g.period)!r}, term_k, term_q, term_ab,
    {lay.pitch!r}, {lay.width!r}, {lay.sin_bb!r}, {lay.face_width!r}, {lay.l_ac0!r},
    {int(lay.index[0])}, {int(lay.index.size)}, {g.per_length!r}, {mu!r}
}};
"""
    return block, "&lines"


#: the pinion-speed interface: no drivetrain constants (gd_drive.h)
_NO_DRIVE = """struct gd_drive;
const struct gd_drive *const gd_drive_data = 0;"""


def model_data_c(nm: NativeModel | TorsionalNative, title: str = "", token: str = "",
                 drive: str = "") -> str:
    """The text of ``model_data.c`` for a native model.

    ``token`` is the FMU's instantiation token (FMI 2 guid), as in its modelDescription: the
    glue refuses to instantiate with another, and a state that carries another. ``drive``: the
    drivetrain interface's block (:func:`gear_dyn.fmu.export_drive.drive_c`), or "" for the
    pinion-speed interface.

    Raises
    ------
    InputError
        A non-finite value in the table.
    """
    t = nm.table
    if not (np.all(np.isfinite(t.coef)) and np.all(np.isfinite(t.breaks))):
        raise InputError("native FMU table: non-finite coefficients")
    if not re.fullmatch(r"[{}\w-]{0,47}", token):
        raise InputError(f"native FMU token {token!r}: valid tokens are up to 47 characters "
                         "of letters, digits, '-', '{' and '}'")
    start = ", ".join(repr(float(v)) for v in start_values(nm))
    params = ",\n    ".join(
        f'{{"{p.name}", "{p.unit}", {p.low!r}, {p.high!r}, {int(p.low_open)}}}' for p in PARAMS)
    if isinstance(nm, TorsionalNative):  # no flat pieces, TE or backlash; the gd_tors block
        flat, te, gap, phase0, tors = "0", 0, 0, 0.0, "&tors"
        load = -1.0 if nm.load_torque is None else nm.load_torque
        scale = ", ".join(repr(float(v)) for v in nm.q_scale)
        lines, lines_ptr = _lines_c(nm)
        extra = f"""{lines}static const gd_tors tors = {{
    {{{nm.inertias[0]!r}, {nm.inertias[1]!r}}}, {float(nm.z2)!r},
    {{{nm.mean_arms[0]!r}, {nm.mean_arms[1]!r}}}, {load!r}, {{{scale}}}, {lines_ptr}
}};
"""
    else:
        flat = ", ".join(str(int(f)) for f in nm.table.flat)
        te, gap = int(nm.transmission_error), int(nm.half_gap is not None)
        phase0, tors, extra = nm.phase0, "NULL", ""
    n = t.breaks.size - 1
    return f"""/* Generated by gear_dyn ({title}): the model's tables and constants. Do not edit. */
#include "gd_kernel.h"

/* the instantiation token (FMI 2 guid) of the modelDescription (gd_glue.h) */
const char gd_instantiation_token[] = "{token}";
{drive or _NO_DRIVE}
static const double breaks[{t.breaks.size}] = {_arr(t.breaks)};
static const double coef[{max(t.coef.size, 1)}] = {_arr(t.coef)};
static const unsigned char flat[{n}] = {{{flat}}};
static const gd_param params[GD_NPAR] = {{
    {params}
}};
{extra}
const gd_model gd_model_data = {{
    {TABLE_FORMAT}, {n}, {t.degree}, {te}, {gap},
    breaks, coef, flat, params,
    {{{start}}},
    {nm.mass!r}, {nm.mean_stiffness!r}, {nm.rb1!r}, {nm.rb2!r}, {float(nm.z1)!r},
    {phase0!r}, {nm.x_scale!r}, {tors}
}};
"""


def compile_shared(sources: list[Path], out: Path, extra: tuple[str, ...] = ()) -> Path:
    """Compile C sources into a shared library ``out`` linked against libm only.

    Raises
    ------
    InputError
        No C compiler.
    SolverError
        The compiler failed (its message is quoted).
    """
    cc = linux_compiler()
    if cc is None:
        raise InputError("native FMU: no C compiler found; install a C compiler (gcc or clang, "
                         "e.g. 'apt-get install gcc') and put it on PATH or name it in CC, or "
                         "build with --backend python")
    cmd = [cc, *CFLAGS, *extra, "-shared", f"-I{KERNEL_DIR}",
           *(str(s) for s in sources), "-o", str(out), "-lm"]
    proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        raise SolverError(f"native FMU: the C compiler failed ({' '.join(cmd)}):\n"
                          f"{proc.stderr.strip()}")
    return out
