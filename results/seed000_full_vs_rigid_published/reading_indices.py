"""Sobol indices of seed 000's four reading switches (issue 34), exact from the full 2^4 factorial.

Reads ``sweep.csv`` here and ``../seed000_full_vs_rigid_rigid_published/sweep.csv`` (means over
realisations) and writes ``reading_indices.csv``: for each wind speed and output, the first-order
and total indices of each switch taken as an equally likely binary input,
``S1_i = Var(E[Y | x_i]) / Var(Y)`` and ``ST_i = E[(Y(x_i = 1) - Y(x_i = 0))^2] / 4 / Var(Y)``.
Outputs: the flexible model's objectives and the rigid / flexible ratios of damage and hub
deflection (the seed's full-against-simplified agreement). Run from the repository root:
``python results/seed000_full_vs_rigid_published/reading_indices.py``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

HERE = Path(__file__).parent
SWITCHES = {"bending_rayleigh": "printed", "bearing_damping": "stiffness_proportional", "deflection": "frame",
            "deflection_reference": "mean"}
OUTPUTS = ["damage_front", "damage_rear", "rms_deflection_hub", "rms_deflection_gen"]


def _table(path: Path) -> pd.DataFrame:
    """Means over realisations, one row per variant and wind speed, the switches as 0/1 columns."""
    df = pd.read_csv(path).groupby(["variant", "wind_speed"], as_index=False)[OUTPUTS].mean()
    options = df["variant"].map(lambda v: dict(kv.split("=") for kv in v.split(", ")))
    for name, second in SWITCHES.items():
        df[name] = options.map(lambda o, n=name, s=second: int(o.get(n) == s))
    return df


def main() -> None:
    flex = _table(HERE / "sweep.csv")
    rigid = _table(HERE.parent / "seed000_full_vs_rigid_rigid_published" / "sweep.csv")
    rigid_keys = ["wind_speed", "bearing_damping", "deflection_reference"]
    both = flex.merge(rigid[rigid_keys + OUTPUTS], on=rigid_keys, suffixes=("", "_rigid"))
    for out in ("damage_front", "rms_deflection_hub"):
        both[f"ratio_{out}"] = both[f"{out}_rigid"] / both[out]
    rows = []
    names = list(SWITCHES)
    for wind, grp in both.groupby("wind_speed"):
        for out in OUTPUTS + ["ratio_damage_front", "ratio_rms_deflection_hub"]:
            y = grp.set_index(names)[out].sort_index()
            var = float(y.var(ddof=0))
            for name in names:
                s1 = float(y.groupby(level=name).mean().var(ddof=0)) / var
                diff = y.xs(1, level=name) - y.xs(0, level=name)
                st = float(np.mean(diff.to_numpy() ** 2)) / 4.0 / var
                rows.append({"wind_speed": wind, "output": out, "switch": name, "S1": s1, "ST": st})
    pd.DataFrame(rows).to_csv(HERE / "reading_indices.csv", index=False, float_format="%.4f")


if __name__ == "__main__":
    main()
