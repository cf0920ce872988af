"""Accuracy against cost: Sobol-index error of every method against model evaluations and wall time.

``ddgsa bench accuracy`` (or :func:`run`) writes, under ``results/accuracy_cost/``:

* ``accuracy_cost.csv`` -- one row per (function, method, options, seed): ``n_evals``,
  ``wall_s``, ``err_S1`` / ``err_ST`` (max absolute error over parameters), ``rmse_S1`` and
  whether the method trusted itself (``trusted``); M-DRM runs with its default check sample
  (``MDRM_CHECK`` points, counted in ``n_evals``): without one it never trusts a row;
* ``accuracy_<function>.png`` -- per function, error against evaluations and against wall
  time, log-log (hollow markers: the method's own diagnostics distrusted the result);
* ``fidelity_cost.csv`` and ``fidelity_cost.png`` -- the direct drive's objective-function error
  against seconds per evaluation for each fidelity and time step.

Reference answers: closed forms for the analytic functions (:mod:`ddgsa.gsa.testfunctions`);
for the direct drive (``linear`` fidelity, the cheapest within 0.5 % of ``flexible``, 60 s at
11 m/s, the quickstart's five parameters) a PCE of order 5 on 2 048 scrambled-Sobol' points
(seed 99, independent of every compared design), whose agreement with order 4 on the same
points is reported as its own uncertainty (``reference_spread``). The fidelity reference is
``solve_ivp(Radau, rtol 1e-6)`` on the flexible equations.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

import ddgsa
from ddgsa.gsa.result import SobolResult
from ddgsa.gsa.testfunctions import TestFunction, ishigami, linear, product, sobol_g
from ddgsa.gsa.space import ParameterSpace
from ddgsa.report.sections.accuracy_cost import plot_function

OUT = Path("results") / "accuracy_cost"
# Published/measured reference points for the Ishigami chart (the numbers): S1 RMSE.
def functions() -> dict[str, TestFunction]:
    """The analytic test functions of the benchmark."""
    unit4 = ParameterSpace.from_dict({f"x{i}": {"low": 0.0, "high": 1.0} for i in range(4)})
    return {
        "product": product(unit4, [0.5, 0.4, 0.3, 0.1]),          # positive: no sign change
        "additive": linear(unit4, [1.0, 0.8, 0.5, 0.2], offset=0.5),
        "ishigami": ishigami(),
        "g_easy": sobol_g([1.0, 2.0, 5.0, 10.0, 20.0, 50.0]),
        "g_hard": sobol_g([0.0, 0.5, 3.0, 9.0, 99.0, 99.0]),
    }


#: M-DRM's check sample in the comparison: its default, the price of its trust estimate
MDRM_CHECK = 32


def method_grid(max_log2: int = 14, seeds: tuple[int, ...] = (0, 1, 2, 3, 4)) -> list[tuple[str, dict[str, Any]]]:
    """The compared (method, options) pairs: M-DRM 2-9 points (with its check sample), Saltelli/RBD-FAST 2^6..2^max, PCE 2-6, auto."""
    grid: list[tuple[str, dict[str, Any]]] = [("mdrm", {"points": p, "check": MDRM_CHECK}) for p in range(2, 10)]
    grid += [("saltelli", {"n": 1 << k, "seed": s}) for k in range(6, max_log2 + 1) for s in seeds]
    grid += [("rbd_fast", {"n": 1 << k, "seed": s}) for k in range(6, max_log2 + 1, 2) for s in seeds]
    grid += [("pce", {"order": q}) for q in range(2, 7)]
    grid += [("auto", {"budget": b}) for b in (500, 2000, 8000)]
    return grid


def errors(res: SobolResult, s1: np.ndarray, st: np.ndarray) -> dict[str, float]:
    """Max absolute S1/ST errors over parameters, S1 RMSE, and the method's own trust (first output)."""
    t = res.indices[res.indices["output"] == res.indices["output"].iloc[0]]
    d1 = t["S1"].to_numpy(float) - s1
    dt = t["ST"].to_numpy(float) - st
    return {"err_S1": float(np.max(np.abs(d1))), "err_ST": float(np.max(np.abs(dt))),
            "rmse_S1": float(np.sqrt(np.mean(d1 ** 2))), "trusted": bool(t["trusted"].all())}


