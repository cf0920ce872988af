"""Plan -> run -> analyse a validated study (DESIGN.md's flow), without writing files.

:func:`execute` pools the designs of all methods per scene, hands the model runs to
:mod:`ddgsa.runner`, aggregates realisations (a point with any failed realisation is refused,
never imputed), runs each method's ``analyze`` and returns a :class:`StudyResult` that
:mod:`ddgsa.report` writes out.
"""

from __future__ import annotations

import functools
import itertools
import platform
import subprocess
import sys
import threading
import time
import warnings
from dataclasses import dataclass, field
from datetime import datetime, timezone
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

import ddgsa
from ddgsa.checks import study_basis
from ddgsa.detection import DetectionSettings, FaultDetectability, add_noise, assess
from ddgsa.errors import DdgsaError, StudyError
from ddgsa.gsa.auto import AutoSobol
from ddgsa.gsa.base import Design, get_method
from ddgsa.gsa.escalate import Escalation
from ddgsa.gsa.givendata import MIN_POINTS as GIVEN_MIN_POINTS, drawn_rows, given_data_s1
from ddgsa.gsa.pooled import pooled_pce
from ddgsa.gsa.trust import DEFAULT_TOLERANCE
from ddgsa.gsa.result import SobolResult
from ddgsa.gsa.target import with_targets
from ddgsa.models import ImplausibleOutputWarning
from ddgsa.models import get as get_model
from ddgsa.models.auto import pilot_choice, pilot_scene
from ddgsa.runner import EvaluationStore, Evaluator, ModelId, Outcome, Task, local_workers, run_tasks, task_key
from ddgsa.space import ParameterSpace
from ddgsa.loads import cache as loads_cache
from ddgsa.loads.scene import Scene
from ddgsa.study import PlannedScene, Study, plan_scenes
from ddgsa.study_signals import analyse_convergence, analyse_signals


@dataclass
class StudyResult:
    """Everything a report needs."""

    study: Study
    indices: pd.DataFrame
    diagnostics: pd.DataFrame
    evaluations: pd.DataFrame
    provenance: dict[str, Any]
    results: list[tuple[PlannedScene, SobolResult]] = field(default_factory=list)
    sweep: pd.DataFrame | None = None
    fault: pd.DataFrame | None = None
    fault_smallest: pd.DataFrame | None = None
    fault_indices: pd.DataFrame | None = None
    fault_detection: list[tuple[PlannedScene, FaultDetectability]] = field(default_factory=list)
    fault_subsets: pd.DataFrame | None = None
    fidelity: pd.DataFrame | None = None
    moments: pd.DataFrame | None = None
    """Per scene and output: ``mean``, ``std``, ``cv`` (std / |mean|) and their ``source``."""
    signal_indices: pd.DataFrame | None = None
    """Per scene, method, signal, bin and parameter: indices and the bin's variance (:mod:`ddgsa.study_signals`)."""
    signal_generalised: pd.DataFrame | None = None
    """Per scene, method, signal and parameter: the variance-weighted (generalised) indices."""
    convergence: pd.DataFrame | None = None
    """Per scene, method, output and parameter: indices against runs on nested sub-samples."""

    def to_xarray(self) -> Any:
        """Indices, bounds, flags, moments and fault statistics as an :class:`xarray.Dataset` with
        dimensions (scene, output, parameter, method[, fault_level]), the scene fields as coordinates
        and CF-style units and meanings (:func:`ddgsa.export.to_dataset`)."""
        from ddgsa.export import to_dataset

        model = self.study.make_model()
        units = {o: model.output(o).unit for o in self.study.outputs if o in model.outputs}
        return to_dataset(self.indices, self.study.scene_fields, self.moments, self.fault, self.fault_indices,
                          self.diagnostics, {"study": self.study.name, "model": self.study.spec.model.name}, units)

    def __repr__(self) -> str:
        return (f"StudyResult(study={self.study.name!r}, {len(self.indices)} index rows, "
                f"{len(self.evaluations)} evaluations)")

    def _repr_html_(self) -> str:
        """The study's indices as an HTML table in Jupyter (untrusted rows shaded)."""
        from ddgsa.notebook import result_html

        ev = self.provenance.get("evaluations", {})
        facts = [f"model {self.study.spec.model.name} ({self.study.spec.model.fidelity}), "
                 f"{ev.get('total', '?')} evaluations, {ev.get('failed', '?')} failed"]
        if len(self.indices):
            bad = self.indices[~self.indices["trusted"].astype(bool)]
            facts.append("every row trusted" if bad.empty else
                         f"{len(bad)} of {len(self.indices)} rows untrusted (outputs: {', '.join(bad['output'].unique())})")
        return result_html(f"study {self.study.name}", facts, self.indices)


SAMPLE_DESIGNS = ("saltelli", "fast", "rbd_fast", "pce")
"""Methods whose every design point is a draw from the input distribution (pce unless fitted by quadrature)."""


