"""What every study kind shares: the result, the plan of tasks per scene, the runs, and the
:class:`Kind` interface (:func:`ddgsa.execute.pipeline.execute` drives a kind through it).

A kind plans its blocks of points (:meth:`Kind.plan`), runs what depends on earlier answers
(:meth:`Kind.run`), analyses the stored values into its own result type (:meth:`Kind.analyse`) and adds
its own provenance (:meth:`Kind.provenance`).
"""

from __future__ import annotations

import sys

import warnings
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
import pandas as pd

import ddgsa
from ddgsa.errors import StudyError
from ddgsa.gsa.base import Design, get_method
from ddgsa.models import ImplausibleOutputWarning
from ddgsa.models import get as get_model
from ddgsa.models.auto import pilot_choice, pilot_scene
from ddgsa.runner import EvaluationStore, Evaluator, ModelId, Outcome, Task, run_tasks, said_if_slow, task_key
from ddgsa.gsa.space import ParameterSpace
from ddgsa.loads.scene import Scene
from ddgsa.study.spec import PlannedScene, Study, plan_scenes


ABSENT: dict[str, Any] = {
    "results": (), "moments": None, "signal_indices": None, "signal_generalised": None, "convergence": None,
    "sweep": None, "fault": None, "fault_smallest": None, "fault_indices": None, "fault_detection": (),
    "fault_subsets": None}
"""Each kind's own result fields (:class:`~ddgsa.execute.kinds.gsa.GsaResult`, :class:`~ddgsa.execute.kinds.sweep.SweepResult`,
:class:`~ddgsa.execute.kinds.fault.FaultResult`) and how they read on a result of another kind."""


@dataclass
class StudyResult:
    """What every study kind's result has; each kind's result type adds its own fields.

    A field of another kind reads as absent (:data:`ABSENT`: None, or an empty tuple for lists of
    results), so a report can ask any result ``result.sweep is not None``."""

    study: Study
    indices: pd.DataFrame
    """Per scene, method, output and parameter: the indices (empty for a sweep)."""
    diagnostics: pd.DataFrame
    evaluations: pd.DataFrame
    provenance: dict[str, Any]
    fidelity: pd.DataFrame | None = None
    """``fidelity: auto``'s choice per scene (empty without it)."""
    confirmation: pd.DataFrame | None = None
    """The verdict per (scene, output) (:func:`ddgsa.execute.confirm.confirmation_table`, set by the pipeline
    once the analysis is done; ``confirmation.csv``)."""

    def __getattr__(self, name: str) -> Any:
        if name in ABSENT:
            return ABSENT[name]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def to_xarray(self) -> Any:
        """Indices, bounds, flags, moments and fault statistics as an :class:`xarray.Dataset` with
        dimensions (scene, output, parameter, method[, fault_level]), the scene fields as coordinates
        and CF-style units and meanings (:func:`ddgsa.execute.dataset.to_dataset`)."""
        from ddgsa.execute.dataset import to_dataset

        units = self.study.make_model().units()
        return to_dataset(self.indices, self.study.scene_fields, self.moments, self.fault, self.fault_indices,
                          self.diagnostics, {"study": self.study.name, "model": self.study.spec.model.name}, units,
                          confirmation=self.confirmation)

    def __repr__(self) -> str:
        return (f"StudyResult(study={self.study.name!r}, {len(self.indices)} index rows, "
                f"{len(self.evaluations)} evaluations)")

    def _repr_html_(self) -> str:
        """The study's indices as an HTML table in Jupyter (untrusted rows shaded)."""
        from ddgsa.gsa.notebook import result_html

        ev = self.provenance.get("evaluations", {})
        facts = [f"model {self.study.spec.model.name} ({self.study.spec.model.fidelity}), "
                 f"{ev.get('total', '?')} evaluations, {ev.get('failed', '?')} failed"]
        if len(self.indices):
            bad = self.indices[~self.indices["trusted"].astype(bool)]
            facts.append("every row trusted" if bad.empty else
                         f"{len(bad)} of {len(self.indices)} rows untrusted (outputs: {', '.join(bad['output'].unique())})")
        return result_html(f"study {self.study.name}", facts, self.indices)


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



