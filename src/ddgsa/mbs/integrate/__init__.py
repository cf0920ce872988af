"""Integrators of the constrained equations (seed 001 eq. 2.6).

- :mod:`~ddgsa.mbs.integrate.genalpha` -- generalised-alpha for constrained systems, the fast
  nonlinear path (index 3 for holonomic constraints, index 2 for velocity-level ones, scaled).
- :mod:`~ddgsa.mbs.integrate.reference` -- ``solve_ivp`` on the index-1 form with Baumgarte
  stabilisation, the reference path.
- :mod:`~ddgsa.mbs.integrate.exact` -- linearisation about an operating point, reduction on the
  null space of the constraint Jacobian and exact integration of the LTI system.

Each ``simulate(system, t_end, dt, ...)`` returns a :class:`Trajectory`.
"""

from ddgsa.mbs.integrate import exact, genalpha, reference
from ddgsa.mbs.integrate.trajectory import Trajectory

__all__ = ["Trajectory", "genalpha", "reference", "exact"]
