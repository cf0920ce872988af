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
import sys
import time
from dataclasses import dataclass, field
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

import ddgsa
from ddgsa.errors import DdgsaError, StudyError
from ddgsa.gsa.auto import AutoSobol
from ddgsa.gsa.base import Design, get_method
from ddgsa.gsa.result import SobolResult
from ddgsa.models.auto import choose_fidelity
from ddgsa.runner import EvaluationStore, ModelId, Outcome, Task, run_tasks, task_key
from ddgsa.space import ParameterSpace
from ddgsa.loads import cache as loads_cache
from ddgsa.loads.scene import Scene
from ddgsa.study import PlannedScene, Study, plan_scenes

SCENE_FIELDS = ["wind_speed", "turbulence_intensity", "inclination_deg", "shear_exponent"]


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
    fault_samples: pd.DataFrame | None = None
    fidelity: pd.DataFrame | None = None


def model_id(study: Study, fidelity: str | None = None) -> ModelId:
    """The runner's model identity for the study (at ``fidelity`` when given)."""
    spec = study.spec.model
    return ModelId(spec.name, fidelity or spec.fidelity, tuple(sorted(spec.options.items())))


def select_fidelities(study: Study, store: EvaluationStore, evaluate: bool,
                      run_opts: dict[str, Any]) -> list[dict[str, Any]]:
    """``fidelity: auto``: per scene, the cheapest fidelity whose pilot outputs stay within tolerance.

    The pilot set is the nominal point plus ``model.auto.pilot`` scrambled-Sobol' points of the
    space, in the first realisation of each scene, at every fidelity of the model. Errors are
    the largest relative deviation over pilot points and study outputs from the richest
    fidelity (the model's first); cost is the mean measured seconds per evaluation.
    """
    from ddgsa.models import get as get_model

    auto = study.spec.model.auto
    fidelities = list(get_model(study.spec.model.name).fidelities)
    space = study.space
    names = space.names if space is not None else ()
    pilot = np.zeros((1, 0)) if space is None else np.vstack(
        [[space.nominal[n] for n in names], space.sample(auto.pilot, seed=auto.seed, rule="sobol")])
    pts = _points(study, pilot, names)
    outputs = study.outputs
    tasks, plan = [], []
    for ps in plan_scenes(study):
        scene = ps.scenes[0]
        for fid in fidelities:
            mid = model_id(study, fid)
            ts = [Task(task_key(mid, scene, p, ddgsa.__version__), mid, scene, p) for p in pts]
            tasks += ts
            plan.append((ps, fid, ts))
    if evaluate:
        run_tasks(tasks, store, **run_opts)
    got = store.get([t.key for t in tasks])
    if len(got) < len({t.key for t in tasks}):
        raise StudyError("pilot evaluations for fidelity: auto are not in the store; run the study first")
    choices = []
    for ps in plan_scenes(study):
        table = {fid: [got[t.key] for t in ts] for p_, fid, ts in plan if p_.index == ps.index}
        values = {fid: np.array([[o.outputs[n] if o.outputs else np.nan for n in outputs] for o in table[fid]])
                  for fid in fidelities}
        seconds = {fid: float(np.mean([o.seconds for o in table[fid]])) for fid in fidelities}
        entry = {"scene": ps.index, **ps.fields, **choose_fidelity(values, seconds, outputs, auto.tolerance)}
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

    def task(self, ps: PlannedScene, scene: Scene, point: dict[str, float]) -> Task:
        """The task of one point in one realisation of a planned scene."""
        mid = self.mids[ps.index]
        return Task(task_key(mid, scene, point, ddgsa.__version__), mid, scene, point)

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
        arr = np.asarray(per_real, dtype=float)                    # (n_real, n_points, n_out)
        agg = {"mean": np.mean, "median": np.median, "max": np.max}[aggregate]
        return agg(arr, axis=0)


def _designs(study: Study) -> list[tuple[str, Design]]:
    """The fixed designs of the study's methods (``auto`` chooses its points as it goes)."""
    assert study.space is not None
    return [(m.method, get_method(m.method).design(study.space, **m.options)) for m in study.spec.methods
            if m.method != "auto"]


