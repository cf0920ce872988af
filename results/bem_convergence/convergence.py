"""Convergence of the blade-element (BEM) rotor's hub loads in element count and time step (issue 32).

Hub loads of :func:`ddgsa.loads.bem.simulate_bem` for

- **elements**: the 17 Table 2-1 elements split into ``refine`` = 1, 2, 4, 8 sub-elements
  (17, 34, 68, 136 per blade), time step 0.05 s, rotor speed and pitch held at the operating
  point of the mean wind (the aerodynamic discretisation alone; with the controller the slow
  rotor-speed transient after the spin-up would mix in);
- **time step**: dt = 0.1, 0.05, 0.025, 0.0125 s, 17 elements, with the controller (as a study
  runs it), the inflow of the finest step sampled every 8th / 4th / 2nd / 1st step (one wind
  realisation for all steps, so only the rotor's stepping changes: azimuth, rotor speed,
  controller, the skew angle's lag),

in two winds each at 8 and 15 m/s: steady (shear 0.2, 20 deg upflow, 120 s) and turbulent
(I_ref 0.12, shear 0.2, 20 deg upflow, seed 1, 600 s). Statistics: mean and standard deviation
of thrust Fx, torque Mx, tilt My and yaw Mz after the 30 s spin-up; each against the finest
level (refine 8, dt 0.0125 s). Run from the repository root:
``PYTHONPATH=src python results/bem_convergence/convergence.py`` (a few CPU minutes); writes
``convergence.csv`` beside this file. The table is in docs/loads.md.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ddgsa.loads import NREL5MW, SPINUP_S, Scene, wind_field
from ddgsa.loads.bem import Blade, simulate_bem

WINDS = (8.0, 15.0)
REFINE = (1, 2, 4, 8)
DT_FINE = 0.0125
STEPS = (8, 4, 2, 1)                  # dt = 0.1, 0.05, 0.025, 0.0125 s
LOADS = {"Fx": 0, "Mx": 3, "My": 4, "Mz": 5}     # columns of simulate_bem's output


def stats(out: np.ndarray) -> dict[str, float]:
    row = {}
    for name, i in LOADS.items():
        row[f"{name}_mean"] = out[:, i].mean()
        row[f"{name}_std"] = out[:, i].std()
    return row


def main() -> pd.DataFrame:
    rows = []
    for wind, ti, duration in (("steady", 0.0, 120.0), ("turbulent", 0.12, 600.0)):
        for v in WINDS:
            scene = Scene(wind_speed=v, turbulence_intensity=ti, inclination_deg=20.0, shear_exponent=0.2,
                          duration=duration, dt=DT_FINE, seed=1)
            fine = wind_field(scene)
            init = NREL5MW.steady_state(v)
            for k in STEPS:
                dt = DT_FINE * k
                out = simulate_bem(NREL5MW, fine[:, ::k], dt, init, spinup=int(round(SPINUP_S / dt)))
                rows.append({"wind": wind, "wind_speed": v, "study": "dt", "elements": 17, "dt": dt, **stats(out)})
            inflow = fine[:, ::4]
            for refine in REFINE:
                out = simulate_bem(NREL5MW, inflow, 0.05, init, spinup=int(round(SPINUP_S / 0.05)),
                                   blade=Blade(refine=refine), fixed=True)
                rows.append({"wind": wind, "wind_speed": v, "study": "elements", "elements": 17 * refine, "dt": 0.05,
                             **stats(out)})
            print(wind, v, flush=True)
    table = pd.DataFrame(rows)
    # relative difference from the finest level of each study; moments against the torque's scale
    # where their own value is small (a mean yaw moment near zero)
    ref = table.groupby(["wind", "wind_speed", "study"]).transform(lambda c: c.iloc[-1])
    for col in [c for c in table.columns if c.endswith(("_mean", "_std"))]:
        scale = np.maximum(ref[col].abs(), 0.05 * ref["Mx_mean"].abs()) if col.startswith(("My", "Mz")) \
            else ref[col].abs()
        table[f"d_{col}"] = (table[col] - ref[col]) / scale
    table.to_csv(Path(__file__).with_name("convergence.csv"), index=False, float_format="%.6g")
    return table


if __name__ == "__main__":
    t = main()
    cols = ["wind", "wind_speed", "study", "elements", "dt"] + [c for c in t.columns if c.startswith("d_")]
    print(t[cols].to_string(float_format=lambda x: f"{x:+.4f}" if abs(x) < 1 else f"{x:.4g}"))