def moments(space: ParameterSpace, name: str, design: Design, y: np.ndarray, res: SobolResult,
            outputs: list[str]) -> list[dict[str, Any]] | None:
    """Mean and standard deviation of each output from one method's evaluations (``n``: the sample
    size, 0 for a surrogate's moments), or None. The study reports those of the largest sample.

    A sampling design (Saltelli, FAST, RBD-FAST, PCE regression) gives the sample moments of all
    its points; M-DRM those of its quasi-random check sample, or without one its own surrogate's
    moments (``h_c^(1-n) prod rho_i``, ``h_c^(2(1-n)) prod theta_i``; exact for products).
    """
    finite = np.isfinite(y).all(axis=1)
    if name in SAMPLE_DESIGNS and design.options.get("fit") != "quadrature":
        sample, source = y[finite], f"{name} sample ({_count(finite)})"
    elif name == "mdrm" and design.options.get("check"):
        check = y[-design.options["check"]:]
        ok = np.isfinite(check).all(axis=1)
        sample, source = check[ok], f"M-DRM check sample ({_count(ok)})"
    elif name == "mdrm" and "rho" in res.extras:
        n = space.dim
        h_c, rho, theta = res.extras["h_cut"], res.extras["rho"], res.extras["theta"]     # (k,), (k, n), (k, n)
        with np.errstate(all="ignore"):
            mean = h_c ** (1 - n) * np.prod(rho, axis=1)
            var = h_c ** (2 * (1 - n)) * np.prod(theta, axis=1) - mean ** 2
        return [{"output": o, "mean": float(mean[j]), "std": float(np.sqrt(max(var[j], 0.0))),
                 "source": "M-DRM surrogate", "n": 0} for j, o in enumerate(outputs)]
    else:
        return None
    if len(sample) < 2:
        return None
    return [{"output": o, "mean": float(sample[:, j].mean()), "std": float(sample[:, j].std(ddof=1)),
             "source": source, "n": len(sample)} for j, o in enumerate(outputs)]


def auto_moments(res: SobolResult, outputs: list[str]) -> list[dict[str, Any]]:
    """Mean and standard deviation of each output over the points ``method: auto`` drew from the
    input distribution (its check sample, PCE and Saltelli points; :mod:`ddgsa.gsa.auto`)."""
    m = res.extras["moments"]
    return [{"output": o, "mean": float(m["mean"][j]), "std": float(m["std"][j]),
             "source": f"auto sample ({m['n']} of {m['drawn']} points)" if m["n"] < m["drawn"]
             else f"auto sample ({m['n']} points)", "n": m["n"]} for j, o in enumerate(outputs)]


def _count(finite: np.ndarray) -> str:
    """``64 points``, or ``50 of 64 points (failed ones left out)``."""
    n, ok = len(finite), int(finite.sum())
    return f"{n} points" if ok == n else f"{ok} of {n} points, failed ones left out"


def model_id(study: Study, fidelity: str | None = None) -> ModelId:
    """The runner's model identity for the study (at ``fidelity`` when given)."""
    spec = study.spec.model
    return ModelId(spec.name, fidelity or spec.fidelity, tuple(sorted(spec.options.items())),
                   tuple(study.spec.signals))


def model_evaluator(mid: ModelId) -> Evaluator:
    """The runner's model factory: the registered model's ``evaluate``, scenes given as dicts.
    Implausible outputs are not warned per batch: the study reports them once, over all evaluations."""
    model = get_model(mid.name, fidelity=mid.fidelity, **dict(mid.options))
    scene_type = getattr(model, "scene_type", Scene)

    def evaluate(points: pd.DataFrame, scene: dict[str, Any]) -> pd.DataFrame:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ImplausibleOutputWarning)
            return model.evaluate(points, scene_type(**scene), signals=mid.signals)

    return evaluate


def make_task(mid: ModelId, scene: Any, point: dict[str, float]) -> Task:
    """The runner's task for one point of one scene realisation."""
    fields = scene.to_dict()
    return Task(task_key(mid, fields, point, ddgsa.__version__), mid, fields, point)


SLOW_FIRST_S = 3.0
"""A first evaluation longer than this [s] is explained on screen (kernel compilation)."""


