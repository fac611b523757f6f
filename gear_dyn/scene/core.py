"""The core scene tables: scene, gear, operating, inertia, stiffness, damping, backlash,
transmission_error, solver."""

from __future__ import annotations

import math

from gear_dyn.choices import STIFFNESS_METHODS
from gear_dyn.geometry import MAX_SPEED, MAX_TORQUE
from gear_dyn.scene.fields import REQUIRED, Field, Section
from gear_dyn.scene.registry import register_section
from gear_dyn.stiffness.weber import MODULI, current_modulus

DEG = math.pi / 180

SCENE = register_section(Section("scene", (
    Field("name", kind="str", default="", doc="case name"),
    Field("description", kind="str", default="", doc="free text"),
    Field("model", kind="str", default="sdof", choices=("sdof", "torsional"),
          doc="dynamic model: single-DOF mesh model or two-DOF torsional model"),
), optional=True, doc="what the case is and which model runs it"))

GEAR = register_section(Section("gear", (
    Field("teeth_pinion", kind="int", default=REQUIRED, low=5, high=10000, doc="z1"),
    Field("teeth_gear", kind="int", default=REQUIRED, low=5, high=10000, doc="z2"),
    Field("module", "m", default=REQUIRED, low=0.0, high=1.0, low_open=True,
          doc="normal module m_n"),
    Field("pressure_angle", "rad", default=20 * DEG, low=5 * DEG, high=45 * DEG,
          doc="normal pressure angle"),
    Field("helix_angle", "rad", default=0.0, low=-45 * DEG, high=45 * DEG,
          doc="pinion helix angle: 0 spur, > 0 right-hand, < 0 left-hand (the gear has the "
              "other hand; the geometry uses its magnitude)"),
    Field("face_width", "m", default=REQUIRED, low=0.0, high=10.0, low_open=True, doc="B"),
    Field("addendum_coef", default=1.0, low=0.5, high=1.5, doc="ha*"),
    Field("clearance_coef", default=0.25, low=0.0, high=0.5, doc="c*"),
    Field("profile_shift_pinion", default=0.0, low=-1.0, high=1.5, doc="x1"),
    Field("profile_shift_gear", default=0.0, low=-1.0, high=1.5, doc="x2"),
    Field("tip_diameter_pinion", "m", default=None, low=0.0, high=10.0, low_open=True,
          doc="pinion tip diameter d_a1 (default d1 + 2 m_n (ha* + x1 - k*)); above its base "
              "and root circles"),
    Field("tip_diameter_gear", "m", default=None, low=0.0, high=10.0, low_open=True,
          doc="gear tip diameter d_a2 (default d2 + 2 m_n (ha* + x2 - k*)); above its base and "
              "root circles"),
    Field("tip_shortening", default=0.0, low=0.0, high=1.5,
          doc="tip shortening coefficient k*: both tips cut by k* m_n (not with a tip "
              "diameter)"),
    Field("center_distance", "m", default=None, low=0.0, low_open=True,
          doc="operating centre distance a_w (default: zero-backlash)"),
    Field("center_distance_offset", "m", default=0.0, low=-1.0, high=1.0,
          doc="shaft offset added to the centre distance (as in Jiang et al. 2018)"),
    Field("youngs_modulus", "Pa", default=206e9, low=1e6, high=1e13, doc="E (both gears)"),
    Field("poisson", default=0.3, low=0.0, high=0.5, high_open=True, doc="nu (both gears)"),
    Field("density", "kg/m**3", default=7850.0, low=0.0, high=1e5, low_open=True,
          doc="density (both gears)"),
), optional=False, doc="the involute gear pair"))

OPERATING = register_section(Section("operating", (
    Field("speed", "rad/s", default=REQUIRED, low=0.0, high=MAX_SPEED, low_open=True,
          doc="pinion (input) speed"),
    Field("torque", "N*m", default=REQUIRED, low=0.0, high=MAX_TORQUE,
          doc="pinion (input) torque T1"),
), optional=False, doc="operating point"))

INERTIA = register_section(Section("inertia", (
    Field("pinion", "kg*m**2", default=REQUIRED, low=0.0, high=1e6, low_open=True, doc="I1"),
    Field("gear", "kg*m**2", default=REQUIRED, low=0.0, high=1e6, low_open=True, doc="I2"),
), doc="polar inertias; without this table, solid blanks of width B at the pitch radii"))

