"""Scaling benchmark: how wall time grows with model runs, parameters and workers (``ddgsa bench scaling``).

Three measurements of the ``linear`` direct drive on one 60 s turbulent scene (loads warm):

- **runs**: ``n`` evaluations (10^2 ... 10^5, quasi-random points of the paper-C structural space)
  through the runner (SQLite store, batches of 64, 2 loky workers): the fitted exponent of
  ``wall ~ n^p`` above 10^3 runs says whether cost stays proportional to the work;
- **parameters**: a first-order M-DRM analysis (5 Gauss points per parameter, ``5 n + 1`` runs plus
  its 32-point check sample)
  over the first ``n`` of the model's parameters (5 ... 31: the direct drive declares 31, so
  50 is out of its reach), in one process;
- **models**: the same through the runner for the test rig (``hss_rig``, ``linear``, ``paper_a_subsystem``'s
  steady scene) and the geared drive (``indirect_drive``, ``linear``, a 600 s scene), 10^2 ... 10^3 runs of
  points +-10 % around nominal: their cost per run beside the direct drive's;
- **workers**: the same 4 000 runs on 1 and 2 loky workers and on a Dask ``LocalCluster`` of 2
  single-thread workers; parallel efficiency ``t_1 / (k t_k)``. The loky workers are started
  before the timings (joblib reuses them); the Dask cluster is created by each run, as a study
  creates it, so its start-up is in its time.

The chart draws each measurement with its ideal line (proportional to runs, to ``5 n + 1``,
and ``t_1 / k``). Timings depend on the machine and its load; the JSON records both.
"""

from __future__ import annotations

import functools
import json
import os
import platform
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from ddgsa.loads import generate
from ddgsa.loads.scene import Scene

SCENE = Scene(wind_speed=11.0, turbulence_intensity=0.12, duration=60.0, seed=1)
PAPER_C_SPREAD = {"front_bearing_x": 0.1, "rear_bearing_x": 0.1, "k_front_y": 0.2, "k_front_z": 0.2,
                  "k_rear_y": 0.2, "k_rear_z": 0.2, "shaft_bending_stiffness": 0.2, "hub_mass": 0.1,
                  "generator_mass": 0.1, "c_gen": 0.1}


RIG_SPREAD = {"hss_span": 0.1, "hss_diameter": 0.1, "disk_mass": 0.1, "support_stiffness": 0.1}
GEARED_SPREAD = {"k_mount_z": 0.3, "mount_arm": 0.1, "gear_ratio": 0.1, "housing_mass": 0.1}


def _model_scenes() -> dict[str, tuple[Any, dict[str, float]]]:
    """Each measured model's scene and parameter spreads (the direct drive's: :data:`SCENE`)."""
    from ddgsa.models.hss_rig.scenes import RigScene

    return {"direct_drive": (SCENE, PAPER_C_SPREAD),
            "hss_rig": (RigScene("steady", speed_rpm=1500, duration=1.2, sample_rate=2000, settle=0.2, seed=1),
                        RIG_SPREAD),
            "indirect_drive": (Scene(wind_speed=11.0, turbulence_intensity=0.12, duration=600.0, seed=1),
                               GEARED_SPREAD)}


def _points(n: int, seed: int = 0, model: str = "direct_drive") -> list[dict[str, float]]:
    """``n`` scrambled Halton points of ``model``'s space (uniform +- spread around nominal; the
    direct drive's is paper C's structural space)."""
    from scipy.stats import qmc

    import ddgsa.models as models

    spread = _model_scenes()[model][1]
    nominal = models.get(model, fidelity="linear").nominal
    names = list(spread)
    u = qmc.Halton(len(names), seed=seed).random(n)
    x = np.array([nominal[k] for k in names]) * (1 + (2 * u - 1) * np.array([spread[k] for k in names]))
    return [{**nominal, **dict(zip(names, row))} for row in x]


def _run(n: int, jobs: int, backend: str = "loky", model: str = "direct_drive") -> float:
    """Wall seconds of ``n`` linear evaluations of ``model`` through the runner, from an empty store;
    workers share the loads through files as in a study (:mod:`ddgsa.loads.cache`)."""
    from ddgsa.loads import cache
    from ddgsa.execute.kinds.common import make_task, model_evaluator
    from ddgsa.runner import EvaluationStore, ModelId, run_tasks

    mid = ModelId(model, "linear")
    scene = _model_scenes()[model][0]
    tasks = [make_task(mid, scene, p) for p in _points(n, model=model)]
    with tempfile.TemporaryDirectory() as tmp:
        store = EvaluationStore(Path(tmp) / "evaluations.sqlite")
        setup = functools.partial(cache.set_directory, Path(tmp) / "loads")
        t0 = time.perf_counter()
        counts = run_tasks(tasks, store, model_evaluator, jobs=jobs, batch_size=64, backend=backend, quiet=True, setup=setup)
        wall = time.perf_counter() - t0
        store.close()
    if counts["failed"]:
        raise RuntimeError(f"{counts['failed']} of {n} scaling runs failed")
    return wall