def analytic_rows(grid: list[tuple[str, dict[str, Any]]], progress: Callable[[str], None] = print) -> pd.DataFrame:
    """Every method of ``grid`` on every analytic function, timed (one core)."""
    rows = []
    for name, tf in functions().items():
        progress(f"accuracy: {name}")
        for method, opts in grid:
            t0 = time.perf_counter()
            res = ddgsa.sobol(tf.f, tf.space, method, **opts)
            wall = time.perf_counter() - t0
            rows.append({"function": name, "method": method, "options": _opts(opts), "seed": opts.get("seed", 0),
                         "n_evals": res.n_evals, "wall_s": wall, **errors(res, tf.S1, tf.ST),
                         "source": ",".join(sorted(set(res.indices.get("source", pd.Series([method])))))})
    return pd.DataFrame(rows)


def _opts(opts: dict[str, Any]) -> str:
    return " ".join(f"{k}={v}" for k, v in opts.items() if k != "seed")


def drive_train_rows(jobs: int = 2, store_path: Path | None = None,
                     progress: Callable[[str], None] = print) -> pd.DataFrame:
    """The compared methods on the direct drive (linear fidelity, 60 s) against a PCE reference."""
    from ddgsa.execute.pipeline import execute
    from ddgsa.runner import EvaluationStore
    from ddgsa.study.spec import validate_study

    grid = [("mdrm", {"points": p, "check": MDRM_CHECK}) for p in range(2, 8)]
    grid += [("saltelli", {"n": 1 << k, "seed": 0}) for k in range(6, 10)]
    grid += [("rbd_fast", {"n": 1 << k, "seed": 0}) for k in range(6, 11, 2)]
    grid += [("pce", {"order": q}) for q in (2, 3, 4)]
    reference = [("pce", {"order": 4, "n": 2048, "seed": 99}), ("pce", {"order": 5, "n": 2048, "seed": 99})]
    spec = {
        "name": "accuracy_cost_direct_drive",
        "model": {"name": "direct_drive", "fidelity": "linear"},
        "parameters": {"k_front_z": {"nominal": 1e10, "spread": 0.3}, "k_rear_z": {"nominal": 1e10, "spread": 0.3},
                       "k_front_y": {"nominal": 3e9, "spread": 0.3},
                       "hub_mass": {"dist": "truncnormal", "mean": 40000, "std": 2000, "low": 34000, "high": 46000},
                       "bearing_C_front": {"nominal": 1e7, "spread": 0.1}},
        "scenes": {"wind_speed": [11.0], "turbulence_intensity": 0.12, "duration": 60, "realisations": 1, "seed": 1},
        "outputs": ["damage_front", "damage_rear", "rms_deflection_hub"],
        "methods": [{"method": m, **o} for m, o in grid + reference],
        "run": {"jobs": jobs, "batch_size": 16},
    }
    study = validate_study(spec)
    progress("accuracy: direct drive (linear fidelity, 60 s scene)")
    store = EvaluationStore(store_path or OUT / "evaluations.sqlite")
    result = execute(study, store, quiet=False)
    per_eval = float(result.evaluations["seconds"].median()) if "seconds" in result.evaluations else np.nan
    results = [res for _, res in result.results]
    ref4, ref5 = results[-2], results[-1]
    rows = []
    for out in spec["outputs"]:
        r5 = ref5.indices[ref5.indices["output"] == out]
        r4 = ref4.indices[ref4.indices["output"] == out]
        s1, st = r5["S1"].to_numpy(float), r5["ST"].to_numpy(float)
        spread = float(np.max(np.abs(np.r_[s1 - r4["S1"].to_numpy(float), st - r4["ST"].to_numpy(float)])))
        for (method, opts), res in zip(grid, results[: len(grid)]):
            sub = SobolResult(res.indices[res.indices["output"] == out].reset_index(drop=True), res.n_evals,
                              res.method, res.options, res.diagnostics)
            rows.append({"function": f"direct_drive:{out}", "method": method, "options": _opts(opts),
                         "seed": opts.get("seed", 0), "n_evals": res.n_evals, "wall_s": res.n_evals * per_eval,
                         **errors(sub, s1, st), "source": method, "reference_spread": spread})
    return pd.DataFrame(rows)


