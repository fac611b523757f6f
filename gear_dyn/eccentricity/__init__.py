"""Geometric eccentricity of a helical pair (Liu et al. 2017; docs/eccentricity.md).

- :mod:`.kinematics`: centres, centre distance, dynamic pressure angle, pitch point, ratio, speeds
- :mod:`.contact_lines`: time-varying contact lines and their total length L(t)
- :mod:`.friction`: friction force and friction torques on both gears
"""

from gear_dyn.eccentricity.kinematics import Eccentricity, EccentricMesh, Kinematics

__all__ = ["Eccentricity", "EccentricMesh", "Kinematics"]