class Runs:
    """Every model evaluation a study asks for, counted once per unique evaluation.

    Each call hands tasks to the runner (when ``evaluate``); :meth:`counts` gives the figures
    the CLI line, ``summary.md`` and ``provenance.json`` all print: ``total`` unique
    evaluations, ``evaluated`` (run now), ``cached`` (found in the store), ``failed`` (of all,
    with stored reasons) and ``failed_now``.
    """

    def __init__(self, store: EvaluationStore, evaluate: bool, run_opts: dict[str, Any]) -> None:
        self.store, self.evaluate, self.run_opts = store, evaluate, run_opts
        self.tasks: dict[str, Task] = {}
        self.evaluated = self.failed_now = 0
        self._warm: set[ModelId] = set()

    def __call__(self, tasks: list[Task]) -> None:
        """Evaluate what the store lacks of ``tasks``."""
        self.tasks.update((t.key, t) for t in tasks)
        if not self.evaluate:
            return
        self._warm_up(tasks)
        self._run(tasks, self.run_opts)

    def _run(self, tasks: list[Task], opts: dict[str, Any]) -> None:
        got = run_tasks(tasks, self.store, model_evaluator, **opts)
        self.evaluated += got["evaluated"]
        self.failed_now += got["failed"]

    def _warm_up(self, tasks: list[Task]) -> None:
        """One evaluation per model in this process before the parallel workers start. A first
        run after installing compiles the model's numba kernels here (cached on disk, so the
        workers load them instead of each compiling them again; forked workers inherit them
        loaded, :mod:`ddgsa.runner`); when that takes longer than
        :data:`SLOW_FIRST_S`, the user is told what is happening and then how long it took."""
        missing = {t.key for t in tasks} - self.store.known(t.key for t in tasks)
        first: dict[ModelId, Task] = {}
        for t in tasks:
            if t.key in missing and t.model not in self._warm:
                first.setdefault(t.model, t)
        quiet = self.run_opts.get("quiet", False)
        for mid, task in first.items():
            self._warm.add(mid)
            note = threading.Timer(SLOW_FIRST_S, print, args=(
                f"{mid.name} ({mid.fidelity}): first evaluation, compiling the model's kernels (a first run after "
                "installing only: one to two minutes on 2 cores; later runs load them from the cache)...",),
                kwargs={"file": sys.stderr, "flush": True})
            if not quiet:
                note.start()
            t0 = time.perf_counter()
            try:
                self._run([task], {**self.run_opts, "jobs": 1, "backend": "loky", "quiet": True})
            finally:
                note.cancel()
            if not quiet and time.perf_counter() - t0 > SLOW_FIRST_S:
                print(f"{mid.name} ({mid.fidelity}): kernels ready after {time.perf_counter() - t0:.0f} s",
                      file=sys.stderr, flush=True)

    def counts(self) -> dict[str, int]:
        """Unique evaluations asked for, run now, found in the store, failed (all and now)."""
        got = self.store.get(self.tasks)
        total = len(self.tasks)
        return {"total": total, "evaluated": self.evaluated, "cached": total - self.evaluated,
                "failed": sum(o.outputs is None for o in got.values()), "failed_now": self.failed_now}


def select_fidelities(study: Study, runs: Runs) -> list[dict[str, Any]]:
    """``fidelity: auto``: per scene, the cheapest fidelity whose pilot outputs stay within tolerance.

    The pilot set is the nominal point plus ``model.auto.pilot`` scrambled-Sobol' points of the
    space, in the first realisation of each scene (its seed, on a record of at most
    :data:`ddgsa.models.auto.PILOT_DURATION_S`), at every fidelity of the model (of its
    ``pilot_fidelities`` where it declares them). Errors are
    the largest relative deviation over pilot points and study outputs from the richest
    fidelity (the model's first); cost is the model's deterministic cost model
    (:meth:`ddgsa.models.Model.fidelity_cost`), never measured time, so the choice is the same on
    any machine and load. Measured seconds are recorded beside it for information.
    """
    auto = study.spec.model.auto
    model = get_model(study.spec.model.name)
    fidelities = list(model.pilot_pool())
    space = study.space
    names = space.names if space is not None else ()
    pilot = np.zeros((1, 0)) if space is None else np.vstack(
        [[space.nominal[n] for n in names], space.sample(auto.pilot, seed=auto.seed, rule="sobol")])
    pts = _points(study, pilot, names)
    outputs = study.outputs
    tasks, plan = [], []
    for ps in plan_scenes(study):
        scene = pilot_scene(ps.scenes[0])
        for fid in fidelities:
            mid = model_id(study, fid)
            ts = [make_task(mid, scene, p) for p in pts]
            tasks += ts
            plan.append((ps, fid, ts))
    runs(tasks)
    got = runs.store.get([t.key for t in tasks])
    if len(got) < len({t.key for t in tasks}):
        raise StudyError("pilot evaluations for fidelity: auto are not in the store; run the study first")
    choices = []
    for ps in plan_scenes(study):
        table = {fid: [got[t.key] for t in ts] for p_, fid, ts in plan if p_.index == ps.index}
        values = {fid: np.array([[o.outputs[n] if o.outputs else np.nan for n in outputs] for o in table[fid]])
                  for fid in fidelities}
        entry = {"scene": ps.index, **ps.fields, **pilot_choice(model, values, outputs, auto.tolerance),
                 "pilot_duration_s": pilot_scene(ps.scenes[0]).duration}
        entry.update({f"measured_s_per_eval_{fid}": round(float(np.mean([o.seconds for o in table[fid]])), 4)
                      for fid in fidelities})
        choices.append(entry)
    return choices


def _points(study: Study, x: np.ndarray, names: tuple[str, ...]) -> list[dict[str, float]]:
    fixed = dict(study.spec.fixed)
    return [{**fixed, **{n: float(v) for n, v in zip(names, row)}} for row in x]