def _run_auto(plan: _Plan, store: EvaluationStore, outputs: list[str], options: dict[str, Any],
              evaluate: bool, run_opts: dict[str, Any], counts: dict[str, int]) -> list[SobolResult]:
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
        if evaluate:
            got = run_tasks(tasks, store, **run_opts)
            for k in ("total", "cached", "evaluated", "failed"):
                counts[k] += got[k]
        nxt = {}
        for i, x in pending.items():
            new = autos[i].feed(plan.values_at(store, x, names, plan.scenes[i], outputs, aggregate))
            if new is not None:
                nxt[i] = new
        pending = nxt
    results = [a.result for a in autos]
    assert all(r is not None for r in results)             # every state machine finishes with a result
    return results  # type: ignore[return-value]


def execute(study: Study, store: EvaluationStore, jobs: int | None = None, backend: str | None = None,
            address: str | None = None, quiet: bool = False, evaluate: bool = True) -> StudyResult:
    """Run (or, with ``evaluate=False``, only read back) all model evaluations and analyse them.

    Wind-load realisations are shared by all workers through files beside the store
    (:mod:`ddgsa.loads.cache`): each is generated once per study, not once per worker process."""
    with loads_cache.shared(store.path.parent / "loads"):
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
    fidelity_choice: list[dict[str, Any]] = []
    if spec.model.fidelity == "auto":
        fidelity_choice = select_fidelities(study, store, evaluate, run_opts)
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
    counts = {"total": len({t.key for t in plan.tasks}), "cached": 0, "evaluated": 0, "failed": 0}
    if evaluate:
        counts = run_tasks(plan.tasks, store, **run_opts)
    auto = [_run_auto(plan, store, outputs, m.options, evaluate, run_opts, counts)
            for m in spec.methods if m.method == "auto"]
    t_eval = time.perf_counter() - t0
    result = StudyResult(study, pd.DataFrame(), pd.DataFrame(), pd.DataFrame(), {})
    failures: list[dict[str, Any]] = []
    if spec.kind == "sweep":
        result.sweep = _sweep_table(plan, store, outputs)
    else:
        _analyse(plan, store, designs, outputs, result, auto)
        if spec.kind == "fault":
            result.fault, result.fault_samples = _fault_verdicts(plan, store, outputs, result.indices)
    result.evaluations = _evaluation_table(store, plan)
    failures += [{"key": r["key"], "scene": {k: r[k] for k in SCENE_FIELDS + ["seed"]}, "error": r["error"]}
                 for r in result.evaluations.to_dict("records") if isinstance(r["error"], str)]
    result.provenance = _provenance(study, mids, counts, t_eval, time.perf_counter() - t0, failures, designs)
    result.provenance["fidelity_selection"] = fidelity_choice
    result.provenance["sampling"] = _sampling(study)
    result.fidelity = pd.DataFrame([{k: v for k, v in c.items() if k != "errors"} for c in fidelity_choice])
    return result


def _analyse(plan: _Plan, store: EvaluationStore, designs: list[tuple[str, Design]], outputs: list[str],
             result: StudyResult, auto: list[list[SobolResult]]) -> None:
    study = plan.study
    assert study.space is not None
    pooled, _ = plan.blocks["gsa"]
    rows, diag_rows = [], []
    for k, ps in enumerate(plan.scenes):
        y = plan.values(store, "gsa", ps, outputs, study.spec.scenes.aggregate)
        scene_results = [get_method(name).analyze(study.space, design, y[_row_index(pooled, design.points)],
                                                  outputs=outputs) for name, design in designs]
        for res in scene_results + [per_scene[k] for per_scene in auto]:
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
    result.indices = pd.concat(rows, ignore_index=True)
    result.diagnostics = (pd.concat(diag_rows, ignore_index=True) if diag_rows else
                          pd.DataFrame(columns=["scene", "method", "name", "severity", "output", "parameter",
                                                "value", "message"]))


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
                vals = out.outputs or {name: np.nan for name in outputs}
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
    result.fidelity = first.fidelity
    return result


