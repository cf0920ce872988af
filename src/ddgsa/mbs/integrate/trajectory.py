"""The result of a time integration: states, multipliers, element outputs and constraint drift."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from numpy.typing import NDArray

Array = NDArray[np.float64]


@dataclass
class Trajectory:
    """States of a system at the output times.

    Attributes
    ----------
    t : (n_t,) times [s]
    q, qd : (n_t, n) coordinates and velocities (SI: m, rad, elastic coordinates' units)
    lam : (n_t, n_c) constraint multipliers (see each constraint's ``reaction``)
    outputs : (n_t, n_el, 6) each element's wrench on its first marker [N, N m]
    position_drift : (n_t,) max |C(q)| of the holonomic constraints [m]
    velocity_drift : (n_t,) max |C_q q_dot + C_t| (and of the velocity-level constraints) [m/s, rad/s]
    coord_names, element_names, multiplier_names : names of the columns
    info : solver figures (method, steps, Newton iterations, function evaluations...)
    """

    t: Array
    q: Array
    qd: Array
    lam: Array
    outputs: Array
    position_drift: Array
    velocity_drift: Array
    coord_names: tuple[str, ...]
    element_names: tuple[str, ...]
    multiplier_names: tuple[str, ...]
    info: dict = field(default_factory=dict)

    @property
    def max_drift(self) -> float:
        """Largest holonomic constraint violation over the run [m]."""
        return float(self.position_drift.max()) if self.position_drift.size else 0.0

    def element(self, name: str) -> Array:
        """Wrench history (n_t, 6) of the element called ``name``."""
        return self.outputs[:, self.element_names.index(name)]

    def to_frame(self) -> pd.DataFrame:
        """Time series indexed by time [s]: coordinates, rates (``d_`` prefix), multipliers, element wrenches."""
        cols: dict[str, Array] = {}
        for i, nm in enumerate(self.coord_names):
            cols[nm] = self.q[:, i]
        for i, nm in enumerate(self.coord_names):
            cols[f"d_{nm}"] = self.qd[:, i]
        for i, nm in enumerate(self.multiplier_names):
            cols[nm] = self.lam[:, i]
        for e, nm in enumerate(self.element_names):
            for k, comp in enumerate(("Fx", "Fy", "Fz", "Mx", "My", "Mz")):
                cols[f"{nm}_{comp}"] = self.outputs[:, e, k]
        cols["position_drift"] = self.position_drift
        cols["velocity_drift"] = self.velocity_drift
        return pd.DataFrame(cols, index=pd.Index(self.t, name="time"))