class _Plan:
    """Tasks of a study and how to read values back per scene (each scene may use its own fidelity)."""

    def __init__(self, study: Study, mids: dict[int, ModelId]) -> None:
        self.study, self.mids = study, mids
        self.scenes = plan_scenes(study)
        self.tasks: list[Task] = []
        self.blocks: dict[str, tuple[np.ndarray, tuple[str, ...]]] = {}
        self.auto_points: dict[int, list[tuple[np.ndarray, np.ndarray]]] = {}
        """Per scene, the points and aggregated values each ``auto`` method ran (``confirm`` pools them)."""

    def task(self, ps: PlannedScene, scene: Any, point: dict[str, float]) -> Task:
        """The task of one point in one realisation of a planned scene."""
        return make_task(self.mids[ps.index], scene, point)

    def add_block(self, name: str, x: np.ndarray, names: tuple[str, ...]) -> None:
        """Points (n, len(names)) to evaluate in every scene and realisation."""
        self.blocks[name] = (x, names)
        pts = _points(self.study, x, names)
        for ps in self.scenes:
            for scene in ps.scenes:
                self.tasks += [self.task(ps, scene, p) for p in pts]

    def values(self, store: EvaluationStore, block: str, ps: PlannedScene, outputs: list[str],
               aggregate: str) -> np.ndarray:
        """Aggregated values (n_points, n_outputs) of a block in one scene; NaN where any realisation failed."""
        x, names = self.blocks[block]
        return self.values_at(store, x, names, ps, outputs, aggregate)

    def values_at(self, store: EvaluationStore, x: np.ndarray, names: tuple[str, ...], ps: PlannedScene,
                  outputs: list[str], aggregate: str) -> np.ndarray:
        """Aggregated values (n_points, n_outputs) at points ``x`` in one scene; NaN where any realisation failed."""
        arr = self.realisations_at(store, x, names, ps, outputs)
        agg = {"mean": np.mean, "median": np.median, "max": np.max}[aggregate]
        return agg(arr, axis=0)

    def realisations_at(self, store: EvaluationStore, x: np.ndarray, names: tuple[str, ...], ps: PlannedScene,
                        outputs: list[str]) -> np.ndarray:
        """Values (n_realisations, n_points, n_outputs) at points ``x`` in one scene; NaN where one failed."""
        pts = _points(self.study, x, names)
        per_real = []
        for scene in ps.scenes:
            keys = [self.task(ps, scene, p).key for p in pts]
            got = store.get(keys)
            missing = [k for k in keys if k not in got]
            if missing:
                raise StudyError(f"{len(missing)} evaluations of scene {ps.fields} are not in the store; "
                                 "run the study first (ddgsa run)")
            rows = []
            for k in keys:
                o: Outcome = got[k]
                if o.outputs is None:              # failures are listed in provenance, never imputed
                    rows.append([np.nan] * len(outputs))
                else:
                    rows.append([o.outputs[name] for name in outputs])
            per_real.append(rows)
        values = np.asarray(per_real, dtype=float).reshape(len(per_real), len(pts), len(outputs))
        return values * self.study.output_factors(outputs)            # (n_real, n_points, n_out)


def _designs(study: Study, space: ParameterSpace | None = None) -> list[tuple[str, Design]]:
    """The fixed designs of the study's methods over ``space`` (default: the study's; ``auto`` chooses
    its points as it goes)."""
    space = space or study.space
    assert space is not None
    return [(m.method, get_method(m.method).design(space, **m.options)) for m in study.spec.methods
            if m.method != "auto"]


def _run_auto(plan: _Plan, runs: Runs, outputs: list[str], options: dict[str, Any]) -> list[SobolResult]:
    """``method: auto`` in every scene at once: each stage's points of all scenes go to the runner together."""
    study = plan.study
    assert study.space is not None
    names, aggregate = study.space.names, study.spec.scenes.aggregate
    autos = [AutoSobol(study.space, outputs, **options) for _ in plan.scenes]
    pending = {i: a.start() for i, a in enumerate(autos)}
    while pending:
        tasks = [plan.task(plan.scenes[i], scene, p) for i, x in pending.items()
                 for scene in plan.scenes[i].scenes for p in _points(study, x, names)]
        plan.tasks += tasks
        runs(tasks)
        nxt = {}
        for i, x in pending.items():
            new = autos[i].feed(plan.values_at(runs.store, x, names, plan.scenes[i], outputs, aggregate))
            if new is not None:
                nxt[i] = new
        pending = nxt
    for i, a in enumerate(autos):
        plan.auto_points.setdefault(i, []).append((a.x, a.y))
    results = [a.result for a in autos]
    assert all(r is not None for r in results)             # every state machine finishes with a result
    return results  # type: ignore[return-value]


def execute(study: Study, store: EvaluationStore, jobs: int | None = None, backend: str | None = None,
            address: str | None = None, quiet: bool = False, evaluate: bool = True) -> StudyResult:
    """Run (or, with ``evaluate=False``, only read back) all model evaluations and analyse them.

    Wind-load realisations are shared by all workers through files beside the store
    (:mod:`ddgsa.loads.cache`): each is generated once per study, not once per worker process.
    Studies of a model with its own scene type (no wind loads) use no loads cache. The local
    workers are forked once for the study, after the fidelity pilot's warm-up (:func:`ddgsa.runner.local_workers`)."""
    with loads_cache.shared(store.path.parent / "loads" if study.wind else None), local_workers():
        return _execute(study, store, jobs, backend, address, quiet, evaluate)