class Runs:
    """Every model evaluation a study asks for, counted once per unique evaluation.

    Each call hands tasks to the runner (when ``evaluate``); :meth:`counts` gives the figures
    the CLI line, ``summary.md`` and ``provenance.json`` all print: ``total`` unique
    evaluations, ``evaluated`` (run now), ``cached`` (found in the store), ``failed`` (of all,
    with stored reasons) and ``failed_now``.
    """

    def __init__(self, store: EvaluationStore, evaluate: bool, run_opts: dict[str, Any],
                 retry_failed: bool = False) -> None:
        self.store, self.evaluate, self.run_opts = store, evaluate, run_opts
        self.retry_failed = retry_failed
        """Run again the evaluations the store holds as failed (``ddgsa run --retry-failed``)."""
        self.tasks: dict[str, Task] = {}
        self.evaluated = self.failed_now = 0
        self._warm: set[ModelId] = set()

    def __call__(self, tasks: list[Task]) -> None:
        """Evaluate what the store lacks of ``tasks`` (and, with ``retry_failed``, what failed)."""
        self.tasks.update((t.key, t) for t in tasks)
        if not self.evaluate:
            return
        if self.retry_failed and (gone := self.store.forget_failed(t.key for t in tasks)) \
                and not self.run_opts.get("quiet", False):
            print(f"ddgsa: note: {gone} stored failed evaluation{'s' if gone > 1 else ''} run again (--retry-failed)",
                  file=sys.stderr, flush=True)
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
        :data:`ddgsa.runner.SLOW_FIRST_S`, the user is told what is happening and then how long it took."""
        missing = {t.key for t in tasks} - self.store.known(t.key for t in tasks)
        first: dict[ModelId, Task] = {}
        for t in tasks:
            if t.key in missing and t.model not in self._warm:
                first.setdefault(t.model, t)
        quiet = self.run_opts.get("quiet", False)
        for mid, task in first.items():
            self._warm.add(mid)
            with said_if_slow(f"{mid.name} ({mid.fidelity}): first evaluation, compiling the model's kernels (a "
                              "first run after installing only: one to two minutes on 2 cores; later runs load them "
                              "from the cache)...", quiet, done=f"{mid.name} ({mid.fidelity}): kernels ready"):
                self._run([task], {**self.run_opts, "jobs": 1, "backend": "loky", "quiet": True})

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
    pts = plan_points(study, pilot, names)
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
        raise StudyError(f"{runs.store.path}: the pilot evaluations for fidelity: auto are not in this evaluation "
                         "store; run the study first (ddgsa run)")
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


def plan_points(study: Study, x: np.ndarray, names: tuple[str, ...]) -> list[dict[str, float]]:
    fixed = dict(study.spec.fixed)
    return [{**fixed, **{n: float(v) for n, v in zip(names, row)}} for row in x]


class Plan:
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
        pts = plan_points(self.study, x, names)
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
        pts = plan_points(self.study, x, names)
        per_real = []
        for scene in ps.scenes:
            keys = [self.task(ps, scene, p).key for p in pts]
            got = store.get(keys)
            missing = [k for k in keys if k not in got]
            if missing:
                raise StudyError(f"{store.path}: {len(missing)} evaluations of scene {ps.fields} are not in this "
                                 "evaluation store; run the study first (ddgsa run)")
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


def method_designs(study: Study, space: ParameterSpace | None = None) -> list[tuple[str, Design]]:
    """The fixed designs of the study's methods over ``space`` (default: the study's; ``auto`` chooses
    its points as it goes)."""
    space = space or study.space
    assert space is not None
    return [(m.method, get_method(m.method).design(space, **m.options)) for m in study.spec.methods
            if m.method != "auto"]


def row_index(pooled: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Row of ``pooled`` (sorted unique rows) that equals each row of ``points``."""
    lookup = {row.tobytes(): i for i, row in enumerate(pooled)}
    return np.array([lookup[row.tobytes()] for row in np.ascontiguousarray(points)])



class Kind(Protocol):
    """One study kind (``gsa``, ``sweep``, ``fault``), made per execution from the study."""

    designs: list[tuple[str, Design]]
    """The fixed designs of the study's methods (empty for a sweep); provenance records their seeds."""

    def plan(self, plan: Plan) -> None:
        """Add the kind's blocks of points to ``plan`` (run together, before :meth:`run`)."""

    def run(self, plan: Plan, runs: Runs) -> None:
        """Run what depends on earlier answers (``method: auto``'s stages), after the planned blocks."""

    def analyse(self, plan: Plan, runs: Runs) -> StudyResult:
        """The kind's own result type from the stored values (may run more, e.g. ``confirm:``'s stages);
        :func:`ddgsa.execute.pipeline.execute` adds the evaluations and provenance."""

    def provenance(self, provenance: dict[str, Any]) -> None:
        """Add the kind's own entries to the study's provenance."""
