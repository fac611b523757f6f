"""Involute gear pair geometry.

All quantities are SI: metres, radians, pascals, kilograms. Subscript 1 is the pinion (driver),
2 the gear (driven). Helical pairs are described in the transverse plane with the normal module
``m_n`` and helix angle ``beta``. The sign of ``beta`` is the hand of the pinion's helix
(positive right-hand, negative left-hand; the gear of an external pair has the other hand); the
geometry uses ``|beta|``, as a mirrored pair meshes the same (the hand only sets the direction of
the axial force, which no model here carries).

Formulas (ISO 21771 / any gear text; Liu et al. 2017, eqs. 14, 28, 29, with its typo corrected):

- ``tan a_t = tan a_n / cos b``; ``tan b_b = tan b cos a_t`` (Liu et al. 2017, eq. 29 prints
  ``sin b_b = tan b cos a_t``: a typo, not implemented)
- ``r = m_n z / (2 cos b)``, ``r_b = r cos a_t``, ``r_a = r + m_n (ha* + x - k*)`` (k* the tip
  shortening coefficient, default 0; or ``r_a = d_a / 2`` from a given tip diameter),
  ``r_f = r - m_n (ha* + c* - x)``
- reference centre distance ``a = r1 + r2``; operating ``cos a_wt = a cos a_t / a_w``; the default
  operating centre distance is the zero-backlash one from
  ``inv a_wt = inv a_t + 2 tan a_n (x1 + x2) / (z1 + z2)``
- ``p_bt = pi m_n cos a_t / cos b``, ``g_a = sqrt(r_a1^2 - r_b1^2) + sqrt(r_a2^2 - r_b2^2)
  - a_w sin a_wt``, ``eps_a = g_a / p_bt``, ``eps_b = B tan b_b / p_bt``
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

from gear_dyn.errors import InputError, check_range

#: smallest non-zero helix angle in rad (0.0057 deg); a smaller one is a spur pair in all but
#: rounding, and the helical contact-line formulas underflow
MIN_HELIX_ANGLE = 1e-4


def involute(alpha: float) -> float:
    """Involute function ``inv(a) = tan a - a`` (a in rad)."""
    return math.tan(alpha) - alpha


def inverse_involute(value: float) -> float:
    """Pressure angle (rad) whose involute function equals ``value`` (Newton iteration)."""
    if value < 0:
        raise InputError(f"involute value = {value:.6g} must be >= 0")
    a = (3.0 * value) ** (1.0 / 3.0)  # small-angle start: inv a ~ a^3/3
    for _ in range(60):
        f = math.tan(a) - a - value
        d = math.tan(a) ** 2
        if d == 0.0:
            break
        step = f / d
        a -= step
        if abs(step) < 1e-15:
            break
    return a


@dataclass(frozen=True)
class GearPair:
    """An external involute gear pair (spur or helical), validated at construction.

    Parameters
    ----------
    z1, z2 : int
        Teeth of pinion (driver) and gear (driven), >= 5.
    module : float
        Normal module m_n in m, 0 < m_n <= 1.
    pressure_angle : float
        Normal pressure angle a_n in rad, 5..45 deg.
    face_width : float
        Face width B in m, > 0.
    helix_angle : float
        Helix angle b of the pinion in rad, -45 .. 45 deg: 0 spur, > 0 right-hand, < 0
        left-hand (the gear has the other hand). The geometry uses ``|b|`` (:attr:`hand` keeps
        the sign).
    addendum_coef, clearance_coef : float
        ha* (default 1.0) and c* (default 0.25), dimensionless.
    x1, x2 : float
        Profile-shift coefficients, dimensionless, -1..1.5.
    center_distance : float or None
        Operating centre distance a_w in m; None gives the zero-backlash value.
    youngs_modulus1, youngs_modulus2 : float
        Young's moduli in Pa (default 206 GPa steel).
    poisson1, poisson2 : float
        Poisson's ratios (default 0.3).
    density1, density2 : float
        Densities in kg/m^3 (default 7850), used for solid-blank inertias.
    tip_diameter1, tip_diameter2 : float or None
        Tip diameters d_a in m of pinion and gear (None: ``d + 2 m_n (ha* + x - k*)``). A
        given tip must lie above the base and root circles (``d_a > max(d_b, d_f)``); the
        pointed-tip, clearance and contact-ratio checks then apply to it.
    tip_shortening : float
        Tip shortening coefficient k* >= 0 (dimensionless, default 0): both tips are cut by
        ``k* m_n`` (ISO 21771's tip alteration, as a reduction). Not combined with a given tip
        diameter.

    Raises
    ------
    InputError
        Non-positive sizes, a contact ratio below 1, an undercut pinion or gear, involute
        interference, a pointed tip, negative tip clearance, a centre distance too short, a tip
        diameter at or below the base or root circle.

    Attributes
    ----------
    r1, r2, rb1, rb2 : float
        Reference (pitch) and base radii of pinion and gear in m.
    contact_ratio, overlap_ratio, total_contact_ratio : float
        eps_a, eps_b and eps_a + eps_b, dimensionless.
    backlash : float
        Theoretical backlash along the line of action in m (zero at the zero-backlash a_w).

    See Also
    --------
    :func:`~gear_dyn.geometry.mesh_frequency` : The mesh frequency of the pair at a pinion speed.
    :func:`~gear_dyn.models.sdof.sdof_from_pair`
        The single-DOF model of the pair at an operating point.
    :func:`~gear_dyn.stiffness.select.build_stiffness` : Its mesh stiffness by any method.

    Examples
    --------
    >>> import math
    >>> pair = GearPair(19, 48, 3.2e-3, math.radians(20), 16e-3)
    >>> round(pair.r1 * 1e3, 2)  # pinion pitch radius in mm
    30.4
    >>> round(pair.total_contact_ratio, 3)
    1.646
    >>> GearPair(3, 48, 3.2e-3, math.radians(20), 16e-3)
    Traceback (most recent call last):
    ...
    gear_dyn.errors.InputError: z1 = 3 ...
    """

    z1: int
    z2: int
    module: float
    pressure_angle: float
    face_width: float
    helix_angle: float = 0.0
    addendum_coef: float = 1.0
    clearance_coef: float = 0.25
    x1: float = 0.0
    x2: float = 0.0
    center_distance: float | None = None
    youngs_modulus1: float = 206e9
    youngs_modulus2: float = 206e9
    poisson1: float = 0.3
    poisson2: float = 0.3
    density1: float = 7850.0
    density2: float = 7850.0
    tip_diameter1: float | None = None
    tip_diameter2: float | None = None
    tip_shortening: float = 0.0

    def __post_init__(self) -> None:
        for name in ("z1", "z2"):
            z = getattr(self, name)
            if (isinstance(z, bool) or not isinstance(z, int | float) or not math.isfinite(z)
                    or z != int(z)):
                raise InputError(f"{name} = {z!r}: teeth must be a whole number >= 5")
            check_range(name, z, "teeth", low=5, high=100000)
            object.__setattr__(self, name, int(z))
        check_range("module", self.module, "m", low=0.0, high=1.0, low_open=True)
        check_range(
            "pressure_angle", self.pressure_angle, "rad", low=math.radians(5), high=math.radians(45)
        )
        check_range("face_width", self.face_width, "m", low=0.0, high=10.0, low_open=True)
        check_range("helix_angle", self.helix_angle, "rad", low=-math.radians(45),
                    high=math.radians(45))
        if 0.0 < abs(self.helix_angle) < MIN_HELIX_ANGLE:  # contact lines degenerate below this
            raise InputError(
                f"helix_angle = {self.helix_angle:.6g} rad: valid range 0 (spur) or "
                f"{MIN_HELIX_ANGLE:g} <= |x| <= {math.radians(45):.6g} rad"
            )
        check_range("addendum_coef", self.addendum_coef, "", low=0.5, high=1.5)
        check_range("clearance_coef", self.clearance_coef, "", low=0.0, high=0.5)
        check_range("x1", self.x1, "", low=-1.0, high=1.5)
        check_range("x2", self.x2, "", low=-1.0, high=1.5)
        for name in ("youngs_modulus1", "youngs_modulus2"):
            check_range(name, getattr(self, name), "Pa", low=1e6, high=1e13)
        for name in ("poisson1", "poisson2"):
            check_range(name, getattr(self, name), "", low=0.0, high=0.5, high_open=True)
        for name in ("density1", "density2"):
            check_range(name, getattr(self, name), "kg/m^3", low=0.0, high=1e5, low_open=True)
        self._check_tips()
        if self.center_distance is not None:
            check_range(
                "center_distance", self.center_distance, "m", low=self.rb1 + self.rb2,
                high=10 * (self.r1 + self.r2), low_open=True,
            )
        self._validate_meshing()

    # ------------------------------------------------------------------ basic radii
    # Derived values are cached on the instance (functools.cached_property; the pair is frozen,
    # so they never go stale): validation and a run read them hundreds of times.
    @cached_property
    def hand(self) -> str:
        """Hand of the pinion's helix: ``"right"`` (b > 0), ``"left"`` (b < 0) or ``"spur"``."""
        if self.helix_angle == 0.0:
            return "spur"
        return "right" if self.helix_angle > 0 else "left"

    @cached_property
    def beta(self) -> float:
        """Helix angle magnitude ``abs(b)`` in rad (the geometry's b; :attr:`hand` has the sign)."""
        return abs(self.helix_angle)

    @cached_property
    def alpha_t(self) -> float:
        """Transverse pressure angle a_t in rad."""
        return math.atan(math.tan(self.pressure_angle) / math.cos(self.beta))

    @cached_property
    def beta_b(self) -> float:
        """Base helix angle b_b in rad (tan b_b = tan abs(b) cos a_t), >= 0."""
        return math.atan(math.tan(self.beta) * math.cos(self.alpha_t))

    @cached_property
    def transverse_module(self) -> float:
        """Transverse module m_t = m_n / cos b in m."""
        return self.module / math.cos(self.beta)

    @cached_property
    def r1(self) -> float:
        """Pinion reference (pitch) radius in m."""
        return self.transverse_module * self.z1 / 2

    @cached_property
    def r2(self) -> float:
        """Gear reference (pitch) radius in m."""
        return self.transverse_module * self.z2 / 2

    @cached_property
    def rb1(self) -> float:
        """Pinion base radius in m."""
        return self.r1 * math.cos(self.alpha_t)

    @cached_property
    def rb2(self) -> float:
        """Gear base radius in m."""
        return self.r2 * math.cos(self.alpha_t)

    @cached_property
    def ra1(self) -> float:
        """Pinion tip radius in m (``d_a1 / 2`` if given, else ``r1 + m_n (ha* + x1 - k*)``)."""
        if self.tip_diameter1 is not None:
            return self.tip_diameter1 / 2
        return self.r1 + self.module * (self.addendum_coef + self.x1 - self.tip_shortening)

    @cached_property
    def ra2(self) -> float:
        """Gear tip radius in m (``d_a2 / 2`` if given, else ``r2 + m_n (ha* + x2 - k*)``)."""
        if self.tip_diameter2 is not None:
            return self.tip_diameter2 / 2
        return self.r2 + self.module * (self.addendum_coef + self.x2 - self.tip_shortening)

    @cached_property
    def rf1(self) -> float:
        """Pinion root radius in m."""
        return self.r1 - self.module * (self.addendum_coef + self.clearance_coef - self.x1)

    @cached_property
    def rf2(self) -> float:
        """Gear root radius in m."""
        return self.r2 - self.module * (self.addendum_coef + self.clearance_coef - self.x2)

    @cached_property
    def ratio(self) -> float:
        """Gear ratio u = z2 / z1."""
        return self.z2 / self.z1

    # ------------------------------------------------------------------ centre distance
    @cached_property
    def reference_center_distance(self) -> float:
        """Reference centre distance a = r1 + r2 in m."""
        return self.r1 + self.r2

    @cached_property
    def zero_backlash_center_distance(self) -> float:
        """Centre distance in m at which the shifted teeth mesh without backlash."""
        inv_w = involute(self.alpha_t) + 2 * math.tan(self.pressure_angle) * (self.x1 + self.x2) / (
            self.z1 + self.z2
        )
        a_wt = inverse_involute(inv_w)
        return self.reference_center_distance * math.cos(self.alpha_t) / math.cos(a_wt)

    @cached_property
    def a_w(self) -> float:
        """Operating centre distance in m."""
        if self.center_distance is not None:
            return self.center_distance
        return self.zero_backlash_center_distance

    @cached_property
    def alpha_wt(self) -> float:
        """Operating transverse pressure angle in rad."""
        return math.acos(self.reference_center_distance * math.cos(self.alpha_t) / self.a_w)

    @cached_property
    def rw1(self) -> float:
        """Pinion operating pitch radius in m."""
        return self.rb1 / math.cos(self.alpha_wt)

    @cached_property
    def rw2(self) -> float:
        """Gear operating pitch radius in m."""
        return self.rb2 / math.cos(self.alpha_wt)

    # ------------------------------------------------------------------ contact
    @cached_property
    def base_pitch(self) -> float:
        """Transverse base pitch p_bt in m."""
        return math.pi * self.module * math.cos(self.alpha_t) / math.cos(self.beta)

    @cached_property
    def line_of_action_length(self) -> float:
        """Distance T1T2 between the tangent points on the base circles, in m."""
        return self.a_w * math.sin(self.alpha_wt)

    @cached_property
    def tip_reach1(self) -> float:
        """Distance from T1 to the pinion tip circle along the line of action, in m."""
        return math.sqrt(self.ra1**2 - self.rb1**2)

    @cached_property
    def tip_reach2(self) -> float:
        """Distance from T2 to the gear tip circle along the line of action, in m."""
        return math.sqrt(self.ra2**2 - self.rb2**2)

    @cached_property
    def path_of_contact(self) -> float:
        """Length g_a of the path of contact (transverse) in m."""
        return self.tip_reach1 + self.tip_reach2 - self.line_of_action_length

    @cached_property
    def start_of_contact(self) -> float:
        """Distance from T1 to the start of contact A (gear tip meets pinion root), in m."""
        return self.line_of_action_length - self.tip_reach2

    @cached_property
    def end_of_contact(self) -> float:
        """Distance from T1 to the end of contact E (pinion tip), in m."""
        return self.tip_reach1

    @cached_property
    def pitch_point(self) -> float:
        """Distance from T1 to the operating pitch point C, in m."""
        return self.rb1 * math.tan(self.alpha_wt)

    @cached_property
    def contact_ratio(self) -> float:
        """Transverse contact ratio eps_a."""
        return self.path_of_contact / self.base_pitch

    @cached_property
    def overlap_ratio(self) -> float:
        """Overlap (face) contact ratio eps_b = B tan b_b / p_bt."""
        return self.face_width * math.tan(self.beta_b) / self.base_pitch

    @cached_property
    def total_contact_ratio(self) -> float:
        """Total contact ratio eps_g = eps_a + eps_b."""
        return self.contact_ratio + self.overlap_ratio

    # ------------------------------------------------------------------ thickness, backlash
    def tooth_thickness(self, gear: int, radius: float) -> float:
        """Transverse circular tooth thickness (arc) of gear 1 or 2 at ``radius`` in m.

        Parameters
        ----------
        gear : {1, 2}
            1 the pinion, 2 the gear.
        radius : float
            Radius in m at which the thickness is measured (at or above the base circle).

        Returns
        -------
        float
            Arc thickness in m.

        See Also
        --------
        :attr:`~gear_dyn.geometry.GearPair.backlash`
            The circumferential backlash, from these thicknesses.

        Examples
        --------
        >>> import math
        >>> pair = GearPair(19, 48, 3.2e-3, math.radians(20), 16e-3)
        >>> s = pair.tooth_thickness(1, pair.r1)  # half the pitch at x = 0
        >>> abs(s - math.pi * pair.module / 2) < 1e-15
        True
        """
        x, r, rb = (self.x1, self.r1, self.rb1) if gear == 1 else (self.x2, self.r2, self.rb2)
        s = self.transverse_module * (math.pi / 2 + 2 * x * math.tan(self.pressure_angle))
        a_y = math.acos(min(1.0, rb / radius))
        return 2 * radius * (s / (2 * r) + involute(self.alpha_t) - involute(a_y))

    @cached_property
    def backlash(self) -> float:
        """Theoretical backlash along the line of action in m (zero at the zero-backlash a_w).

        Teeth at nominal thickness (no thickness allowances); a larger operating centre distance
        opens it: ``j = (2 pi r_w1 / z1 - s_w1 - s_w2) cos a_wt``.
        """
        pw = 2 * math.pi * self.rw1 / self.z1
        jwt = pw - self.tooth_thickness(1, self.rw1) - self.tooth_thickness(2, self.rw2)
        return jwt * math.cos(self.alpha_wt)

    # ------------------------------------------------------------------ inertia
    def blank_inertias(self) -> tuple[float, float]:
        """Polar moments of inertia (kg m^2) of solid cylinders at the pitch radii, width B.

        Returns
        -------
        (float, float)
            I1, I2 in kg m^2: ``rho pi B r^4 / 2`` of pinion and gear.

        See Also
        --------
        :func:`~gear_dyn.models.sdof.sdof_from_pair` : Uses them where no inertias are given.

        Examples
        --------
        >>> import math
        >>> pair = GearPair(19, 48, 3.2e-3, math.radians(20), 16e-3)
        >>> i1, i2 = pair.blank_inertias()
        >>> round(i2 / i1, 6) == round((48 / 19) ** 4, 6)
        True
        """
        i1 = 0.5 * self.density1 * math.pi * self.face_width * self.r1**4
        i2 = 0.5 * self.density2 * math.pi * self.face_width * self.r2**4
        return i1, i2

    @cached_property
    def effective_youngs_modulus(self) -> float:
        """Plane-strain contact modulus E* = 1 / ((1-nu1^2)/E1 + (1-nu2^2)/E2) in Pa."""
        return 1.0 / (
            (1 - self.poisson1**2) / self.youngs_modulus1
            + (1 - self.poisson2**2) / self.youngs_modulus2
        )

    # ------------------------------------------------------------------ validation
    def _check_tips(self) -> None:
        """A given tip diameter or tip shortening: a number, and the tip above the base and
        root circles."""
        check_range("tip_shortening", self.tip_shortening, "", low=0.0, high=self.addendum_coef)
        given = [n for n in ("tip_diameter1", "tip_diameter2") if getattr(self, n) is not None]
        if given and self.tip_shortening != 0.0:
            raise InputError(f"tip_shortening = {self.tip_shortening:g} with {given[0]}: give "
                             "tip diameters or the tip shortening, not both")
        for name in given:
            gear = 1 if name == "tip_diameter1" else 2
            rb, rf = (self.rb1, self.rf1) if gear == 1 else (self.rb2, self.rf2)
            d = check_range(name, getattr(self, name), "m", low=0.0, high=10.0, low_open=True)
            floor = 2 * max(rb, rf)
            if d <= floor:
                circle = "base" if rb >= rf else "root"
                raise InputError(
                    f"{name} = {d * 1e3:.6g} mm: the tip must lie above the {circle} circle "
                    f"(d_b{gear} = {2 * rb * 1e3:.6g} mm, d_f{gear} = {2 * rf * 1e3:.6g} mm); "
                    f"valid range > {floor * 1e3:.6g} mm"
                )
        for gear in (1, 2):  # a shortened tip must stay above the base and root circles too
            ra, rb, rf = ((self.ra1, self.rb1, self.rf1) if gear == 1
                          else (self.ra2, self.rb2, self.rf2))
            if self.tip_shortening and ra <= max(rb, rf):
                raise InputError(
                    f"tip_shortening = {self.tip_shortening:g}: the "
                    f"{'pinion' if gear == 1 else 'gear'} tip (d_a{gear} = {2 * ra * 1e3:.6g} "
                    f"mm) falls to the base or root circle ({2 * max(rb, rf) * 1e3:.6g} mm)"
                )

    def _validate_meshing(self) -> None:
        for gear, z, x, r in ((1, self.z1, self.x1, self.r1), (2, self.z2, self.x2, self.r2)):
            limit = r * math.sin(self.alpha_t) ** 2
            need = (self.addendum_coef - x) * self.module
            if limit < need * (1 - 1e-9):
                zmin = 2 * (self.addendum_coef - x) * math.cos(self.beta) / math.sin(
                    self.alpha_t
                ) ** 2
                raise InputError(
                    f"z{gear} = {z}: the {'pinion' if gear == 1 else 'gear'} is undercut by the "
                    f"generating rack (needs z{gear} >= {zmin:.2f} at x{gear} = {x:g}, or a "
                    f"profile shift x{gear} >= {self.addendum_coef - limit / self.module:.3f})"
                )
            ra = self.ra1 if gear == 1 else self.ra2
            sa = self.tooth_thickness(gear, ra)
            if sa <= 0.0:
                raise InputError(
                    f"x{gear} = {x:g}: tip of {'pinion' if gear == 1 else 'gear'} is pointed "
                    f"(tip thickness {sa * 1e3:.3g} mm <= 0); reduce x{gear} or addendum_coef"
                )
        gap1 = self.a_w - self.ra1 - self.rf2
        gap2 = self.a_w - self.ra2 - self.rf1
        if min(gap1, gap2) < 0.0:
            raise InputError(
                f"center_distance = {self.a_w * 1e3:.6g} mm: negative tip clearance "
                f"({min(gap1, gap2) * 1e3:.3g} mm); valid range >= "
                f"{(self.a_w - min(gap1, gap2)) * 1e3:.6g} mm"
            )
        if max(self.tip_reach1, self.tip_reach2) > self.line_of_action_length:
            raise InputError(
                f"z1 = {self.z1}, z2 = {self.z2}: involute interference (a tip reaches past the "
                "mating base-circle tangent point); add positive profile shift to the pinion"
            )
        if self.contact_ratio < 1.0:
            raise InputError(
                f"contact_ratio = {self.contact_ratio:.4f}: the pair does not mesh continuously "
                "(transverse contact ratio must be >= 1); check center_distance and addendum_coef"
            )
        if self.backlash < -1e-12 * self.module:
            raise InputError(
                f"center_distance = {self.a_w * 1e3:.6g} mm: teeth overlap (backlash "
                f"{self.backlash * 1e6:.3g} um < 0); valid range >= "
                f"{self.zero_backlash_center_distance * 1e3:.6g} mm"
            )


def mesh_frequency(pair: GearPair, speed1: float) -> float:
    """Mesh frequency f_m = z1 n1 / 60 in Hz for pinion speed ``speed1`` in rad/s.

    Parameters
    ----------
    pair : GearPair
        The gear pair (its pinion teeth z1 count).
    speed1 : float
        Pinion speed w1 in rad/s.

    Returns
    -------
    float
        f_m = z1 w1 / (2 pi) in Hz.

    See Also
    --------
    :func:`~gear_dyn.geometry.output_speed` : The driven gear's speed.
    :class:`~gear_dyn.geometry.GearPair` : The pair.

    Examples
    --------
    >>> import math
    >>> pair = GearPair(19, 48, 3.2e-3, math.radians(20), 16e-3)
    >>> round(mesh_frequency(pair, 1000 * 2 * math.pi / 60), 6)  # 19 teeth at 1000 rpm, Hz
    316.666667
    """
    return teeth_mesh_frequency(pair.z1, speed1)


#: the largest pinion speed anywhere (rad/s; about 955000 rpm): the one speed range, checked by
#: :func:`check_speed`
MAX_SPEED = 1e5
#: the largest pinion torque anywhere (N m), checked by :func:`check_torque`
MAX_TORQUE = 1e8


def check_speed(speed: float, name: str = "speed") -> float:
    """The one speed-range rule: a pinion speed in rad/s, ``0 < speed <= MAX_SPEED``.

    Returns the speed as a float.

    Raises
    ------
    InputError
        Out of range, naming ``name``, the value and the unit.

    Examples
    --------
    >>> check_speed(314.0)
    314.0
    >>> check_speed(0.0)
    Traceback (most recent call last):
    ...
    gear_dyn.errors.InputError: speed = 0 rad/s is out of range: valid range 0 < x <= 100000 rad/s
    """
    return check_range(name, speed, "rad/s", low=0.0, high=MAX_SPEED, low_open=True)


def check_torque(torque: float, name: str = "torque", positive: bool = False) -> float:
    """The one torque-range rule: a pinion torque in N m, ``0 <= torque <= MAX_TORQUE``
    (``0 < torque`` where ``positive``). Returns it as a float.

    Raises
    ------
    InputError
        Out of range, naming ``name``, the value and the unit.
    """
    return check_range(name, torque, "N*m", low=0.0, high=MAX_TORQUE, low_open=positive)


def teeth_mesh_frequency(z1: int, speed1: float) -> float:
    """Mesh frequency f_m = z1 w1 / (2 pi) in Hz of a pinion of ``z1`` teeth at ``speed1``
    rad/s (the one home of the formula: :func:`mesh_frequency` of a pair uses it)."""
    return z1 * speed1 / (2 * math.pi)


def output_speed(pair: GearPair, speed1: float) -> float:
    """Driven speed in rad/s: w2 = w1 z1 / z2.

    Parameters
    ----------
    pair : GearPair
        The gear pair.
    speed1 : float
        Pinion speed w1 in rad/s.

    Returns
    -------
    float
        Gear speed w2 in rad/s.

    See Also
    --------
    :func:`~gear_dyn.geometry.mesh_frequency` : The mesh frequency at the same speed.
    :class:`~gear_dyn.geometry.GearPair` : The pair.

    Examples
    --------
    >>> import math
    >>> pair = GearPair(19, 48, 3.2e-3, math.radians(20), 16e-3)
    >>> output_speed(pair, 48.0)  # rad/s
    19.0
    """
    return speed1 * pair.z1 / pair.z2