def _execute(study: Study, store: EvaluationStore, jobs: int | None, backend: str | None, address: str | None,
             quiet: bool, evaluate: bool) -> StudyResult:
    if study.spec.model.variants:
        return _execute_variants(study, store, jobs=jobs, backend=backend, address=address, quiet=quiet,
                                 evaluate=evaluate)
    t0 = time.perf_counter()
    spec = study.spec
    run = spec.run
    run_opts = {"jobs": jobs or run.jobs, "batch_size": run.batch_size, "backend": backend or run.backend,
                "address": address or run.address, "quiet": quiet,
                "setup": functools.partial(loads_cache.set_directory, loads_cache.directory())}
    runs = Runs(store, evaluate, run_opts)
    fidelity_choice: list[dict[str, Any]] = []
    if spec.model.fidelity == "auto":
        fidelity_choice = select_fidelities(study, runs)
        mids = {c["scene"]: model_id(study, c["chosen"]) for c in fidelity_choice}
    else:
        mids = {ps.index: model_id(study) for ps in plan_scenes(study)}
    plan = _Plan(study, mids)
    outputs = study.outputs
    designs: list[tuple[str, Design]] = []
    if spec.kind == "sweep":
        plan.add_block("nominal", *_grid(study))
    else:
        designs = _designs(study)
        assert study.space is not None
        pooled = np.unique(np.vstack([d.points for _, d in designs] + [np.zeros((0, study.space.dim))]), axis=0)
        plan.add_block("gsa", pooled, study.space.names)
        if spec.kind == "fault":
            _add_fault_blocks(study, plan)
    runs(plan.tasks)
    auto = [_run_auto(plan, runs, outputs, m.options) for m in spec.methods if m.method == "auto"]
    t_eval = time.perf_counter() - t0
    result = StudyResult(study, pd.DataFrame(), pd.DataFrame(), pd.DataFrame(), {})
    failures: list[dict[str, Any]] = []
    confirm_log: list[dict[str, Any]] = []
    if spec.kind == "sweep":
        result.sweep = _sweep_table(plan, store, outputs)
    else:
        _analyse(plan, store, designs, outputs, result, auto)
        if spec.confirm is not None:
            confirm_log = _confirm(plan, runs, designs, outputs, result)
        _signals_and_convergence(plan, store, designs, outputs, result)
        if spec.kind == "fault":
            _fault_verdicts(plan, store, outputs, result)
    result.evaluations = _evaluation_table(store, list(runs.tasks.values()))
    failures += [{"key": r["key"], "fidelity": r["fidelity"], "scene": {k: r[k] for k in study.scene_fields + ["seed"]},
                  "error": r["error"]} for r in result.evaluations.to_dict("records") if isinstance(r["error"], str)]
    result.provenance = _provenance(study, mids, runs.counts(), t_eval, time.perf_counter() - t0, failures, designs)
    if confirm_log:
        result.provenance["confirm"] = confirm_log
    if spec.kind == "fault":
        result.provenance["seeds"]["fault"] = fault_seed(study)
    result.provenance["fidelity_selection"] = fidelity_choice
    result.provenance["sampling"] = _sampling(study)
    result.provenance["basis"] = study_basis(study)
    asked = [c for c in result.evaluations.columns if c in outputs]     # only the outputs the study reads
    result.provenance["implausible"] = study.make_model().implausible(result.evaluations[asked])
    result.fidelity = pd.DataFrame([{k: v for k, v in c.items() if k != "errors"} for c in fidelity_choice])
    return result


def _analyse(plan: _Plan, store: EvaluationStore, designs: list[tuple[str, Design]], outputs: list[str],
             result: StudyResult, auto: list[list[SobolResult]]) -> None:
    study = plan.study
    assert study.space is not None
    pooled, _ = plan.blocks["gsa"]
    rows, diag_rows, moment_rows = [], [], []
    raw = outputs
    for k, ps in enumerate(plan.scenes):
        y, outputs = with_targets(plan.values(store, "gsa", ps, raw, study.spec.scenes.aggregate), raw, study.targets)
        ys = [y[_row_index(pooled, design.points)] for _, design in designs]
        scene_results = [get_method(name).analyze(study.space, design, yd, outputs=outputs)
                         for (name, design), yd in zip(designs, ys)]
        scene_results += pooled_crosscheck(study, designs, pooled, y, outputs)
        found = [m for m in (moments(study.space, name, design, yd, res, outputs)
                             for (name, design), yd, res in zip(designs, ys, scene_results)) if m]
        found += [auto_moments(per_scene[k], outputs) for per_scene in auto]
        for m in max(found, key=lambda ms: ms[0]["n"], default=[]):          # the largest sample
            m["cv"] = m["std"] / abs(m["mean"]) if m["mean"] else float("inf")
            moment_rows.append({"scene": ps.index, **m})
        for res in scene_results + [per_scene[k] for per_scene in auto]:
            _add_result(study, ps, res, result, rows, diag_rows)
    result.indices = pd.concat(rows, ignore_index=True)
    result.moments = pd.DataFrame(moment_rows, columns=["scene", "output", "mean", "std", "cv", "source", "n"])
    result.diagnostics = (pd.concat(diag_rows, ignore_index=True) if diag_rows else
                          pd.DataFrame(columns=["scene", "method", "name", "severity", "output", "parameter",
                                                "value", "message"]))


