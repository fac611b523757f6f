"""Plain-dict summaries of a stiffness curve and of the operating geometry (for JSON and tables).

The operating centre distance (the shaft offset of Jiang et al. 2018, ``a_w = a + d_a``) moves the
start and end of contact, so the contact ratio, the share of the cycle with one pair in contact,
the backlash and every stiffness curve follow it; :func:`operating_summary` reports those figures.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from gear_dyn.geometry import GearPair
from gear_dyn.stiffness.periodic import PeriodicStiffness


def zone_edges(contact_ratio: float) -> tuple[float, int, int]:
    """``(f, n_low, n_high)``: pairs ``n_high = n_low + 1`` touch on [0, f), ``n_low`` on [f, 1)."""
    n = int(math.floor(contact_ratio))
    return contact_ratio - n, n, n + 1


def operating_summary(pair: GearPair) -> dict[str, Any]:
    """Operating geometry of ``pair``: centre distance, contact ratio, zones, backlash.

    Keys (SI): center_distance_m, zero_backlash_center_distance_m, center_distance_offset_m,
    operating_pressure_angle_deg, contact_ratio, overlap_ratio, single_contact_share (share of the
    mesh cycle with floor(eps_a) pairs; 2 - eps_a for 1 < eps_a < 2), path_of_contact_m,
    base_pitch_m, backlash_m (along the line of action, teeth at nominal thickness).
    """
    f, _, _ = zone_edges(pair.contact_ratio)
    return {
        "center_distance_m": pair.a_w,
        "zero_backlash_center_distance_m": pair.zero_backlash_center_distance,
        "center_distance_offset_m": pair.a_w - pair.zero_backlash_center_distance,
        "operating_pressure_angle_deg": math.degrees(pair.alpha_wt),
        "contact_ratio": pair.contact_ratio,
        "overlap_ratio": pair.overlap_ratio,
        "single_contact_share": 1.0 - f if f > 1e-12 else 1.0,
        "path_of_contact_m": pair.path_of_contact,
        "base_pitch_m": pair.base_pitch,
        "backlash_m": pair.backlash,
    }


def stiffness_summary(pair: GearPair, k: PeriodicStiffness, points: int = 4001) -> dict[str, Any]:
    """Mean, min, max and zone values of ``k`` (N/m).

    ``single_pair_n_per_m`` and ``double_pair_n_per_m`` are the mean stiffness over the part of the
    cycle with ``floor(eps_a)`` and ``floor(eps_a) + 1`` transverse pairs in contact (for a
    rectangular wave: exactly its two levels). ``pairs_low``/``pairs_high`` say which counts those
    are (1 and 2 for 1 < eps_a < 2).
    """
    f, n_low, n_high = zone_edges(pair.contact_ratio)
    out: dict[str, Any] = {
        "method": k.name,
        "mean_n_per_m": k.mean,
        "min_n_per_m": k.min,
        "max_n_per_m": k.max,
        "switching_phases": [float(v) for v in k.switching_phases],
        "pairs_low": n_low,
        "pairs_high": n_high,
    }
    if f > 1e-9:
        hi = (np.arange(points) + 0.5) / points * f
        lo = f + (np.arange(points) + 0.5) / points * (1 - f)
        out["double_pair_n_per_m"] = float(np.mean(k(hi)))
        out["single_pair_n_per_m"] = float(np.mean(k(lo)))
    else:
        out["double_pair_n_per_m"] = None
        out["single_pair_n_per_m"] = float(k.mean)
    return out
