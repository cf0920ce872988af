"""The small multibody kernel the drive-train models share.

- :mod:`ddgsa.mbs.ffr` -- floating-frame-of-reference body of lumped mass points (compiled).
- :mod:`ddgsa.mbs.beam` -- FE Euler-Bernoulli shaft eigenmodes used as shape functions.
- :mod:`ddgsa.mbs.system` -- a body on spring-dampers with point loads and a torque law;
  generalised-alpha integrator and the ``solve_ivp`` reference path.
- :mod:`ddgsa.mbs.modal` -- linearisation and modal analysis.
"""
