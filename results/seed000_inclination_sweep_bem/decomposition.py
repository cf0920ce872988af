"""Measured decomposition of the inclination trends (issue 32; results/README.md, inclination).

Front and rear damage of the nominal direct drive (linear fidelity) at 8 m/s (below rated) and
15 m/s (above), I_ref 0.12, seeds 1-4 (600 s), for variants of the inflow and the rotor:

- ``table`` / ``bem``: the two rotors at 0 and 20 deg upflow (ddgsa's convention: the mean wind
  speed is along the inclined flow, so the axial component is V cos(chi + tilt));
- ``bem, no skewed wake``: the BEM rotor with the skewed-wake redistribution off;
- ``bem, no tower``: the BEM rotor without tower shadow;
- ``bem, horizontal V kept``: mean speed V / cos(chi) along the inclined flow (the horizontal
  component stays V: one reading of "vertical inclination" in seed 000);
- ``bem, downflow, horizontal V kept``: the same with the flow inclined downwards (-20 deg).

Run from the repository root: ``PYTHONPATH=src python results/seed000_inclination_sweep_bem/decomposition.py``
(about 5 CPU minutes); writes ``decomposition.csv`` beside this file. Rotor variants are set by
replacing the BEM rotor's default blade for the run (in memory, no shared loads cache).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

import ddgsa.loads as loads
from ddgsa import models
from ddgsa.loads.bem import NREL5MW_BLADE, Blade, simulate_bem
from ddgsa.loads.scene import Scene

SEEDS = (1, 2, 3, 4)
WINDS = (8.0, 15.0)
CASES = (   # name, fidelity, inclination [deg], speed factor of the inclination, blade
    ("table", "table", 0.0, False, NREL5MW_BLADE),
    ("table", "table", 20.0, False, NREL5MW_BLADE),
    ("bem", "bem", 0.0, False, NREL5MW_BLADE),
    ("bem", "bem", 20.0, False, NREL5MW_BLADE),
    ("bem, no skewed wake", "bem", 0.0, False, Blade(skewed_wake=False)),
    ("bem, no skewed wake", "bem", 20.0, False, Blade(skewed_wake=False)),
    ("bem, no tower", "bem", 0.0, False, Blade(tower_shadow=False)),
    ("bem, no tower", "bem", 20.0, False, Blade(tower_shadow=False)),
    ("bem, horizontal V kept", "bem", 20.0, True, NREL5MW_BLADE),
    ("bem, downflow, horizontal V kept", "bem", -20.0, True, NREL5MW_BLADE),
)


def main() -> pd.DataFrame:
    model = models.get("direct_drive", fidelity="linear")
    rows = []
    defaults = simulate_bem.__defaults__
    for name, fidelity, chi, keep_horizontal, blade in CASES:
        simulate_bem.__defaults__ = (0, blade, False, None)
        loads._generate.cache_clear()
        loads._as_array.cache_clear()
        for v in WINDS:
            speed = v / np.cos(np.deg2rad(chi)) if keep_horizontal else v
            for seed in SEEDS:
                scene = Scene(wind_speed=speed, turbulence_intensity=0.12, inclination_deg=chi, duration=600.0,
                              seed=seed, loads_fidelity=fidelity)
                out = model.evaluate(None, scene).iloc[0]
                lo = loads.generate(scene)
                rows.append({"case": name, "wind_speed": v, "inclination_deg": chi, "seed": seed,
                             "damage_front": out["damage_front"], "damage_rear": out["damage_rear"],
                             "Fx_mean": lo["Fx"].mean(), "My_mean": lo["My"].mean(), "Mz_mean": lo["Mz"].mean(),
                             "My_std": lo["My"].std(), "Mz_std": lo["Mz"].std(), "front_Fr_mean": out["front_Fr_mean"],
                             "rear_Fr_mean": out["rear_Fr_mean"]})
            print(name, chi, v, flush=True)
    simulate_bem.__defaults__ = defaults
    table = pd.DataFrame(rows)
    table.to_csv(Path(__file__).with_name("decomposition.csv"), index=False, float_format="%.6g")
    return table


if __name__ == "__main__":
    t = main()
    print(t.groupby(["case", "inclination_deg", "wind_speed"], sort=False).mean(numeric_only=True)
          .drop(columns="seed").to_string(float_format=lambda x: f"{x:.4g}"))
