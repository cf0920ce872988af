"""The multibody kernel the drive-train models share.

Parts (each small and testable alone):

- :mod:`ddgsa.mbs.bodies` -- :class:`RigidBody`, :class:`FlexibleBody` (FFR shaft on the FE
  eigenmodes of :mod:`ddgsa.mbs.beam`, inertia invariants of :mod:`ddgsa.mbs.ffr`),
  :class:`Ground`, :class:`PrescribedBody`; bodies own their coordinates and give markers.
- :mod:`ddgsa.mbs.elements` -- :class:`SpringDamper3`, :class:`Bushing6`, :class:`TorsionalSpring`,
  :class:`TorqueLaw`, :class:`AppliedLoad`, :class:`RadialForce` (a callable law of the radial
  displacement) between markers (forces and tangents).
- :mod:`ddgsa.mbs.constraints` -- :class:`Spherical`, :class:`TransverseBearing`,
  :class:`GearContact` (seed 001 eqs. 2.3-2.4), :class:`PrescribedSpeed`, :class:`Lock` (chosen
  relative translations/rotations), :class:`PrescribedCoordinate` (one held at a value or ``f(t)``).
- :mod:`ddgsa.mbs.assembly` -- :class:`System`: the equations of eq. 2.5 from those parts.
- :mod:`ddgsa.mbs.statics` -- :func:`static_equilibrium`, the one static equilibrium of any System.
- :mod:`ddgsa.mbs.integrate` -- ``genalpha`` (fast nonlinear path), ``reference`` (``solve_ivp``),
  ``exact`` (linearised, exactly discretised).
- :mod:`ddgsa.mbs.modal` -- constrained linearisation and labelled modes;
  :mod:`ddgsa.mbs.campbell` -- Campbell diagrams.
- :mod:`ddgsa.mbs.system`, :mod:`ddgsa.mbs.linear` -- the single-body compiled kernel of the
  direct drive and its exact LTI integration (shared functions).

See ``docs/kernel.md`` for how a model is written on these parts.
"""

from ddgsa.mbs.assembly import System
from ddgsa.mbs.bodies import FlexibleBody, Ground, Marker, PrescribedBody, RigidBody
from ddgsa.mbs.constraints import (GearContact, Lock, PrescribedCoordinate, PrescribedSpeed, Spherical,
                                   TransverseBearing)
from ddgsa.mbs.elements import (AirGapPull, AppliedLoad, Bushing6, EccentricMass, RadialForce, SpringDamper3,
                                TorqueLaw, TorsionalSpring)
from ddgsa.mbs.integrate import Trajectory, exact, genalpha, reference
from ddgsa.mbs.modal import linearise_system, modes
from ddgsa.mbs.statics import static_equilibrium

__all__ = [
    "System", "RigidBody", "FlexibleBody", "Ground", "PrescribedBody", "Marker",
    "SpringDamper3", "Bushing6", "TorsionalSpring", "TorqueLaw", "AppliedLoad", "RadialForce", "AirGapPull",
    "EccentricMass",
    "Spherical", "TransverseBearing", "GearContact", "PrescribedSpeed", "Lock", "PrescribedCoordinate",
    "genalpha", "reference", "exact", "Trajectory", "linearise_system", "modes", "static_equilibrium",
]
