"""Gear mesh with a pressure angle: seed 001 eq. 2.4 along the line of action.

:class:`~ddgsa.mbs.constraints.GearContact` makes the pitch-point velocities of the two gears
equal along the common tangent ``t``. Real involute teeth push along the line of action
``n = cos(alpha) t + sin(alpha) e`` (``e`` from gear i's axis towards gear j's): for pure rotation
the two constraints are the same (the radial velocity of a pitch point is zero), but the
multiplier is then the normal tooth force, whose component ``sin(alpha)`` separates the shafts
and loads their bearings as real teeth do. The driven flank is the one of positive drive torque
on gear i (for a reversed torque the line of action mirrors; not modelled). External pairs only.
"""

from __future__ import annotations

import math

import numpy as np

from ddgsa.errors import ModelError
from ddgsa.mbs.bodies import Marker, MarkerState
from ddgsa.mbs.constraints import GearContact


class GearMesh(GearContact):
    """:class:`~ddgsa.mbs.constraints.GearContact` along the line of action at ``pressure_angle`` [rad].

    The multiplier is the normal tooth force on gear ``j`` along ``n`` [N]. Parameters as
    :class:`~ddgsa.mbs.constraints.GearContact`, plus ``pressure_angle`` in [0, pi/4].
    """

    reaction = ("normal_force_on_j",)

    def __init__(self, gear_i: Marker, gear_j: Marker, radius_i: float, radius_j: float, housing: Marker,
                 pressure_angle: float, internal: bool = False, name: str = "gear") -> None:
        if not 0.0 <= pressure_angle <= math.pi / 4:
            raise ModelError(f"gear mesh {name!r}: pressure angle {pressure_angle} rad is outside [0, pi/4]")
        if internal and pressure_angle > 0.0:
            raise ModelError(f"gear mesh {name!r}: a pressure angle is modelled for external pairs only; "
                             "use GearContact for an internal pair")
        super().__init__(gear_i, gear_j, radius_i, radius_j, housing, internal=internal, name=name)
        self.pressure_angle = float(pressure_angle)

    def bind(self, states: list[MarkerState]) -> None:
        super().bind(states)
        si, sj, sh = states
        d = sh.a.T @ (sj.r - si.r)                      # housing frame; x is the gear axis
        d[0] = 0.0
        e = d / np.linalg.norm(d)
        self.tangent = math.cos(self.pressure_angle) * self.tangent + math.sin(self.pressure_angle) * e
