"""Benchmark: the rig's coast-down indices by a Saltelli design tilted towards its resonance (issue 46 item 6;
:mod:`ddgsa.gsa.tilted`), against the same design untilted at the same runs (reported, not asserted).

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/tilted_coastdown.py [out.json] [BASE] [tilted,plain]`` (~6 min on 2 cores at
the default base 512). On the coast-down of ``studies/paper_a_subsystem.yaml`` (8 parameters +-10 %, from 1500
rpm synchronous, 1.2 s at 2 kHz, fidelity ``linear``: the block path):

1. a pilot of 256 scrambled Sobol' points gives the rig's control feature ``critical_ratio_1`` (synchronous
   speed over the lowest lateral frequency) and the outputs; a Gaussian process
   (:class:`ddgsa.gsa.control.GaussianSurrogate`) of the feature predicts it anywhere in the unit cube;
2. the ratio the resonance sits at is read from the pilot (the feature's median over the 8 runs with the
   largest first-housing RMS): the tilt is the squared amplification of ``feature / that`` with a damping of
   :data:`DAMPING` (wider than the mode's 0.015-0.031: the prediction's error and the outputs' own spread);
3. a control per output: a Gaussian process of ``log y`` over the inputs and the predicted ratio's log
   amplification, fitted on :data:`CONTROL_PILOT` runs drawn as the tilted base is (half along the tilt: where
   the spike is), its moments from a tilted design of base :data:`CONTROL_MOMENTS` on the process;
4. a tilted design (mix 1/2) and an untilted one (mix 0) of base ``BASE`` (``BASE (2 d + 1)`` runs each) are
   run, and each output's first and total indices with their bootstrap half-widths and the weighted terms'
   Pareto tail shapes compared: tilted, tilted with the control, untilted; the committed
   ``results/paper_a_subsystem`` confirm_saltelli rows of the coast-down (20 480 runs, controlled) beside them.
"""

from __future__ import annotations

import json
import os
import sys
import time
from typing import Any

import numpy as np
import pandas as pd
from joblib import Parallel, delayed

PARAMETERS = {"hss_diameter": 0.025, "hss_span": 1.0, "disk_position": 0.5, "disk_mass": 15.0,
              "disk_damping": 70.0, "bearing_stiffness": 5e7, "support_stiffness": 2e7, "eccentric_mass": 0.005}
SCENE = {"kind": "coastdown", "speed_rpm": 1500, "duration": 1.2, "sample_rate": 2000, "settle": 0.2, "seed": 1}
OUTPUTS = ["peak_disk_y", "order1x_disk_y", "peak_housing_1_y", "rms_housing_1_y", "order1x_housing_1_y",
           "rms_housing_2_z"]
PILOT, BASE, DAMPING, CHUNK = 256, 512, 0.03, 128
CONTROL_PILOT, CONTROL_MOMENTS = 1024, 32768
"""Runs of the controls' pilot; base of the tilted design on each control for its moments."""
PAIRS = (("hss_span", "hss_diameter"), ("hss_diameter", "disk_mass"), ("disk_position", "disk_damping"))
"""The pairs of neighbours in the coast-down's ranking whose difference intervals are reported."""


def _chunk(x: np.ndarray, names: list[str]) -> tuple[np.ndarray, np.ndarray]:
    import warnings

    import ddgsa

    warnings.simplefilter("ignore")
    model = ddgsa.models.get("hss_rig", fidelity="linear", time_step=5e-4)
    out = model.evaluate(pd.DataFrame(x, columns=names), SCENE)
    return out[OUTPUTS].to_numpy(float), np.asarray(out.attrs["features"]["critical_ratio_1"], float)


def run(x: np.ndarray, names: list[str], jobs: int) -> tuple[np.ndarray, np.ndarray]:
    """Outputs (n, k) and the feature ``critical_ratio_1`` (n,) at points ``x``, ``jobs`` processes."""
    parts = Parallel(n_jobs=jobs)(delayed(_chunk)(x[k:k + CHUNK], names) for k in range(0, len(x), CHUNK))
    return np.vstack([p[0] for p in parts]), np.concatenate([p[1] for p in parts])