def _signals_and_convergence(plan: _Plan, store: EvaluationStore, designs: list[tuple[str, Design]],
                             outputs: list[str], result: StudyResult) -> None:
    """Indices of the study's signals and the convergence curves of its outputs (:mod:`ddgsa.study_signals`)."""
    study = plan.study
    pooled, names = plan.blocks["gsa"]
    rows = [_row_index(pooled, d.points) for _, d in designs]
    pts = _points(study, pooled, names)
    result.signal_indices, result.signal_generalised = analyse_signals(
        study, plan.scenes, lambda ps, scene: [plan.task(ps, scene, p).key for p in pts], store, designs, rows)
    result.convergence = analyse_convergence(
        study, plan.scenes, lambda ps: plan.values(store, "gsa", ps, outputs, study.spec.scenes.aggregate),
        designs, rows, outputs)


def _add_result(study: Study, ps: PlannedScene, res: SobolResult, result: StudyResult, rows: list[pd.DataFrame],
                diag_rows: list[pd.DataFrame]) -> None:
    """One scene's result: kept, its table with the scene fields, its diagnostics."""
    result.results.append((ps, res))
    table = res.to_frame()
    for key, v in ps.fields.items():
        table.insert(0, key, v)
    table.insert(0, "scene", ps.index)
    table.insert(0, "study", study.name)
    rows.append(table)
    d = res.diagnostics_frame()
    if len(d):
        d.insert(0, "method", res.method)
        d.insert(0, "scene", ps.index)
        diag_rows.append(d)


def _confirm(plan: _Plan, runs: Runs, designs: list[tuple[str, Design]], outputs: list[str],
             result: StudyResult) -> list[dict[str, Any]]:
    """``confirm: {budget}``: per scene, an :class:`~ddgsa.gsa.escalate.Escalation` from every point
    of the scene (every design, ``auto``'s stages included, each point once) and every result there; each stage's points of all scenes go to the runner together. The
    escalations' results are added beside the methods'; returns their logs (provenance ``confirm``)."""
    study = plan.study
    spec = study.spec.confirm
    assert study.space is not None and spec is not None
    names, aggregate = study.space.names, study.spec.scenes.aggregate
    pooled, _ = plan.blocks["gsa"]
    tol = min([d.options.get("tolerance", DEFAULT_TOLERANCE) for _, d in designs] or [DEFAULT_TOLERANCE])
    salt = next((d for name, d in designs if name == "saltelli"), None)
    escs, pending = [], {}
    for i, ps in enumerate(plan.scenes):
        y = plan.values(runs.store, "gsa", ps, outputs, aggregate)
        have = [r for p_, r in result.results if p_.index == ps.index]
        x_all = np.vstack([pooled] + [ax for ax, _ in plan.auto_points.get(i, [])])
        y_all = np.vstack([y] + [ay for _, ay in plan.auto_points.get(i, [])])
        _, first = np.unique(x_all, axis=0, return_index=True)     # a point twice would flatter the LOO error
        keep = np.sort(first)
        esc = Escalation(study.space, outputs, spec.budget, x_all[keep], y_all[keep], have, tol, seed=spec.seed,
                         saltelli=None if salt is None else (salt, y[_row_index(pooled, salt.points)]))
        escs.append(esc)
        x = esc.start()
        if x is not None:
            pending[i] = x
    while pending:
        tasks = [plan.task(plan.scenes[i], scene, p) for i, x in pending.items()
                 for scene in plan.scenes[i].scenes for p in _points(study, x, names)]
        plan.tasks += tasks
        runs(tasks)
        pending = {i: nxt for i, x in pending.items() if (nxt := escs[i].feed(
            plan.values_at(runs.store, x, names, plan.scenes[i], outputs, aggregate))) is not None}
    rows, diag_rows = [result.indices], [result.diagnostics] if len(result.diagnostics) else []
    for ps, esc in zip(plan.scenes, escs):
        for res in esc.stages:
            _add_result(study, ps, res, result, rows, diag_rows)
    result.indices = pd.concat(rows, ignore_index=True)
    if diag_rows:
        result.diagnostics = pd.concat(diag_rows, ignore_index=True)
    return [{"scene": ps.index, "budget": spec.budget, "spent": esc.spent, "log": esc.log}
            for ps, esc in zip(plan.scenes, escs)]


def pooled_crosscheck(study: Study, designs: list[tuple[str, Design]], x: np.ndarray, y: np.ndarray,
                      outputs: list[str]) -> list[SobolResult]:
    """The cross-checks at zero extra runs: the sparse PCE on every point of the scene
    (:mod:`ddgsa.gsa.pooled`), when it is not one of the study's own methods again (the study has
    M-DRM, whose cut lines no sampling method uses, or several designs); and the given-data first-order
    indices on every drawn point (:mod:`ddgsa.gsa.givendata`). None for dependent inputs (both
    assume independent ones)."""
    assert study.space is not None
    if not designs or study.space.dependent:
        return []
    tol = min(d.options.get("tolerance", DEFAULT_TOLERANCE) for _, d in designs)
    out = []
    if not (len(designs) == 1 and designs[0][0] != "mdrm"):
        res = pooled_pce(study.space, x, y, outputs, tol)
        if res is not None:
            out.append(res)
    drawn = np.unique(np.vstack([d.points[drawn_rows(d)] for _, d in designs]), axis=0)
    if len(drawn) < GIVEN_MIN_POINTS:                  # e.g. M-DRM without a check sample
        return out
    given = given_data_s1(study.space, drawn, y[_row_index(x, drawn)], outputs, tol)
    return out + ([given] if given is not None else [])


