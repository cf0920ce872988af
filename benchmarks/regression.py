"""Regression figures of the direct drive on the 600 s bench scene (recorded, then asserted by a test).

Run: ``python benchmarks/regression.py`` writes ``benchmarks/results/regression_600s.json``:
the objective functions of every fidelity at the nominal point and two off-nominal points on
:data:`ddgsa.bench.FULL` (11 m/s, I 0.12, seed 1). ``tests/models/test_direct_drive.py``
compares the model with them, so a port of the model onto another multibody API shows it
kept the numbers (or says by how much it moved them).
"""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd

import ddgsa.models as models
from ddgsa.bench.timing import FULL

RESULT = Path(__file__).parent / "results" / "regression_600s.json"
POINTS = (
    {},
    {"k_front_y": 2.5e9, "c_gen": 9.0e5, "thrust_factor": 1.1},
    {"shaft_bending_stiffness": 1.2e9, "bearing_damping_ratio": 0.02, "hub_mass": 42000.0},
)
FIDELITIES = ("flexible", "rigid", "linear")


def compute(fidelity: str) -> pd.DataFrame:
    """Objectives of ``fidelity`` at :data:`POINTS` on the 600 s scene (one row per point)."""
    model = models.get("direct_drive", fidelity=fidelity, shaft="table2")   # the recorded figures' shaft (issue 47)
    return model.evaluate(pd.DataFrame([{**model.nominal, **p} for p in POINTS]), FULL)


def main() -> None:
    out = {"scene": FULL.to_dict(), "points": list(POINTS),
           "objectives": {f: compute(f).to_dict("records") for f in FIDELITIES}}
    RESULT.parent.mkdir(parents=True, exist_ok=True)
    RESULT.write_text(json.dumps(out, indent=2) + "\n")
    print(f"wrote {RESULT}")


if __name__ == "__main__":
    main()
