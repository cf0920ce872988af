"""The test rig's speed against its accuracy (``ddgsa bench rig --out DIR``): the block path, the per-point
``linear`` path and the nonlinear ``kloss`` rig on the same points, in one run (issue 46).

For each scene of ``studies/paper_a_subsystem.yaml`` (steady state at 1500 rpm, start-up, coast-down;
1.2 s records at 2 kHz; ``quick``: a 0.6 s steady record, a start-up's and coast-down's keep 1.2 s, in which
they turn the revolutions their ball-pass bands need) ``points`` uniform draws of the study's space (seeded),
with an axisymmetric coupling (``coupling_asymmetry = 0``: the linear fidelity carries the jaw coupling's
anisotropy as a load and the ``kloss`` reference starts without its orbit, a stated bias that
:mod:`ddgsa.bench.rig` times apart; here the linearisation's error alone), are evaluated three ways:

* ``kloss``: the nonlinear rig integrated by generalised-alpha at :data:`~ddgsa.bench.rig.REFERENCE_STEP`,
  one point at a time -- the reference the errors are taken against;
* ``linear, per point``: the ``linear`` fidelity through :meth:`ddgsa.models.base.Model._evaluate_block`'s
  loop, one point at a time;
* ``linear, block``: the ``linear`` fidelity's block path (:mod:`ddgsa.models.hss_rig.steady_block`,
  :mod:`ddgsa.models.hss_rig.sweep_block`), all points in one call.

A path's error at a point is the largest relative difference from ``kloss`` over the study's outputs
(:data:`~ddgsa.bench.rig.OUTPUTS`) whose reference exceeds the output's declared resolution (a numerically
zero output has no relative error to speak of); the chart shows, per scene and path, the CPU seconds a run
(best of repeats, as :func:`~ddgsa.bench.timing.timed`) against the median and largest of those errors.
The ``kloss`` rows' own error is that of a step twice as long (its step-halving estimate, second order).
"""

from __future__ import annotations

import json
import math
import os
import platform
from pathlib import Path
from typing import Any

import numpy as np

from ddgsa.bench.rig import LINEAR_STEP, OUTPUTS, REFERENCE_STEP
from ddgsa.bench.timing import RIG_STUDY, timed

PATHS = ("kloss", "linear, per point", "linear, block")
"""The three paths, slowest first."""


def speed_accuracy(points: int = 4, quick: bool = False, seed: int = 11) -> dict[str, Any]:
    """Each path's CPU seconds a run and its errors against ``kloss`` on ``points`` draws per scene (see the
    module); returns the rows and the machine's facts."""
    import pandas as pd

    import ddgsa.models as models
    from ddgsa.models.base import Model
    from ddgsa.study.spec import load_study

    study = load_study(RIG_STUDY)
    linear = models.get("hss_rig", fidelity="linear", time_step=LINEAR_STEP)
    nonlinear = models.get("hss_rig", fidelity="kloss", time_step=REFERENCE_STEP)
    coarse = models.get("hss_rig", fidelity="kloss", time_step=2 * REFERENCE_STEP)
    u = np.random.default_rng(seed).random((points, study.space.dim))
    draws = pd.DataFrame(study.space.ppf(u), columns=list(study.space.names)).assign(coupling_asymmetry=0.0)
    resolution = {str(o): o.resolution for o in linear.outputs}
    rows = []
    for kind in ("steady", "startup", "coastdown"):
        scene = linear._scene({"kind": kind, "speed_rpm": 1500.0, "duration": 0.6 if quick and kind == "steady" else 1.2,
                               "sample_rate": 2000.0, "settle": 0.2, "seed": 1})
        params = linear.resolve(draws)
        linear._evaluate_block(params.iloc[:1], scene)                  # kernels loaded outside the timing
        _, ref_cpu, ref = timed(lambda: Model._evaluate_block(nonlinear, nonlinear.resolve(draws), scene),
                                min_total=0.0, max_repeat=1)
        results = {
            "kloss": (ref_cpu, timed(lambda: Model._evaluate_block(coarse, coarse.resolve(draws), scene),
                                     min_total=0.0, max_repeat=1)[2]),
            "linear, per point": timed(lambda: Model._evaluate_block(linear, params, scene), min_total=0.0,
                                       max_repeat=1)[1:],
            "linear, block": timed(lambda: linear._evaluate_block(params, scene))[1:],
        }
        for path, (cpu, out) in results.items():
            errors = _errors(out, ref, resolution)
            finite = errors[np.isfinite(errors)]
            rows.append({"scene": kind, "path": path, "points": points,
                         "cpu_s_per_run": cpu / points, "median_rel_error": float(np.median(finite)) if len(finite) else math.nan,
                         "max_rel_error": float(finite.max()) if len(finite) else math.nan,
                         "failed_points": int(np.sum(~np.isfinite(errors)))})
    return {"machine": f"{platform.machine()}, {os.cpu_count()} cores", "python": platform.python_version(),
            "quick": quick, "points": points, "seed": seed, "outputs": list(OUTPUTS),
            "reference": f"kloss, generalised-alpha {REFERENCE_STEP:g} s", "rows": rows,
            "load_average": list(os.getloadavg())}


