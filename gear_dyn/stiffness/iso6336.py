"""ISO 6336-1:2019 method B tooth stiffness: single stiffness c' and mesh stiffness c_gamma.

The formulas (q', c' = C_M C_R C_B cos(beta) (E / E_steel) / q', c_gamma = c' (0.75 eps_a + 0.25),
c_gamma_beta = 0.85 c_gamma, the load correction below F_t/b = 100 N/mm when a line load is
given) and the helical case are written out in docs/stiffness.md, "ISO 6336-1 method B".
Validity: steel pairs, beta <= 45 deg, x1 >= x2, -0.5 <= x1 + x2 <= 2 (applied as is outside).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from gear_dyn.errors import check_range
from gear_dyn.geometry import GearPair

C = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)
E_STEEL = 206e9
UNIT = 1e9  # 1 N/(mm um) = 1e9 N/m^2


@dataclass(frozen=True)
class IsoStiffness:
    """ISO 6336-1 method B stiffness of a pair.

    Attributes
    ----------
    c_single : float
        Single stiffness c' in N/m per m of face width (N/m^2).
    c_mesh : float
        Mesh stiffness c_gamma in N/m^2.
    k_single, k_mesh : float
        c' b and c_gamma b in N/m.
    c_mesh_beta : float
        c_gamma_beta = 0.85 c_gamma_alpha in N/m^2 (ISO 6336-1, used for K_Hbeta).
    q_prime : float
        Minimum flexibility q' of the pair in mm um / N.
    c_theoretical : float
        c'_th = 1 / q' in N/(mm um).
    basic_rack_factor : float
        C_B.
    """

    c_single: float
    c_mesh: float
    k_single: float
    k_mesh: float
    c_mesh_beta: float = float("nan")
    q_prime: float = float("nan")
    c_theoretical: float = float("nan")
    basic_rack_factor: float = float("nan")


def iso6336_stiffness(pair: GearPair, line_load: float | None = None) -> IsoStiffness:
    """ISO 6336-1 method B single and mesh stiffness of ``pair``.

    Parameters
    ----------
    pair : GearPair
        The gear pair (its geometry, profile shifts and materials).
    line_load : float or None
        Transverse line load F_t K_A / b in N/m; below 1e5 N/m (100 N/mm) c' is reduced by
        ``(line_load / 1e5) ** 0.25`` as ISO 6336-1 prescribes. None: no reduction.

    Returns
    -------
    IsoStiffness
        c' and c_gamma in N/m^2, k' = c' b and k_m = c_gamma b in N/m, q', C_B.

    Raises
    ------
    InputError
        A non-finite line load.

    See Also
    --------
    :func:`~gear_dyn.stiffness.select.build_stiffness`
        The periodic mesh stiffness (``iso6336`` uses these values).
    :func:`~gear_dyn.stiffness.periodic.rectangular_stiffness`
        The rectangular wave of given stiffness values.

    Examples
    --------
    >>> import math
    >>> from gear_dyn import GearPair
    >>> pair = GearPair(19, 48, 3.2e-3, math.radians(20), 16e-3)
    >>> iso = iso6336_stiffness(pair)
    >>> round(iso.k_mesh / 1e6, 1)  # mesh stiffness c_gamma b in N/um
    304.7
    >>> light = iso6336_stiffness(pair, line_load=1e4)  # 10 N/mm: reduced by 0.1 ** 0.25
    >>> round(light.c_single / iso.c_single, 4)
    0.5623
    """
    cb = math.cos(pair.beta)
    virtual = math.cos(pair.beta_b) ** 2 * cb  # zn = z / (cos^2(beta_b) cos(beta))
    zn1 = pair.z1 / virtual
    zn2 = pair.z2 / virtual
    x1, x2 = pair.x1, pair.x2
    q = (
        C[0] + C[1] / zn1 + C[2] / zn2 + C[3] * x1 + C[4] * x1 / zn1 + C[5] * x2
        + C[6] * x2 / zn2 + C[7] * x1**2 + C[8] * x2**2
    )
    c_th = 1.0 / q
    h_fp = pair.addendum_coef + pair.clearance_coef
    c_b = (1 + 0.5 * (1.2 - h_fp)) * (1 - 0.02 * (20.0 - math.degrees(pair.pressure_angle)))
    c_m, c_r = 0.8, 1.0
    e_eq = 2 * pair.youngs_modulus1 * pair.youngs_modulus2 / (
        pair.youngs_modulus1 + pair.youngs_modulus2
    )
    c1 = c_th * c_m * c_r * c_b * cb * (e_eq / E_STEEL)
    if line_load is not None:
        line_load = check_range("line_load", line_load, "N/m")  # a number, not NaN or text
    if line_load is not None and line_load < 1e5:
        c1 *= (max(line_load, 0.0) / 1e5) ** 0.25
    c1 *= UNIT
    cg = c1 * (0.75 * pair.contact_ratio + 0.25)
    return IsoStiffness(c1, cg, c1 * pair.face_width, cg * pair.face_width,
                        c_mesh_beta=0.85 * cg, q_prime=q, c_theoretical=c_th,
                        basic_rack_factor=c_b)
