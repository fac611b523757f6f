"""A jump of a sweep between two neighbouring speeds, and what caused it."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

#: pinion speed of one rpm, in rad/s
RPM = 2 * math.pi / 60

#: kinds of jumps, from the orbits (:mod:`gear_dyn.analysis.sweep.orbit_jumps`), and the fallback
JUMP_KINDS = ("fold", "contact_pattern", "branch", "unresolved", "rms_fallback")


@dataclass(frozen=True)
class Jump:
    """The response of one sweep direction jumps between two neighbouring speeds.

    Attributes
    ----------
    kind : str
        ``fold``: the orbit at ``from_speed``, continued towards ``to_speed``, turns back at a
        fold (``fold_speed``) before reaching it. ``contact_pattern``: it continues to
        ``to_speed`` without a fold, but the sweep settled there on another orbit with another
        contact pattern (a different number of separations or back-flank contacts per period).
        ``branch``: the same, with the same contact pattern (another branch). ``unresolved``:
        the continuation stopped between the speeds (step below its minimum), so where the
        orbit went is not known. ``rms_fallback``: one of the two speeds has no periodic orbit
        (aperiodic response or the transient method); the RMS DTE changes by more than the
        fallback threshold there.
    from_speed, to_speed : float
        The two neighbouring speeds in sweep order, rad/s.
    fold_speed : float
        ``fold``: the located fold (rad/s; to the continuation's ``locate_tol``, or the
        turning point of the branch where it turns without a located fold); NaN otherwise.
    rms_dte_before, rms_dte_after : float
        RMS DTE of the sweep at the two speeds, m.
    separation_before, separation_after : float
        Share of the period with the teeth apart at the two speeds (-).
    pattern_before, pattern_after : str
        Contact patterns of the two orbits (``D`` drive flank, ``G`` gap, ``B`` back flank, in
        time order from t = 0); empty where not computed (``rms_fallback``).
    """

    kind: str
    from_speed: float
    to_speed: float
    fold_speed: float
    rms_dte_before: float
    rms_dte_after: float
    separation_before: float
    separation_after: float
    pattern_before: str = ""
    pattern_after: str = ""

    def row(self) -> dict[str, Any]:
        """JSON-able fields, speeds in rpm and in rad/s (``fold_rpm``, ``fold_rad_s`` None
        where no fold was located)."""
        located = math.isfinite(self.fold_speed)
        return {"kind": self.kind, "from_rpm": self.from_speed / RPM,
                "to_rpm": self.to_speed / RPM,
                "fold_rpm": self.fold_speed / RPM if located else None,
                "from_rad_s": self.from_speed, "to_rad_s": self.to_speed,
                "fold_rad_s": self.fold_speed if located else None,
                "rms_dte_before_m": self.rms_dte_before, "rms_dte_after_m": self.rms_dte_after,
                "separation_before": self.separation_before,
                "separation_after": self.separation_after,
                "pattern_before": self.pattern_before, "pattern_after": self.pattern_after}
