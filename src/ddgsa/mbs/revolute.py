"""Axis alignment: the two rotation equations that, with :class:`~ddgsa.mbs.constraints.Spherical`,
make a revolute joint (a hub on its shaft flange, turning only about the common axis).

``C = [a_i^T b_j1, a_i^T b_j2] = 0``: the x axis ``a_i`` of marker i's section stays perpendicular
to the y and z axes ``b_j1, b_j2`` of marker j's, so the two x axes stay parallel and the only
relative rotation left is about them (where a torsional spring can act).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ddgsa.mbs.bodies import Marker, MarkerState
from ddgsa.mbs.constraints import Constraint

Array = NDArray[np.float64]


class AxisAlignment(Constraint):
    """Keep the x axes of two marker sections parallel (2 holonomic equations).

    The multipliers are moments [N m] about ``a_i x b_j1`` and ``a_i x b_j2`` (for aligned axes:
    about marker j's z and y axes) that the joint exerts to keep the axes aligned.

    Examples
    --------
    >>> from ddgsa.mbs.bodies import Ground, RigidBody
    >>> from ddgsa.mbs.assembly import System
    >>> hub = RigidBody("hub", mass=1.0, inertia=(2.0, 1.0, 1.0), angles=(0.3, 0.0, 0.0))
    >>> c = AxisAlignment(hub.marker(), Ground().marker())
    >>> float(np.abs(System([hub], constraints=[c]).holonomic_residual(hub.initial_state()[0], np.zeros(6), 0.0)[0]).max())
    0.0
    """

    n_eq = 2
    holonomic = True
    reaction = ("moment_n1", "moment_n2")

    def __init__(self, marker_i: Marker, marker_j: Marker, name: str = "alignment") -> None:
        self.markers, self.name = (marker_i, marker_j), name

    def position(self, t: float, states: list[MarkerState]) -> tuple[Array, Array]:
        si, sj = states
        u = si.a[:, 0]
        jac = np.zeros((2, 12))
        val = np.zeros(2)
        for k in (1, 2):
            v = sj.a[:, k]
            val[k - 1] = u @ v
            # d(u.v) = (dth_i x u).v + u.(dth_j x v) = dth_i.(u x v) + dth_j.(v x u)
            jac[k - 1, 3:6] = np.cross(u, v)
            jac[k - 1, 9:12] = np.cross(v, u)
        return val, jac