def _fault_space(study: Study) -> tuple[ParameterSpace, str]:
    assert study.space is not None and study.spec.fault is not None
    name = study.spec.fault.parameter
    others = [p for p in study.space.parameters if p.name != name]
    if not others:
        raise StudyError("a fault study needs uncertain parameters besides the fault parameter")
    return ParameterSpace.from_parameters(others), name


def _add_fault_blocks(study: Study, plan: _Plan) -> None:
    fault = study.spec.fault
    assert fault is not None
    others, name = _fault_space(study)
    base = others.sample(fault.samples, seed=12345, rule="sobol")
    for level in [fault.healthy, *fault.faulty]:
        x = np.column_stack([base, np.full(len(base), level)])
        plan.add_block(f"fault:{level!r}", x, (*others.names, name))


def _fault_verdicts(plan: _Plan, store: EvaluationStore, outputs: list[str],
                    indices: pd.DataFrame) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Separation of faulty from healthy outputs over the other uncertainties, per scene and output."""
    fault = plan.study.spec.fault
    assert fault is not None
    rows, samples = [], []
    for ps in plan.scenes:
        healthy = plan.values(store, f"fault:{fault.healthy!r}", ps, outputs, plan.study.spec.scenes.aggregate)
        for level in fault.faulty:
            faulty = plan.values(store, f"fault:{level!r}", ps, outputs, plan.study.spec.scenes.aggregate)
            for j, out in enumerate(outputs):
                h, f = healthy[:, j], faulty[:, j]
                spread = float(np.nanstd(h, ddof=1))
                sep = float(abs(np.nanmean(f) - np.nanmean(h)) / spread) if spread > 0 else float("inf")
                st = indices[(indices["scene"] == ps.index) & (indices["output"] == out)
                             & (indices["parameter"] == fault.parameter)]
                rows.append({"scene": ps.index, **ps.fields, "fault": fault.parameter, "healthy": fault.healthy,
                             "faulty": level, "output": out, "ST_fault": float(st["ST"].iloc[0]),
                             "ST_method": str(st["method"].iloc[0]), "mean_healthy": float(np.nanmean(h)),
                             "mean_faulty": float(np.nanmean(f)), "std_healthy": spread, "separation": sep,
                             "detectable": bool(sep >= fault.threshold), "threshold": fault.threshold})
                samples += [{"scene": ps.index, "output": out, "level": lev, "value": float(v)}
                            for lev, arr in (("healthy", h), (f"faulty {level:g}", f)) for v in arr]
    return pd.DataFrame(rows), pd.DataFrame(samples).drop_duplicates()


def _evaluation_table(store: EvaluationStore, plan: _Plan) -> pd.DataFrame:
    keys = list({t.key: t for t in plan.tasks}.items())
    got = store.get([k for k, _ in keys])
    rows = []
    for key, task in keys:
        o = got.get(key)
        if o is None:
            continue
        rows.append({"key": key, **task.scene.to_dict(), **task.point, **(o.outputs or {}), "error": o.error,
                     "seconds": o.seconds})
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


def _provenance(study: Study, mids: dict[int, ModelId], counts: dict[str, int], t_eval: float, t_total: float,
                failures: list[dict[str, Any]], designs: list[tuple[str, Design]]) -> dict[str, Any]:
    sc = study.spec.scenes
    return {
        "study": study.name, "study_sha256": study.digest, "study_file": str(study.path) if study.path else None,
        "kind": study.spec.kind, "model": {**model_id(study).as_dict(),
                                           "per_scene": {i: m.fidelity for i, m in mids.items()}},
        "versions": _versions(), "python": sys.version.split()[0], "platform": platform.platform(),
        "seeds": {"scene_seeds": [sc.seed + r for r in range(sc.realisations)],
                  "methods": {name: d.options.get("seed") for name, d in designs}},
        "evaluations": counts, "timings_s": {"evaluation": round(t_eval, 3), "total": round(t_total, 3)},
        "failures": failures,
    }


def default_out(study: Study) -> Path:
    """Default output folder: ``results/<study name>``."""
    return Path("results") / study.name
