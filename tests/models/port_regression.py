"""Objectives of the direct drive on a fixed set of points and scenes: the port's regression table, a
guard (the code must keep reproducing it), not an oracle (it holds what the code computed, right or not).

``python tests/models/port_regression.py`` (with ``PYTHONPATH=src``) writes
``tests/models/data/direct_drive_objectives.csv`` from the code as it is; the table committed before
the direct drive moved onto ``ddgsa.mbs``'s System is what ``test_direct_drive_port.py`` holds the
ported model to (1e-6 relative; the tolerances and why: ``test_direct_drive_port.py``).
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from ddgsa import models
from ddgsa.loads.scene import Scene

TABLE = Path(__file__).parent / "data" / "direct_drive_objectives.csv"
SCENES = ((6.0, 0.12, 0.0), (11.0, 0.12, 10.0), (18.0, 0.20, 0.0))
POINTS = ({}, {"k_front_y": 1.3e10, "shaft_bending_stiffness": 0.8, "hub_mass": 1.1, "c_gen": 0.9},
          {"k_rear_z": 0.7, "bearing_damping_ratio": 1.5, "front_bearing_x": 1.2, "generator_mass": 0.85})
FIDELITIES = ("flexible", "rigid", "linear")
PORT_BASIS = {"beam": "euler_bernoulli", "bending_modes": 2, "shaft": "table2"}
"""The port's basis and shaft (seed 000 Table 2's, the default shaft until issue 47)."""
"""The shaft basis the port was made on (seed 000's, the default until issue 26): the table holds it."""


def points_frame(nominal: dict[str, float]) -> pd.DataFrame:
    """The three points: nominal, and two with some parameters scaled (values < 2 are factors)."""
    rows = []
    for change in POINTS:
        row = dict(nominal)
        for name, value in change.items():
            row[name] = value if value > 2 else nominal[name] * value
        rows.append(row)
    return pd.DataFrame(rows)


def objectives() -> pd.DataFrame:
    """One row per (fidelity, scene, point) with every output of the direct drive on :data:`PORT_BASIS`."""
    frames = []
    for fidelity in FIDELITIES:
        model = models.get("direct_drive", fidelity=fidelity, **PORT_BASIS)
        pts = points_frame(model.nominal)
        for wind, ti, incl in SCENES:
            scene = Scene(wind_speed=wind, turbulence_intensity=ti, inclination_deg=incl, duration=60.0, seed=1)
            out = model.evaluate(pts, scene).reset_index(drop=True)
            out.insert(0, "point", range(len(pts)))
            out.insert(0, "wind_speed", wind)
            out.insert(0, "fidelity", fidelity)
            frames.append(out)
    return pd.concat(frames, ignore_index=True)


if __name__ == "__main__":
    TABLE.parent.mkdir(exist_ok=True)
    objectives().to_csv(TABLE, index=False, float_format="%.17g")
    print(f"wrote {TABLE}")