def _errors(out: Any, ref: Any, resolution: dict[str, float]) -> np.ndarray:
    """Per point, the largest relative difference of ``out`` from ``ref`` over :data:`OUTPUTS` whose reference
    exceeds its resolution (NaN where the point failed on either path)."""
    worst, failed = np.zeros(len(ref)), np.zeros(len(ref), dtype=bool)
    for o in OUTPUTS:
        r, v = ref[o].to_numpy(float), out[o].to_numpy(float)
        failed |= ~(np.isfinite(r) & np.isfinite(v))
        with np.errstate(divide="ignore", invalid="ignore"):
            worst = np.fmax(worst, np.where(np.abs(r) > resolution[o], np.abs(v / r - 1.0), 0.0))
    return np.where(failed, np.nan, worst)


def write(res: dict[str, Any], out: Path) -> list[Path]:
    """``rig_speed_accuracy.json`` and ``rig_speed_accuracy.png`` in ``out``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out.mkdir(parents=True, exist_ok=True)
    (out / "rig_speed_accuracy.json").write_text(json.dumps(res, indent=2))
    fig, ax = plt.subplots(figsize=(7.0, 4.4))
    markers = {"kloss": "s", "linear, per point": "o", "linear, block": "D"}
    colours = {"steady": "tab:blue", "startup": "tab:orange", "coastdown": "tab:green"}
    for r in res["rows"]:
        lo, hi = max(r["median_rel_error"], 1e-6), max(r["max_rel_error"], 1e-6)
        ax.errorbar(r["cpu_s_per_run"], lo, yerr=[[0.0], [hi - lo]], fmt=markers[r["path"]], color=colours[r["scene"]],
                    capsize=3, ms=7, mfc="white" if r["path"] == "kloss" else colours[r["scene"]])
    for path, m in markers.items():
        ax.plot([], [], m, color="0.3", mfc="white" if path == "kloss" else "0.3",
                label="kloss (error: of twice its step)" if path == "kloss" else path)
    for scene, c in colours.items():
        ax.plot([], [], "-", color=c, label=scene)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("CPU seconds a run")
    ax.set_ylabel("error against kloss (median, bar to largest) [-]")
    ax.set_title(f"hss_rig: speed against accuracy, {res['points']} points a scene"
                 + (" (quick: 0.6 s steady record)" if res["quick"] else "") + ", axisymmetric coupling", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, ncol=2, loc="best")
    fig.tight_layout()
    fig.savefig(out / "rig_speed_accuracy.png", dpi=110)
    plt.close(fig)
    return [out / "rig_speed_accuracy.json", out / "rig_speed_accuracy.png"]


def format_speed_accuracy(res: dict[str, Any]) -> str:
    """A plain-text table of :func:`speed_accuracy`'s rows."""
    lines = [f"hss_rig speed against accuracy, {res['points']} points a scene, machine {res['machine']}, "
             f"load average {res['load_average']}; errors against {res['reference']}", "",
             f"{'scene':10s} {'path':18s} {'CPU s/run':>10s} {'median err':>11s} {'max err':>9s} {'failed':>7s}"]
    for r in res["rows"]:
        lines.append(f"{r['scene']:10s} {r['path']:18s} {r['cpu_s_per_run']:10.4f} {r['median_rel_error']:11.2e} "
                     f"{r['max_rel_error']:9.2e} {r['failed_points']:7d}")
    return "\n".join(lines)
