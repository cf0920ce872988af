"""Indirect drive with a one-stage gearbox as kinematic constraints (seed 001 §2.2-2.3, thesis paper D).

- :mod:`.parameters` -- declared parameters with units, ranges and sources (NREL 5-MW defaults);
- :mod:`.closed_form` -- the stage's geometry and the closed-form references (torsional mode,
  torque balance, housing roll on its mounts);
- :mod:`.outputs` -- objective functions of a simulated record.
"""