def _row_index(pooled: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Row of ``pooled`` (sorted unique rows) that equals each row of ``points``."""
    lookup = {row.tobytes(): i for i, row in enumerate(pooled)}
    return np.array([lookup[row.tobytes()] for row in np.ascontiguousarray(points)])


def _grid(study: Study) -> tuple[np.ndarray, tuple[str, ...]]:
    """The sweep's parameter points: the full factorial of ``grid`` (one empty point without one)."""
    grid = study.spec.grid
    if not grid:
        return np.zeros((1, 0)), ()
    return np.array(list(itertools.product(*grid.values())), dtype=float), tuple(grid)


def _sweep_table(plan: _Plan, store: EvaluationStore, outputs: list[str]) -> pd.DataFrame:
    rows = []
    x, names = plan.blocks["nominal"]
    for ps in plan.scenes:
        for r, scene in enumerate(ps.scenes):
            for row, point in zip(x, _points(plan.study, x, names)):
                o = store.get([plan.task(ps, scene, point).key])
                if not o:
                    raise StudyError("sweep evaluations are not in the store; run the study first (ddgsa run)")
                out = next(iter(o.values()))
                vals = dict(zip(outputs, np.array([(out.outputs or {}).get(name, np.nan) for name in outputs])
                                * plan.study.output_factors(outputs)))
                rows.append({"scene": ps.index, **ps.fields, **dict(zip(names, row)), "realisation": r,
                             "seed": scene.seed, **{name: vals[name] for name in outputs}, "error": out.error})
    return pd.DataFrame(rows)


def _execute_variants(study: Study, store: EvaluationStore, **kwargs: Any) -> StudyResult:
    """A sweep once per entry of ``model.variants``; the tables gain a ``variant`` column."""
    parts = [(label, execute(sub, store, **kwargs)) for label, sub in study.variants()]
    first = parts[0][1]
    result = StudyResult(study, pd.DataFrame(), pd.DataFrame(), pd.DataFrame(), dict(first.provenance))
    result.sweep = pd.concat([r.sweep.assign(variant=label) for label, r in parts], ignore_index=True)
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


def _fault_space(study: Study) -> tuple[ParameterSpace, str]:
    assert study.space is not None and study.spec.fault is not None
    name = study.spec.fault.parameter
    others = [p for p in study.space.parameters if p.name != name]
    if not others:
        raise StudyError("a fault study needs uncertain parameters besides the fault parameter")
    return ParameterSpace.from_parameters(others), name


def fault_seed(study: Study) -> int:
    """Root seed of a fault study's samples, noise and bootstrap (``fault.seed``, else ``scenes.seed``)."""
    fault = study.spec.fault
    assert fault is not None
    return study.spec.scenes.seed if fault.seed is None else fault.seed


def _fault_stream(study: Study, *key: int) -> np.random.SeedSequence:
    """The seed stream of one use: 0 the sample, 1 noise (scene, level, output), 2 bootstrap (scene)."""
    return np.random.SeedSequence(fault_seed(study), spawn_key=key)


def _fault_levels(study: Study) -> list[float]:
    fault = study.spec.fault
    assert fault is not None
    return [fault.healthy, *fault.levels]


def _add_fault_blocks(study: Study, plan: _Plan) -> None:
    """Per fault level: the detection sample over the other parameters, and each method's design over them."""
    fault = study.spec.fault
    assert fault is not None
    others, name = _fault_space(study)
    base = others.sample(fault.samples, seed=_fault_stream(study, 0), rule="sobol")
    designs = _designs(study, others)
    for level in _fault_levels(study):
        plan.add_block(f"fault:{level!r}", np.column_stack([base, np.full(len(base), level)]), (*others.names, name))
        for method, design in designs:
            x = np.column_stack([design.points, np.full(len(design.points), level)])
            plan.add_block(f"fault:{method}:{level!r}", x, (*others.names, name))


def _fault_measurements(plan: _Plan, store: EvaluationStore, ps: PlannedScene, level: float, k: int,
                        outputs: list[str]) -> pd.DataFrame:
    """One row per (point, realisation) -- each realisation one measurement -- with measurement noise."""
    fault = plan.study.spec.fault
    assert fault is not None
    x, names = plan.blocks[f"fault:{level!r}"]
    arr = plan.realisations_at(store, x, names, ps, outputs)            # (n_real, n_points, n_out)
    y = arr.transpose(1, 0, 2).reshape(-1, len(outputs))              # point-major rows
    for j, out in enumerate(outputs):
        noise = fault.noise.get(out)
        if noise is not None:
            y[:, j] = add_noise(y[:, j], noise.absolute, noise.relative, _fault_stream(plan.study, 1, ps.index, k, j))
    return pd.DataFrame(y, columns=outputs)


def _fault_design(study: Study, pops: dict[float, pd.DataFrame]) -> tuple[np.ndarray, dict[float, pd.DataFrame]]:
    """The measurements each level's statistics compare, and their units (point, wind records).

    ``population`` (default): each (point, realisation) is one measurement; every level rests on
    the same points and records (common random numbers), which :mod:`ddgsa.detection` never
    compares with each other. ``paired`` (one turbine against its own baseline): each measurement
    is the change of a point's output from its healthy record ``r`` to its record ``r + 1`` (mod the
    realisations) -- healthy in the healthy population, faulty in the faulty ones.
    """
    fault = study.spec.fault
    assert fault is not None
    n_points, n_real = fault.samples, study.spec.scenes.realisations
    point, real = np.repeat(np.arange(n_points), n_real), np.tile(np.arange(n_real), n_points)
    if fault.design == "population":
        return np.column_stack([point, real]), pops
    nxt = point * n_real + (real + 1) % n_real              # row of the same point's next record
    base = pops[fault.healthy].to_numpy(float)
    paired = {lev: pd.DataFrame(frame.to_numpy(float)[nxt] - base, columns=frame.columns)
              for lev, frame in pops.items()}
    return np.column_stack([point, real, (real + 1) % n_real]), paired


def _fault_verdicts(plan: _Plan, store: EvaluationStore, outputs: list[str], result: StudyResult) -> None:
    """Detection statistics per scene, fault level and output (and combined), the smallest detectable
    fault, and paper A's view: Sobol indices of the other parameters per fault level."""
    study = plan.study
    fault = study.spec.fault
    assert fault is not None
    settings = DetectionSettings(fault.false_alarm, fault.pod_target, fault.confidence, fault.bootstrap)
    levels = _fault_levels(study)
    indices = result.indices
    rows, smallest, subsets = [], [], []
    for ps in plan.scenes:
        pops = {lev: _fault_measurements(plan, store, ps, lev, k, outputs) for k, lev in enumerate(levels)}
        units, pops = _fault_design(study, pops)
        det = assess(pops.pop(fault.healthy), pops, fault.healthy, settings, _fault_stream(study, 2, ps.index), units,
                     fault.combine)
        result.fault_detection.append((ps, det))
        if len(det.subsets):
            chosen = det.subsets.rename(columns={"level": "faulty"})
            chosen.insert(0, "scene", ps.index)
            subsets.append(chosen)
        table = det.to_frame().rename(columns={"level": "faulty"})
        table.insert(1, "design", fault.design)
        st = indices[(indices["scene"] == ps.index) & (indices["parameter"] == fault.parameter)]
        first = st.drop_duplicates("output").set_index("output")
        table.insert(0, "healthy", fault.healthy)
        table.insert(0, "fault", fault.parameter)
        for key, v in reversed(ps.fields.items()):
            table.insert(0, key, v)
        table.insert(0, "scene", ps.index)
        table["ST_fault"] = table["output"].map(first["ST"]).astype(float)
        table["ST_method"] = table["output"].map(first["method"])
        table["noise_absolute"] = [fault.noise[o].absolute if o in fault.noise else 0.0 for o in table["output"]]
        table["noise_relative"] = [fault.noise[o].relative if o in fault.noise else 0.0 for o in table["output"]]
        rows.append(table)
        sm = det.smallest_detectable()
        sm.insert(0, "scene", ps.index)
        smallest.append(sm)
    result.fault = pd.concat(rows, ignore_index=True)
    result.fault_smallest = pd.concat(smallest, ignore_index=True)
    result.fault_subsets = pd.concat(subsets, ignore_index=True) if subsets else None
    result.fault_indices = _fault_indices(plan, store, outputs)


def _fault_indices(plan: _Plan, store: EvaluationStore, outputs: list[str]) -> pd.DataFrame:
    """Sobol indices of the other parameters in each population (healthy and every faulty level), per
    scene and method, with their change from the healthy population (``dS1``, ``dST``)."""
    study = plan.study
    fault = study.spec.fault
    assert fault is not None
    others, _ = _fault_space(study)
    rows = []
    for ps in plan.scenes:
        for method, design in _designs(study, others):
            for level in _fault_levels(study):
                y = plan.values(store, f"fault:{method}:{level!r}", ps, outputs, study.spec.scenes.aggregate)
                t = get_method(method).analyze(others, design, y, outputs=outputs).to_frame()
                t.insert(0, "level", level)
                t.insert(0, "scene", ps.index)
                rows.append(t)
    table = pd.concat(rows, ignore_index=True)
    key = ["scene", "method", "output", "parameter"]
    ref = table[table["level"] == fault.healthy][[*key, "S1", "ST"]]
    joined = table.merge(ref, on=key, how="left", suffixes=("", "_healthy"))
    joined["dS1"] = joined["S1"] - joined["S1_healthy"]
    joined["dST"] = joined["ST"] - joined["ST_healthy"]
    return joined.drop(columns=["S1_healthy", "ST_healthy"])


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
