"""Rig-specific force elements on the kernel's element interface (:class:`ddgsa.mbs.elements.Element`).

* :class:`MisalignedCoupling` -- the flexible coupling: a 6-DOF bushing in the frame of the
  motor-side hub (it turns with the shaft) whose lateral and angular stiffnesses differ by
  ``+-asymmetry`` in the two transverse directions of that frame (a jaw or pin coupling has a
  two-fold symmetry, not an axisymmetric one), with the motor axis displaced by a parallel
  offset ``delta`` (global y) and tilted by an angle ``alpha`` (about global z). The offset is
  fixed in space while the stiffness turns with the shaft, so the coupling force has a static
  part ``k delta`` and a part ``asymmetry k delta`` turning at twice the shaft speed: the 2x
  signature of misalignment (e.g. Sekhar & Prabhu, JSV 185 (1995): misalignment excites the
  even harmonics through the coupling; here through its stiffness anisotropy, an assumption).
* :class:`EccentricMass` -- the centrifugal force ``m_u w x (r x w)`` of a point mass ``m_u`` at
  radius ``e`` on a section (the disk), turning with it. The tangential term ``m_u e dw/dt``
  (start-up, coast-down) is left out: ``dw/dt / w^2`` is below 1 % above 100 rpm for the rig's
  accelerations (stated in docs/hss_rig.md).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ddgsa.mbs.bodies import Marker, MarkerState
from ddgsa.mbs.elements import Bushing6, Element

Array = NDArray[np.float64]


class MisalignedCoupling(Bushing6):
    """Flexible coupling between the motor-side hub (``marker_i``) and the shaft end (``marker_j``).

    Parameters
    ----------
    stiffness, damping : (6,)
        Axial, two lateral, torsional and two angular values in the hub frame [N/m, N m/rad],
        [N s/m, N m s/rad]; the lateral and angular pairs are the mean values.
    asymmetry : float
        ``(k_1 - k_2) / (k_1 + k_2)`` of the lateral and angular pairs [-].
    offset : float
        Parallel misalignment: motor axis displaced along global y [m].
    angle : float
        Angular misalignment: motor axis turned about global z [rad].
    """

    def __init__(self, marker_i: Marker, marker_j: Marker, stiffness: Array, damping: Array, asymmetry: float,
                 offset: float, angle: float, name: str = "coupling") -> None:
        k = np.asarray(stiffness, dtype=float).copy()
        for a, b in ((1, 2), (4, 5)):
            mean = k[a]
            k[a], k[b] = mean * (1 + asymmetry), mean * (1 - asymmetry)
        super().__init__(marker_i, marker_j, np.diag(k), np.diag(np.asarray(damping, dtype=float)), frame="i",
                         name=name)
        # the shaft end sits at the aligned position; the hub (motor axis) is displaced by the misalignment: a
        # fixed pre-deflection of the bushing, so the compiled kernel computes the coupling as it is
        self.offset = np.array([0.0, offset, 0.0, 0.0, 0.0, angle])


class EccentricMass(Element):
    """Centrifugal force of an eccentric point mass on a turning section (see the module).

    Parameters
    ----------
    marker : Marker
        The section (disk centre); its frame's y axis points at the mass at ``t = 0``.
    mass : float
        Eccentric mass ``m_u`` [kg].
    radius : float
        Its radius ``e`` [m].
    """

    def __init__(self, marker: Marker, mass: float, radius: float, name: str = "unbalance") -> None:
        self.markers = (marker,)
        self.mass, self.radius, self.name = mass, radius, name

    def wrench(self, t: float, states: list[MarkerState]) -> tuple[Array, None, None]:
        s = states[0]
        r = s.a[:, 1] * self.radius
        w = s.w
        out = np.zeros((1, 6))
        out[0, :3] = -self.mass * (w * (w @ r) - r * (w @ w))          # -m w x (w x r)
        return out, None, None