def _mdrm(n_params: int) -> tuple[float, int]:
    """Wall seconds and runs of a first-order M-DRM analysis over the first ``n_params`` parameters."""
    import ddgsa
    import ddgsa.models as models

    model = models.get("direct_drive", fidelity="linear")
    names = [p.name for p in model.parameters][:n_params]
    space = ddgsa.ParameterSpace.from_dict({k: {"dist": "uniform", "nominal": model.nominal[k], "spread": 0.05}
                                            for k in names if model.nominal[k] != 0.0}
                                           | {k: {"dist": "uniform", "low": 0.0, "high": 1e9}
                                              for k in names if model.nominal[k] == 0.0})

    def f(x: np.ndarray) -> np.ndarray:
        return model.evaluate(pd.DataFrame(x, columns=space.names), SCENE)[["damage_front"]].to_numpy()

    t0 = time.perf_counter()
    res = ddgsa.sobol(f, space, method="mdrm", points=5)
    return time.perf_counter() - t0, int(res.n_evals)


def scaling(out: Path, quick: bool = False) -> dict[str, Any]:
    """Measure the three scalings, write ``scaling.json`` and ``scaling.png`` to ``out``; return the figures.

    BLAS is single-threaded in this process (one worker = one core, as in the loky workers)."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        return _scaling(out, quick)


def _scaling(out: Path, quick: bool) -> dict[str, Any]:
    generate(SCENE)
    _run(8, 1)                                        # compile / load kernels outside the timings
    _run(64, 2)                                       # start the reusable loky workers outside the timings
    runs = [10, 30, 100] if quick else [100, 1000, 10_000, 100_000]
    params = [5, 10] if quick else [5, 10, 20, 31]
    n_workers_runs = 100 if quick else 4000
    res: dict[str, Any] = {"machine": f"{platform.machine()}, {os.cpu_count()} cores",
                           "python": platform.python_version(), "scene": SCENE.to_dict(), "quick": quick,
                           "load_average": [round(x, 2) for x in os.getloadavg()]}
    res["runs"] = [{"runs": n, "jobs": 2, "wall_s": _run(n, 2)} for n in runs]
    for model in ("hss_rig", "indirect_drive"):
        _run(4, 2, model=model)                       # compile its kernels, generate its loads outside the timings
    res["models"] = [{"model": m, "runs": n, "jobs": 2, "wall_s": _run(n, 2, model=m)}
                     for m in ("hss_rig", "indirect_drive") for n in ([4, 16] if quick else [100, 300, 1000])]
    res["parameters"] = [dict(zip(("parameters", "wall_s", "runs"), (n, *_mdrm(n)))) for n in params]
    workers = [{"backend": "loky", "workers": 1, "wall_s": _run(n_workers_runs, 1)},
               {"backend": "loky", "workers": 2, "wall_s": _run(n_workers_runs, 2)}]
    try:
        workers.append({"backend": "dask LocalCluster", "workers": 2, "wall_s": _run(n_workers_runs, 2, "dask")})
    except RuntimeError as exc:                   # dask not installed: say so in the figures
        workers.append({"backend": "dask LocalCluster", "workers": 2, "wall_s": None, "error": str(exc)})
    t1 = workers[0]["wall_s"]
    for w in workers:
        w["efficiency"] = None if w["wall_s"] is None else t1 / (w["workers"] * w["wall_s"])
    res["workers"] = workers
    res["workers_runs"] = n_workers_runs
    big = [r for r in res["runs"] if r["runs"] >= (30 if quick else 1000)]
    res["runs_exponent"] = float(np.polyfit(np.log([r["runs"] for r in big]), np.log([r["wall_s"] for r in big]), 1)[0])
    res["parameters_exponent"] = float(np.polyfit(np.log([p["runs"] for p in res["parameters"]]),
                                                  np.log([p["wall_s"] for p in res["parameters"]]), 1)[0])
    out.mkdir(parents=True, exist_ok=True)
    (out / "scaling.json").write_text(json.dumps(res, indent=2) + "\n")
    plot(res).savefig(out / "scaling.png", dpi=120, bbox_inches="tight")
    return res


def plot(res: dict[str, Any]) -> Any:
    """Three panels: wall time against runs (the three drive models), parameters and workers, each with
    its ideal line."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
    n = np.array([r["runs"] for r in res["runs"]], dtype=float)
    t = np.array([r["wall_s"] for r in res["runs"]])
    ax = axes[0]
    ax.loglog(n, t, "o-", label=f"direct drive, 60 s scene (exponent {res['runs_exponent']:.2f} above 10^3)")
    ax.loglog(n, t[-1] * n / n[-1], "k--", label="ideal: proportional to runs")
    names = {"hss_rig": "test rig, steady 1.2 s", "indirect_drive": "geared drive, 600 s scene"}
    for k, model in enumerate(names):
        rows = [r for r in res.get("models", []) if r["model"] == model]
        if rows:
            nm, tm = (np.array([r[key] for r in rows], dtype=float) for key in ("runs", "wall_s"))
            per = tm[-1] / nm[-1]
            ax.loglog(nm, tm, "s-", color=f"C{k + 1}", label=f"{names[model]} ({per * 1e3:.0f} ms a run at {nm[-1]:.0f})")
            ax.loglog(nm, per * nm, ":", color=f"C{k + 1}")
    ax.set(xlabel="model runs (linear fidelity, 2 workers)", ylabel="wall time [s]", title="runs")
    ax.legend(fontsize=7)
    ax = axes[1]
    p = np.array([r["parameters"] for r in res["parameters"]], dtype=float)
    tp = np.array([r["wall_s"] for r in res["parameters"]])
    runs = np.array([r["runs"] for r in res["parameters"]], dtype=float)
    ax.plot(p, tp, "o-", label="measured (M-DRM, 5 points, 1 process)")
    ax.plot(p, tp[-1] * runs / runs[-1], "k--", label="ideal: proportional to runs (5 n + 1 + 32 check)")
    ax.set(xlabel="parameters n", ylabel="wall time [s]", title="parameters")
    ax.legend(fontsize=8)
    ax = axes[2]
    ws = [w for w in res["workers"] if w["wall_s"] is not None]
    labels = [f"{w['backend']}\n{w['workers']} worker{'s' if w['workers'] > 1 else ''}" for w in ws]
    ax.bar(range(len(ws)), [w["wall_s"] for w in ws], color="tab:blue", label="measured")
    t1 = res["workers"][0]["wall_s"]
    ax.plot(range(len(ws)), [t1 / w["workers"] for w in ws], "k_", markersize=40, mew=2, label="ideal: t1 / k")
    for i, w in enumerate(ws):
        ax.annotate(f"eff. {w['efficiency']:.0%}", (i, w["wall_s"]), ha="center", va="bottom", fontsize=8)
    ax.set_xticks(range(len(ws)), labels, fontsize=8)
    ax.set(ylabel="wall time [s]", title=f"workers ({res['workers_runs']} runs)")
    ax.legend(fontsize=8)
    fig.suptitle(f"ddgsa scaling ({res['machine']}; load average {res.get('load_average', 'not recorded')} at the start)", fontsize=10)
    return fig


def format_scaling(res: dict[str, Any]) -> str:
    """A plain-text summary of :func:`scaling`'s figures."""
    lines = [f"machine: {res['machine']}" + (" (QUICK sizes)" if res["quick"] else ""),
             "runs:       " + ", ".join(f"{r['runs']}: {r['wall_s']:.2f} s" for r in res["runs"])
             + f"  -> exponent {res['runs_exponent']:.2f}",
             *(f"  {m}: " + ", ".join(f"{r['runs']}: {r['wall_s']:.2f} s" for r in res.get("models", [])
                                       if r["model"] == m) for m in ("hss_rig", "indirect_drive")),
             "parameters: " + ", ".join(f"{r['parameters']} ({r['runs']} runs): {r['wall_s']:.2f} s"
                                        for r in res["parameters"])
             + f"  -> exponent in runs {res['parameters_exponent']:.2f}",
             "workers:    " + ", ".join(f"{w['backend']} x{w['workers']}: "
                                        + ("-" if w["wall_s"] is None else
                                           f"{w['wall_s']:.2f} s (efficiency {w['efficiency']:.0%})")
                                        for w in res["workers"])]
    return "\n".join(lines)
