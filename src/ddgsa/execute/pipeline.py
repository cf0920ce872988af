"""Plan -> run -> analyse a validated study (DESIGN.md's flow), without writing files.

:func:`execute` picks the study's kind (:data:`KINDS`: ``gsa``, ``sweep``, ``fault``, one module
each under :mod:`ddgsa.execute.kinds`), lets it plan its points, hands the model runs to
:mod:`ddgsa.runner`, lets the kind analyse them (realisations aggregated; a point with any failed
realisation is refused, never imputed) and returns a :class:`StudyResult` with its provenance,
which :mod:`ddgsa.report.write` writes out.
"""

from __future__ import annotations

import functools
import platform
import subprocess
import sys
import time
from datetime import datetime, timezone
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any, Callable

import numpy as np
import pandas as pd

import ddgsa
from ddgsa.study.checks import study_basis
from ddgsa.execute.confirm import confirmation_table
from ddgsa.errors import DdgsaError
from ddgsa.gsa.base import Design
from ddgsa.execute.kinds.common import (Kind, Plan, Runs, StudyResult, model_id,
                                select_fidelities)
from ddgsa.execute.kinds.fault import FaultKind
from ddgsa.execute.kinds.gsa import GsaKind
from ddgsa.execute.kinds.sweep import SweepKind, SweepResult
from ddgsa.loads import cache as loads_cache
from ddgsa.runner import EvaluationStore, ModelId, Task, local_workers, main_blas_threads
from ddgsa.study.spec import Study, plan_scenes


KINDS: dict[str, Callable[[Study], Kind]] = {"gsa": GsaKind, "sweep": SweepKind, "fault": FaultKind}
"""Each ``spec.kind`` and the class that plans and analyses it."""


def execute(study: Study, store: EvaluationStore, jobs: int | None = None, backend: str | None = None,
            address: str | None = None, quiet: bool = False, evaluate: bool = True,
            retry_failed: bool = False) -> StudyResult:
    """Run (or, with ``evaluate=False``, only read back) all model evaluations and analyse them.

    Wind-load realisations are shared by all workers through files beside the store
    (:mod:`ddgsa.loads.cache`): each is generated once per study, not once per worker process.
    Studies of a model with its own scene type (no wind loads) use no loads cache. The local
    workers are forked once for the study, after the fidelity pilot's warm-up (:func:`ddgsa.runner.local_workers`),
    and while they run this process's BLAS keeps to one thread (:func:`ddgsa.runner.main_blas_threads`).
    ``retry_failed`` runs again the evaluations the store holds as failed (after their cause was fixed)."""
    with (loads_cache.shared(store.path.parent / "loads" if study.wind else None), local_workers(),
          main_blas_threads(jobs or study.spec.run.jobs)):
        return _execute(study, store, jobs, backend, address, quiet, evaluate, retry_failed)


def _execute(study: Study, store: EvaluationStore, jobs: int | None, backend: str | None, address: str | None,
             quiet: bool, evaluate: bool, retry_failed: bool = False) -> StudyResult:
    if study.spec.model.variants:
        return _execute_variants(study, store, jobs=jobs, backend=backend, address=address, quiet=quiet,
                                 evaluate=evaluate, retry_failed=retry_failed)
    t0 = time.perf_counter()
    spec = study.spec
    run = spec.run
    run_opts = {"jobs": jobs or run.jobs, "batch_size": run.batch_size, "backend": backend or run.backend,
                "address": address or run.address, "quiet": quiet, "timeout": run.timeout,
                "setup": functools.partial(loads_cache.set_directory, loads_cache.directory())}
    runs = Runs(store, evaluate, run_opts, retry_failed)
    fidelity_choice: list[dict[str, Any]] = []
    if spec.model.fidelity == "auto":
        fidelity_choice = select_fidelities(study, runs)
        mids = {c["scene"]: model_id(study, c["chosen"]) for c in fidelity_choice}
    else:
        mids = {ps.index: model_id(study) for ps in plan_scenes(study)}
    plan = Plan(study, mids)
    kind = KINDS[spec.kind](study)
    kind.plan(plan)
    runs(plan.tasks)
    kind.run(plan, runs)
    t_eval = time.perf_counter() - t0
    result = kind.analyse(plan, runs)
    result.evaluations = _evaluation_table(store, list(runs.tasks.values()))
    failures: list[dict[str, Any]] = [
        {"key": r["key"], "fidelity": r["fidelity"], "scene": {k: r[k] for k in study.scene_fields + ["seed"]},
         "error": r["error"]} for r in result.evaluations.to_dict("records") if isinstance(r["error"], str)]
    result.provenance = _provenance(study, mids, runs.counts(), t_eval, time.perf_counter() - t0, failures,
                                    kind.designs)
    kind.provenance(result.provenance)
    result.provenance["fidelity_selection"] = fidelity_choice
    result.provenance["sampling"] = _sampling(study)
    result.provenance["basis"] = study_basis(study)
    asked = [c for c in result.evaluations.columns if c in study.outputs]     # only the outputs the study reads
    result.provenance["implausible"] = study.make_model().implausible(result.evaluations[asked])
    result.fidelity = pd.DataFrame([{k: v for k, v in c.items() if k != "errors"} for c in fidelity_choice])
    result.confirmation = confirmation_table(result) if len(result.indices) else None
    return result


