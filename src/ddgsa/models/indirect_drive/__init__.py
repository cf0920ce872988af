"""Indirect drive with a one-stage gearbox as kinematic constraints (seed 001 §2.2-2.3, thesis paper D).

- :mod:`.parameters` -- declared parameters with units, ranges and sources (NREL 5-MW defaults);
- :mod:`.closed_form` -- the stage's geometry and the closed-form references (torsional mode,
  torque balance, housing roll on its mounts);
- :mod:`.assembly` -- the bodies, constraints and elements on the shared kernel (:mod:`ddgsa.mbs`);
- :mod:`.linear` -- operating state and the exactly integrated linearisation (``linear`` fidelity);
- :mod:`.series`, :mod:`.outputs` -- time series and objective functions;
- :mod:`.model` -- the registered model :class:`IndirectDrive`.
"""

from ddgsa.models.indirect_drive.model import IndirectDrive

__all__ = ["IndirectDrive"]