def fidelity_rows(duration: float = 60.0, progress: Callable[[str], None] = print) -> pd.DataFrame:
    """Objective-function error of each fidelity and time step against Radau, and seconds per evaluation."""
    import ddgsa.models as models
    from ddgsa.loads import generate
    from ddgsa.loads.scene import Scene

    scene = Scene(wind_speed=11.0, turbulence_intensity=0.12, duration=duration, seed=1)
    generate(scene)
    progress("accuracy: fidelities against solve_ivp(Radau)")
    ref_model = models.get("direct_drive", fidelity="flexible", integrator="Radau")
    t0 = time.perf_counter()
    ref = ref_model.evaluate(None, scene).iloc[0]
    ref_wall = time.perf_counter() - t0
    outputs = [c for c in ref.index if abs(ref[c]) > 0]
    cases = [("linear", None), ("rigid", 0.025), ("rigid", 0.01), ("rigid", 0.005),
             ("flexible", 0.01), ("flexible", 0.005), ("flexible", 0.0025)]
    rows = [{"fidelity": "flexible (Radau rtol 1e-6)", "time_step_s": np.nan, "seconds_per_eval": ref_wall,
             **{f"rel_err_{c}": 0.0 for c in outputs}, "max_rel_error": 0.0}]
    for fidelity, step in cases:
        opts: dict[str, float] = {} if step is None else {"time_step": step}
        model = models.get("direct_drive", fidelity=fidelity, **opts)
        model.evaluate(None, scene.replace(duration=1.0))            # compile outside the timing
        t0 = time.perf_counter()
        got = model.evaluate(None, scene).iloc[0]
        wall = time.perf_counter() - t0
        rel = {f"rel_err_{c}": float(abs(got[c] / ref[c] - 1)) for c in outputs}
        rows.append({"fidelity": fidelity, "time_step_s": np.nan if fidelity == "linear" else opts.get("time_step"),
                     "seconds_per_eval": wall, **rel,
                     "max_rel_error": max(rel.values()),
                     "max_rel_error_damage": max(v for k, v in rel.items() if "damage" in k)})
    return pd.DataFrame(rows)


def plot_fidelity(df: pd.DataFrame) -> Any:
    """Objective-function error against seconds per evaluation, one point per fidelity and step."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 4))
    d = df[df["max_rel_error"] > 0]
    for col, marker, label in (("max_rel_error", "o", "all objectives"), ("max_rel_error_damage", "s", "damage")):
        ax.scatter(d["seconds_per_eval"], d[col].clip(lower=1e-6), marker=marker, label=label)
    for k, r in enumerate(d.itertuples()):
        step = " (exact)" if r.fidelity == "linear" else f" {r.time_step_s * 1e3:g} ms"
        ax.annotate(f"{r.fidelity}{step}", (r.seconds_per_eval, max(r.max_rel_error, 1e-6)), fontsize=7,
                    xytext=(4, 2 + 9 * (k % 3)), textcoords="offset points")
    ref = df[df["max_rel_error"] == 0]["seconds_per_eval"].iloc[0]
    ax.axvline(ref, color="gray", ls=":", label=f"reference Radau ({ref:.0f} s)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("seconds per evaluation (60 s scene, 1 core)")
    ax.set_ylabel("relative error vs Radau")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def run(out: Path = OUT, max_log2: int = 14, seeds: tuple[int, ...] = (0, 1, 2, 3, 4), drive_train: bool = True,
        jobs: int = 2, progress: Callable[[str], None] = print) -> list[Path]:
    """Run the whole benchmark and write its CSVs and charts to ``out``; returns the paths written."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out.mkdir(parents=True, exist_ok=True)
    table = analytic_rows(method_grid(max_log2, seeds), progress)
    if drive_train:
        table = pd.concat([table, drive_train_rows(jobs, out / "evaluations.sqlite", progress)], ignore_index=True)
    written = [out / "accuracy_cost.csv"]
    table.to_csv(written[0], index=False, float_format="%.6g")
    for name, g in table.groupby("function", sort=False):
        fig = plot_function(g, name)
        path = out / f"accuracy_{name.replace(':', '_')}.png"
        fig.savefig(path, dpi=100)
        plt.close(fig)
        written.append(path)
    if drive_train:
        fid = fidelity_rows(progress=progress)
        fid.to_csv(out / "fidelity_cost.csv", index=False, float_format="%.6g")
        fig = plot_fidelity(fid)
        fig.savefig(out / "fidelity_cost.png", dpi=100)
        plt.close(fig)
        written += [out / "fidelity_cost.csv", out / "fidelity_cost.png"]
    return written