def _execute_variants(study: Study, store: EvaluationStore, **kwargs: Any) -> StudyResult:
    """A sweep once per entry of ``model.variants``; the tables gain a ``variant`` column."""
    parts = [(label, execute(sub, store, **kwargs)) for label, sub in study.variants()]
    first = parts[0][1]
    result = SweepResult(study, pd.DataFrame(), pd.DataFrame(), pd.DataFrame(), dict(first.provenance),
                         sweep=pd.concat([r.sweep.assign(variant=label) for label, r in parts], ignore_index=True))
    result.evaluations = pd.concat([r.evaluations.assign(variant=label) for label, r in parts], ignore_index=True)
    prov = result.provenance
    prov["study_sha256"] = study.digest
    prov["evaluations"] = {k: sum(r.provenance["evaluations"][k] for _, r in parts) for k in prov["evaluations"]}
    prov["timings_s"] = {k: round(sum(r.provenance["timings_s"][k] for _, r in parts), 3) for k in prov["timings_s"]}
    prov["failures"] = [{**f, "variant": label} for label, r in parts for f in r.provenance["failures"]]
    result.provenance["variants"] = [label for label, _ in parts]
    result.provenance["sampling"] = [{"variant": label, **row} for label, r in parts for row in r.provenance["sampling"]]
    result.provenance["implausible"] = [f"{label}: {m}" for label, r in parts for m in r.provenance["implausible"]]
    result.fidelity = first.fidelity
    return result


def _evaluation_table(store: EvaluationStore, tasks: list[Task]) -> pd.DataFrame:
    """One row per stored evaluation of ``tasks``: fidelity, scene, point, outputs, failure reason."""
    got = store.get([t.key for t in tasks])
    rows = []
    for task in tasks:
        o = got.get(task.key)
        if o is None:
            continue
        rows.append({"key": task.key, "fidelity": task.model.fidelity, **task.scene, **task.point,
                     **(o.outputs or {}), "error": o.error, "seconds": o.seconds})
    return pd.DataFrame(rows)


def _versions() -> dict[str, str]:
    out = {}
    for pkg in ("ddgsa", "numpy", "scipy", "pandas", "SALib", "chaospy", "numba", "joblib", "pydantic",
                "ruamel.yaml", "matplotlib"):
        try:
            out[pkg] = version(pkg)
        except PackageNotFoundError:
            out[pkg] = "not installed"
    return out


def _sampling(study: Study) -> list[dict[str, Any]]:
    """The model's aliasing-guard table for the study's first scene (nominal parameters)."""
    try:
        return study.make_model().sampling_checks(plan_scenes(study)[0].scenes[0])
    except (DdgsaError, ArithmeticError, RuntimeError, ValueError, np.linalg.LinAlgError) as exc:
        return [{"interval": "-", "verdict": "not checked", "consequence": f"{type(exc).__name__}: {exc}"}]


def code_version() -> dict[str, Any]:
    """The ddgsa version and, in a git checkout, its commit and whether files differ from it."""
    here = Path(__file__).resolve().parent
    out: dict[str, Any] = {"ddgsa": ddgsa.__version__, "commit": None, "modified": None}
    try:
        commit = subprocess.run(["git", "-C", str(here), "rev-parse", "HEAD"], capture_output=True, text=True,
                                timeout=10, check=True).stdout.strip()
        status = subprocess.run(["git", "-C", str(here), "status", "--porcelain", "--untracked-files=no", "--",
                                 str(here)], capture_output=True, text=True, timeout=10, check=True).stdout
    except (OSError, subprocess.SubprocessError):
        return out                                   # an installed copy, no git: the version says it all
    out.update(commit=commit, modified=bool(status.strip()))
    return out


def _provenance(study: Study, mids: dict[int, ModelId], counts: dict[str, int], t_eval: float, t_total: float,
                failures: list[dict[str, Any]], designs: list[tuple[str, Design]]) -> dict[str, Any]:
    sc = study.spec.scenes
    return {
        "study": study.name, "study_sha256": study.digest, "study_file": study.path.name if study.path else None,
        "created_utc": datetime.now(timezone.utc).isoformat(timespec="seconds"), "code": code_version(),
        "kind": study.spec.kind, "model": {**model_id(study).as_dict(),
                                           "per_scene": {i: m.fidelity for i, m in mids.items()}},
        "versions": _versions(), "python": sys.version.split()[0], "platform": platform.platform(),
        "seeds": {"scene_seeds": [sc.seed + r for r in range(sc.realisations)],
                  "methods": {name: d.options.get("seed") for name, d in designs}},
        "evaluations": counts, "timings_s": {"evaluation": round(t_eval, 3), "total": round(t_total, 3)},
        "failures": failures,
    }


def default_out(study: Study) -> Path:
    """Default output folder: ``runs/<study name>`` (ignored by git; ``results/`` holds the curated,
    committed outputs and is written only when asked for with ``--out``)."""
    return Path("runs") / study.name

