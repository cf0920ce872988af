"""Benchmark: the rig's control features as inputs of the confirmation's control variates (issue 46 item 8),
CPU, one process (reported, not asserted).

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/rig_feature_control.py [out.json] [KIND]`` (~5 min on a quiet
core). On the ``KIND`` scene (``steady``, the default, ``startup`` or ``coastdown``: the features
``lateral_ratio_1/2`` or ``critical_ratio_1`` and ``end_ratio_1``) of ``studies/paper_a_subsystem.yaml`` (its 8
parameters +-10 %, 1500 rpm, 1.2 s at 2 kHz, fidelity ``linear``: the block path), a pilot of 256 and of 512 scrambled Sobol' points and one Saltelli
design (N = 256, 2 560 runs, seed 1) are run once. Per output and pilot: the relative leave-one-out error of
the plain control (:func:`ddgsa.gsa.control.fit_control` without features) and of the control with the rig's
features (:class:`ddgsa.gsa.control.FeatureSurrogate`), the Saltelli base the cost rule asks of each
(:func:`ddgsa.gsa.salib.saltelli_n_to_confirm` with the controlled ST), each control's relative RMS error on
1 024 fresh random points (is its leave-one-out error honest?), and, on the same Saltelli rows, the
largest error estimate on ST of the plain, the plain-controlled and the feature-controlled estimators: at a
bound going as ``N^-1/2`` the runs for the same interval scale as its square.
"""

from __future__ import annotations

import json
import sys
import time
from typing import Any

import numpy as np
import pandas as pd

import ddgsa
from ddgsa.gsa.base import get_method
from ddgsa.gsa.control import FeatureSurrogate, controlled_saltelli, fit_control
from ddgsa.gsa.salib import saltelli_n_to_confirm

PARAMETERS = {"hss_diameter": 0.025, "hss_span": 1.0, "disk_position": 0.5, "disk_mass": 15.0,
              "disk_damping": 70.0, "bearing_stiffness": 5e7, "support_stiffness": 2e7, "eccentric_mass": 0.005}
SCENE = {"kind": "steady", "speed_rpm": 1500, "duration": 1.2, "sample_rate": 2000, "settle": 0.2, "seed": 1}
OUTPUTS = ["peak_disk_y", "order1x_disk_y", "peak_housing_1_y", "rms_housing_1_y", "order1x_housing_1_y",
           "rms_housing_2_z"]
PILOTS = (256, 512)
BASE = 256


def run(model: Any, x: np.ndarray, names: list[str]) -> tuple[np.ndarray, np.ndarray]:
    """Outputs (n, k) and features (n, 2) at points ``x``, in blocks of 256."""
    ys, fs = [], []
    for k in range(0, len(x), 256):
        out = model.evaluate(pd.DataFrame(x[k:k + 256], columns=names), SCENE)
        ys.append(out[OUTPUTS].to_numpy(float))
        fs.append(np.column_stack(list(out.attrs["features"].values())))
    return np.vstack(ys), np.vstack(fs)


def main(path: str | None = None, kind: str = "steady") -> dict[str, Any]:
    import warnings

    SCENE["kind"] = kind

    warnings.simplefilter("ignore")
    space = ddgsa.ParameterSpace.from_dict({p: {"nominal": v, "spread": 0.1} for p, v in PARAMETERS.items()})
    names = list(space.names)
    model = ddgsa.models.get("hss_rig", fidelity="linear", time_step=5e-4)
    run(model, space.sample(2, seed=0, rule="sobol"), names)                 # compile or load the kernels
    pilot = space.sample(max(PILOTS), seed=2, rule="sobol")
    t0 = time.process_time()
    y_pilot, phi_pilot = run(model, pilot, names)
    per_run = (time.process_time() - t0) / len(pilot)
    design = get_method("saltelli").design(space, n=BASE, seed=1)
    y_salt, _ = run(model, design.points, names)
    u_fresh = np.random.default_rng(9).random((1024, space.dim))
    y_fresh, _ = run(model, space.ppf(u_fresh), names)
    d = space.dim
    u_pilot = np.column_stack([space[p].cdf(pilot[:, i]) for i, p in enumerate(names)])
    u_salt = np.column_stack([space[p].cdf(design.points[:, i]) for i, p in enumerate(names)])
    rows = []
    for n in PILOTS:
        for j, o in enumerate(OUTPUTS):
            u, y, phi = u_pilot[:n], y_pilot[:n, j], phi_pilot[:n]
            t = time.process_time()
            plain = fit_control(u, y, seed=0)
            t_plain = time.process_time() - t
            t = time.process_time()
            feat = FeatureSurrogate.fit(u, y, phi, seed=0)
            t_feat = time.process_time() - t
            f = y_salt[:, j].reshape(BASE, d + 2)
            none = controlled_saltelli(f, np.zeros_like(f), (0.0, np.zeros(d), np.zeros(d)), seed=1)
            row: dict[str, Any] = {"pilot": n, "output": o, "plain_fit": None if plain is None else plain.fitted_to,
                                   "plain_loo": None if plain is None else plain.loo,
                                   "feature_fit": None if feat is None else feat.fitted_to,
                                   "feature_loo": None if feat is None else feat.loo,
                                   "fit_cpu_s_plain": t_plain, "fit_cpu_s_feature": t_feat,
                                   "ST_plain_estimator": none.ST.round(4).tolist(),
                                   "ST_error_none": float(none.ST_error.max())}
            for key, g in (("plain", plain), ("feature", feat)):
                if g is None:
                    continue
                t = time.process_time()
                c = controlled_saltelli(f, g(u_salt).reshape(BASE, d + 2), g.variances(), seed=1,
                                        exact_error=g.variance_errors())
                row[f"fresh_error_{key}"] = float(np.sqrt(np.mean((g(u_fresh) - y_fresh[:, j]) ** 2))
                                                  / y_fresh[:, j].std())
                row[f"ST_{key}"] = c.ST.round(4).tolist()
                row[f"ST_error_{key}"] = float(c.ST_error.max())
                row[f"N_rule_{key}"] = saltelli_n_to_confirm(c.ST, 0.02, g.loo)
                row[f"variances_cpu_s_{key}"] = time.process_time() - t
            rows.append(row)
            print(json.dumps(row), flush=True)
    res = {"scene": SCENE, "cpu_s_per_run_block": per_run, "base": BASE, "rows": rows}
    if path:
        with open(path, "w") as fh:
            json.dump(res, fh, indent=1)
    return res


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None, sys.argv[2] if len(sys.argv) > 2 else "steady")
