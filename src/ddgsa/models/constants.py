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


def tilted_gravity(tilt_deg: float = TILT_DEG) -> tuple[float, float, float]:
    """Gravity [m/s^2] in a shaft frame (x along the shaft, z up) tilted by ``tilt_deg`` [deg]."""
    tau = math.radians(tilt_deg)
    return (GRAVITY * math.sin(tau), 0.0, -GRAVITY * math.cos(tau))