def main(path: str | None = None, base: int = BASE, jobs: int = 2,
         designs: tuple[str, ...] = ("tilted", "plain")) -> dict[str, Any]:
    import ddgsa
    from ddgsa.gsa.control import GaussianSurrogate
    from ddgsa.gsa.tilted import control_moments, proposal_sample, resonance_tilt, tilted_design, tilted_indices

    space = ddgsa.ParameterSpace.from_dict({p: {"nominal": v, "spread": 0.1} for p, v in PARAMETERS.items()})
    names, d = list(space.names), space.dim
    t0 = time.perf_counter()
    u_pilot = space.unit_sample(PILOT, seed=7)
    y_pilot, feature = run(space.ppf(u_pilot), names, jobs)
    gp = GaussianSurrogate.fit(u_pilot, feature)
    if gp is None:
        raise SystemExit("the feature's Gaussian process did not fit")
    loo = float(np.sqrt(np.mean((gp.loo_values - feature) ** 2)) / np.std(feature))
    top = np.argsort(y_pilot[:, OUTPUTS.index("rms_housing_1_y")])[-8:]
    at = float(np.median(feature[top]))
    tilt = resonance_tilt(lambda u: gp(u) / at, DAMPING, d, mix=0.5, seed=1)
    plain = resonance_tilt(lambda u: gp(u) / at, DAMPING, d, mix=0.0, seed=1)
    result: dict[str, Any] = {"base": base, "runs_each": base * (2 * d + 1), "pilot": PILOT, "damping": DAMPING,
                              "feature_loo_relative": loo, "resonance_at_feature": at,
                              "feature_range": [float(feature.min()), float(feature.max())], "designs": {}}
    committed = pd.read_csv(os.path.join(os.path.dirname(__file__), "..", "results", "paper_a_subsystem",
                                         "indices.csv"))
    committed = committed[(committed.scene == 2) & (committed.method == "confirm_saltelli")]
    # the controls: a process of log y over the inputs and the predicted ratio's log amplification, fitted on
    # a pilot drawn like the tilted base (half from the input law, half along the tilt: where the spike is)
    u_ctl = proposal_sample(tilt, CONTROL_PILOT, d, seed=5)
    y_ctl, _ = run(space.ppf(u_ctl), names, jobs)

    def augmented(u: np.ndarray) -> np.ndarray:
        s = gp(u) / at
        return np.column_stack([u, -0.5 * np.log((1 - s * s) ** 2 + (2 * DAMPING * s) ** 2)])

    controls, control_loo = {}, {}
    for j, out in enumerate(OUTPUTS):
        proc = GaussianSurrogate.fit(augmented(u_ctl), np.log(y_ctl[:, j]), max_loo=np.inf, exact=False)
        controls[out] = (lambda p: lambda u: np.exp(p(augmented(u))))(proc)
        control_loo[out] = float(proc.loo)
    result["control"] = {"pilot": CONTROL_PILOT, "loo_of_log_y": control_loo}
    for label, t in (("tilted", tilt), ("plain", plain)):
        if label not in designs:
            continue
        design = tilted_design(t, base, d, seed=11)
        start = time.perf_counter()
        y, _ = run(space.ppf(design.u), names, jobs)
        seconds = time.perf_counter() - start
        tables: dict[str, Any] = {}
        for variant in ((label, label + "_controlled") if label == "tilted" else (label,)):
            rows = tables[variant] = {}
            for j, out in enumerate(OUTPUTS):
                if not np.isfinite(y[:, j]).all():
                    rows[out] = "failed runs"
                    continue
                control = None
                if variant.endswith("controlled"):
                    g = controls[out]
                    control = (g(design.u), control_moments(g, t, d, n=CONTROL_MOMENTS, seed=12))
                frame = tilted_indices(design, y[:, j], names, seed=3, control=control)
                rows[out] = frame.round(5).to_dict(orient="index")
                diff = frame.attrs["ST_difference_conf"]
                rows[out]["differences"] = {f"{a} - {b}": [round(float(frame.ST[a] - frame.ST[b]), 5),
                                                          round(float(diff.loc[a, b]), 5)] for a, b in PAIRS}
        near = float(np.mean(np.abs(gp(design.u[:base]) / at - 1.0) < 0.05))
        for variant, rows in tables.items():
            result["designs"][variant] = {"seconds": seconds, "base_within_5pct_of_resonance": near, "indices": rows}
    result["committed_confirm_saltelli"] = {
        out: committed[committed.output == out].set_index("parameter")[["S1", "S1_conf", "ST", "ST_conf"]]
        .round(5).to_dict(orient="index") for out in OUTPUTS}
    result["total_seconds"] = time.perf_counter() - t0
    result["load_average"] = list(os.getloadavg())
    if path:
        with open(path, "w") as fh:
            json.dump(result, fh, indent=1)
    return result


def summary(res: dict[str, Any]) -> str:
    lines = [f"base {res['base']} ({res['runs_each']} runs each); feature LOO {res['feature_loo_relative']:.2g}; "
             f"resonance at feature {res['resonance_at_feature']:.4f}"]
    for out in OUTPUTS:
        lines.append(out)
        com = res["committed_confirm_saltelli"][out]
        for p in PARAMETERS:
            cells = []
            for label in (k for k in ("tilted", "tilted_controlled", "plain") if k in res["designs"]):
                r = res["designs"][label]["indices"][out]
                cells.append("failed" if isinstance(r, str) else
                             f"{label} ST {r[p]['ST']:.3f}+-{r[p]['ST_conf']:.3f} k {r[p]['ST_tail']:.2f}")
            c = com.get(p, {})
            lines.append(f"  {p:18s} " + " | ".join(cells) + f" | committed {c.get('ST', float('nan')):.3f}+-"
                         f"{c.get('ST_conf', float('nan')):.3f}")
        for label in (k for k in ("tilted", "tilted_controlled", "plain") if k in res["designs"]):
            r = res["designs"][label]["indices"][out]
            if not isinstance(r, str):
                lines.append(f"  {label} differences: " + "; ".join(f"{k} {v[0]:+.3f}+-{v[1]:.3f}"
                                                                 for k, v in r["differences"].items()))
    return "\n".join(lines)


if __name__ == "__main__":
    res = main(sys.argv[1] if len(sys.argv) > 1 else None, int(sys.argv[2]) if len(sys.argv) > 2 else BASE,
               designs=tuple(sys.argv[3].split(",")) if len(sys.argv) > 3 else ("tilted", "plain"))
    print(summary(res))
