"""What a scene's inputs leave out, said where a result would otherwise look quiet.

A backlash scene whose only excitation is the mesh stiffness variation k(t): the dynamic part of
the mesh force is then proportional to the static load W (divide the equation of motion
m x'' + c x' + k(t) f(x) = W by W), so F / W and whether the teeth leave contact do not depend on
the load. A light load opens the gap only with an excitation that does not scale with W: a
static transmission error, profile modification, eccentricity or manufacturing deviations
(Kahraman & Singh 1990, who excite their backlash oscillator by a static transmission error).
"""

from __future__ import annotations

from gear_dyn.scene.validated import Scene

#: scene tables whose excitation does not scale with the load (a displacement imposed by the
#: geometry: harmonics of e(t), the relief's depth, the centres' offsets, tooth deviations)
LOAD_INDEPENDENT_TABLES = ("transmission_error", "tip_relief", "eccentricity", "deviations")


def load_independent_excitations(scene: Scene) -> list[str]:
    """The tables of ``scene`` that excite the mesh independently of the load (see
    :data:`LOAD_INDEPENDENT_TABLES`; a table with ``pattern = "none"`` excites nothing)."""
    return [name for name in LOAD_INDEPENDENT_TABLES
            if scene.has(name) and scene.tables[name].get("pattern") != "none"]


def backlash_gap_hint(scene: Scene, separated: bool = False) -> str | None:
    """The hint for a backlash scene with no load-independent excitation, or None.

    Parameters
    ----------
    scene : Scene
    separated : bool
        The result shows the teeth leaving contact somewhere (then the gap does open, and no
        hint is given).

    Returns
    -------
    str or None
        One sentence for the result's warnings, or None where the scene has no backlash, has
        an excitation that can open the gap, or the teeth separate anyway.
    """
    if not scene.has("backlash") or separated or load_independent_excitations(scene):
        return None
    return (f"{scene.name}: backlash with only the mesh stiffness variation as excitation: the "
            "dynamic force scales with the load W, so F/W and the teeth staying in contact do "
            "not depend on the torque (a light load behaves as a full one); to open the gap at "
            "light load add an excitation that does not scale with W: [transmission_error] "
            "harmonics, [tip_relief], [eccentricity] or manufacturing [deviations]")


__all__ = ["LOAD_INDEPENDENT_TABLES", "backlash_gap_hint", "load_independent_excitations"]
