"""The rig-specific force element on the kernel's element interface (:class:`ddgsa.mbs.elements.Element`).

* :class:`MisalignedCoupling` -- the flexible coupling: a 6-DOF bushing in the frame of the
  motor-side hub (it turns with the shaft) whose lateral and angular stiffnesses differ by
  ``+-asymmetry`` in the two transverse directions of that frame (a jaw or pin coupling has a
  two-fold symmetry, not an axisymmetric one), with the motor axis displaced by a parallel
  offset ``delta`` (global y) and tilted by an angle ``alpha`` (about global z). The offset is
  fixed in space while the stiffness turns with the shaft, so the coupling force has a static
  part ``k delta`` and a part ``asymmetry k delta`` turning at twice the shaft speed: the 2x
  signature of misalignment (e.g. Sekhar & Prabhu, JSV 185 (1995): misalignment excites the
  even harmonics through the coupling; here through its stiffness anisotropy, an assumption).

The eccentric mass on the disk is the kernel's :class:`ddgsa.mbs.elements.EccentricMass`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ddgsa.mbs.bodies import Marker
from ddgsa.mbs.elements import Bushing6

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