STIFFNESS = register_section(Section("stiffness", (
    Field("method", kind="str", default=None,
          choices=STIFFNESS_METHODS,
          doc="how k(t) is computed (default: contact_line for a helical pair, iso6336 for a "
              "spur pair)"),
    Field("single", "N/m", default=None, low=0.0, high=1e13, low_open=True,
          doc="single-pair stiffness (rectangular method)"),
    Field("double", "N/m", default=None, low=0.0, high=1e13, low_open=True,
          doc="double-pair stiffness (rectangular method)"),
    Field("fourier_terms", kind="int", default=None, low=1, high=200,
          doc="truncate k(t) to this many Fourier harmonics (Jiang et al. 2018 use 5)"),
    # options of the geometric methods (gear_dyn.stiffness.build_stiffness; docs/stiffness.md)
    Field("samples_per_cycle", kind="int", default=None, low=4, high=100_000,
          doc="potential_energy/weber: samples per mesh cycle (default 200)"),
    Field("face_slices", kind="int", default=None, low=1, high=10_000,
          doc="potential_energy/weber, helical pairs: discrete face slices (default: "
              "continuous slicing)"),
    Field("fillet_radius_coef", default=None, low=0.0, high=1.0,
          doc="basic-rack tip rounding rho_fP/m_n (default c*/(1 - sin a_n))"),
    Field("bore_radius_pinion", "m", default=None, low=0.0, low_open=True,
          doc="pinion bore radius for the fillet-foundation term (default r_f/2)"),
    Field("bore_radius_gear", "m", default=None, low=0.0, low_open=True,
          doc="gear bore radius for the fillet-foundation term (default r_f/2)"),
    Field("plane_strain", kind="bool", default=None,
          doc="potential_energy/weber: E/(1-nu^2) in the tooth terms (default false)"),
    Field("weber_slices", kind="int", default=None, low=1, high=10_000,
          doc="weber: slices per tooth (default 20)"),
    Field("weber_modulus", kind="str", default=None, choices=MODULI,
          doc="weber: modulus in the tooth terms (default jiang2018: Jiang et al. 2018, eq. 11; "
              "its old name seed still works, with a warning)", renamed=current_modulus),
    Field("weber_foundation", kind="bool", default=None,
          doc="weber: add the Sainsot et al. (2004) fillet-foundation term (default false, as "
              "Jiang et al. 2018)"),
    Field("per_length", "N/m**2", default=None, low=0.0, low_open=True,
          doc="contact_line: stiffness per unit contact-line length (default from ISO)"),
), doc="mesh stiffness; default contact-line length k_l L(t) for a helical pair, ISO 6336 "
        "rectangular wave for a spur pair, both with the ISO 6336-1 mean c_gamma b"))

DAMPING = register_section(Section("damping", (
    Field("ratio", default=0.06, low=0.0, high=10.0, doc="mesh damping ratio xi"),
), doc="c_m = 2 xi sqrt(m_e k_m)"))

BACKLASH = register_section(Section("backlash", (
    Field("half_gap", "m", default=REQUIRED, low=0.0, high=0.01, low_open=True,
          doc="half of the backlash b_g along the line of action"),
), doc="dead-zone backlash (present = enabled)"))

TRANSMISSION_ERROR = register_section(Section("transmission_error", (
    Field("cos", "m", kind="floatlist", default=REQUIRED,
          doc="cosine amplitudes of mesh harmonics 1..N"),
    Field("sin", "m", kind="floatlist", default=None, doc="sine amplitudes (default zeros)"),
), doc="static transmission error e(t) as mesh harmonics (present = enabled)"))

SOLVER = register_section(Section("solver", (
    Field("method", kind="str", default="auto",
          choices=("auto", "exact", "RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA",
                   "periodic"),  # periodic last: FMU enumeration items keep their numbers
          doc="integration method"),
    Field("rtol", default=1e-8, low=1e-13, high=1e-2, doc="relative tolerance"),
    Field("atol", default=None, low=0.0, low_open=True,
          doc="absolute tolerance (default rtol x state scale)"),
    Field("periods", kind="int", default=200, low=2, high=10_000_000,
          doc="mesh periods simulated"),
    Field("steady_periods", kind="int", default=None, low=1, high=10_000_000,
          doc="last mesh periods taken as steady state (default: half)"),
    Field("samples_per_period", kind="int", default=64, low=4, high=4096,
          doc="output samples per mesh period"),
), doc="integration settings"))
