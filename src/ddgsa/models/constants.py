"""Physical constants and turbine-layout numbers the models share (one place, so two models never disagree).

Examples
--------
>>> tilted_gravity(0.0)
(0.0, 0.0, -9.81)
>>> round(tilted_gravity()[0], 4)   # the shaft's 4 deg tilt puts a little gravity along it
0.6843
"""

from __future__ import annotations

import math

GRAVITY = 9.81
"""Gravitational acceleration [m/s^2]."""
TILT_DEG = 4.0
"""Main-shaft tilt of the NREL 5 MW reference turbine [deg] (the direct and the geared drive)."""


HUB_MASS = 40000.0
"""Rotor hub mass on the main shaft's flange [kg] (seed 000 Table 2, m1): both wind models."""
HUB_INERTIA_X = 1.96e6
"""Rotor hub polar inertia about the shaft [kg m^2]: seed 000 Table 2's m1 with its equivalent radius
R1 = 7 m read as a radius of gyration, ``m1 R1^2``. The inertia the shaft's bending and gyroscopic
dynamics see in both wind models; the blades' remaining polar inertia (loads model, NREL 5-MW) is
turned by the drive-train torsion only (their flap flexibility decouples their tilt, docs/physics.md
"Rotor inertia of the two wind models")."""
HUB_INERTIA_YZ = 0.98e6
"""Rotor hub diametral inertia [kg m^2]: half the polar one (a thin disc), as :data:`HUB_INERTIA_X`."""


def tilted_gravity(tilt_deg: float = TILT_DEG) -> tuple[float, float, float]:
    """Gravity [m/s^2] in a shaft frame (x along the shaft, z up) tilted by ``tilt_deg`` [deg]."""
    tau = math.radians(tilt_deg)
    return (GRAVITY * math.sin(tau), 0.0, -GRAVITY * math.cos(tau))
