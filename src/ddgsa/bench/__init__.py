"""Benchmarks, kept out of the core modules (``ddgsa bench``): none of the library imports them.

- :mod:`~ddgsa.bench.speed` -- every speed target with its measured value and verdict
  (``ddgsa bench``, ``ddgsa bench indirect``);
- :mod:`~ddgsa.bench.rig` -- the test rig's linear paths against the nonlinear rig (``ddgsa bench rig``);
- :mod:`~ddgsa.bench.scaling` -- wall time against runs, parameters and workers (``ddgsa bench scaling``);
- :mod:`~ddgsa.bench.accuracy_cost` -- index error against cost per method (``ddgsa bench accuracy``);
- :mod:`~ddgsa.bench.calibration` -- the calibration of every method's ``trusted`` flag (``ddgsa bench trust``).
"""
