"""The ``gsa`` study kind: every method's design pooled per scene, each method's indices, the
zero-cost cross-checks, ``method: auto``, ``confirm:``, output moments, signal indices and
convergence curves."""

from __future__ import annotations

import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from ddgsa.gsa.auto import AutoSobol
from ddgsa.gsa.base import Design, get_method
from ddgsa.gsa.escalate import TIME_ONLY, Escalation
from ddgsa.gsa.givendata import MIN_POINTS as GIVEN_MIN_POINTS, drawn_rows, given_data_s1
from ddgsa.gsa.pooled import pooled_pce
from ddgsa.gsa.result import SobolResult
from ddgsa.gsa.target import with_targets
from ddgsa.gsa.trust import DEFAULT_TOLERANCE
from ddgsa.execute.kinds.common import Plan, Runs, StudyResult, method_designs, plan_points, row_index
from ddgsa.runner import EvaluationStore
from ddgsa.gsa.space import ParameterSpace
from ddgsa.study.spec import PlannedScene, Study
from ddgsa.execute.signals import analyse_convergence, analyse_signals


@dataclass
class GsaResult(StudyResult):
    """A ``gsa`` study's result: the indices (shared fields) with each scene's results, moments,
    signal indices and convergence curves."""

    results: list[tuple[PlannedScene, SobolResult]] = field(default_factory=list)
    moments: pd.DataFrame | None = None
    """Per scene and output: ``mean``, ``std``, ``cv`` (std / |mean|) and their ``source``."""
    signal_indices: pd.DataFrame | None = None
    """Per scene, method, signal, bin and parameter: indices and the bin's variance (:mod:`ddgsa.execute.signals`)."""
    signal_generalised: pd.DataFrame | None = None
    """Per scene, method, signal and parameter: the variance-weighted (generalised) indices."""
    convergence: pd.DataFrame | None = None
    """Per scene, method, output and parameter: indices against runs on nested sub-samples."""


SAMPLE_DESIGNS = ("saltelli", "fast", "rbd_fast", "pce", "hsic")
"""Methods whose every design point is a draw from the input distribution (pce unless fitted by quadrature)."""


def moments(space: ParameterSpace, name: str, design: Design, y: np.ndarray, res: SobolResult,
            outputs: list[str]) -> list[dict[str, Any]] | None:
    """Mean and standard deviation of each output from one method's evaluations (``n``: the sample
    size, 0 for a surrogate's moments), or None. The study reports those of the largest sample.

    A sampling design (Saltelli, FAST, RBD-FAST, PCE regression) gives the sample moments of all
    its points; M-DRM those of its quasi-random check sample, or without one its own surrogate's
    moments (``h_c^(1-n) prod rho_i``, ``h_c^(2(1-n)) prod theta_i``; exact for products).
    """
    if name in SAMPLE_DESIGNS and design.options.get("fit") != "quadrature":
        return sample_moments(y, f"{name} sample", outputs)
    if name == "mdrm" and design.options.get("check"):
        end = design.meta["inert"]["n"] if "inert" in design.meta else len(y)     # before the inert check's pairs
        return sample_moments(y[end - design.options["check"]:end], "M-DRM check sample", outputs)
    if name == "mdrm" and "rho" in res.extras:
        n = space.dim
        h_c, rho, theta = res.extras["h_cut"], res.extras["rho"], res.extras["theta"]     # (k,), (k, n), (k, n)
        with np.errstate(all="ignore"):
            mean = h_c ** (1 - n) * np.prod(rho, axis=1)
            var = h_c ** (2 * (1 - n)) * np.prod(theta, axis=1) - mean ** 2
        return [{"output": o, "mean": float(mean[j]), "std": float(np.sqrt(max(var[j], 0.0))),
                 "source": "M-DRM surrogate", "n": 0} for j, o in enumerate(outputs)]
    return None


def sample_moments(y: np.ndarray, source: str, outputs: list[str]) -> list[dict[str, Any]] | None:
    """Mean and standard deviation of each output over the finite rows of ``y`` (n, k), a sample of the
    input distribution, with ``source`` and the count (``source (64 points)``); None below two rows."""
    finite = np.isfinite(y).all(axis=1)
    sample = y[finite]
    if len(sample) < 2:
        return None
    return [{"output": o, "mean": float(sample[:, j].mean()), "std": float(sample[:, j].std(ddof=1)),
             "source": f"{source} ({_count(finite)})", "n": len(sample)} for j, o in enumerate(outputs)]


MOMENT_COLUMNS = ["scene", "output", "mean", "std", "cv", "source", "n"]
"""``result.moments`` (``output_moments.csv``)."""


def _moment_row(scene: int, m: dict[str, Any]) -> dict[str, Any]:
    """One row of :data:`MOMENT_COLUMNS`: ``m`` with its scene and CV (std / |mean|)."""
    return {"scene": scene, **m, "cv": m["std"] / abs(m["mean"]) if m["mean"] else float("inf")}


def _larger_moments(moments: pd.DataFrame, scene: int, found: list[dict[str, Any]]) -> pd.DataFrame:
    """``moments`` with each (``scene``, output) row of ``found`` in place of the one there where its sample
    is larger (the study reports the moments of its largest sample)."""
    rows = moments.to_dict("records")
    at = {(int(r["scene"]), r["output"]): i for i, r in enumerate(rows)}
    for m in found:
        i = at.get((scene, m["output"]))
        if i is None:
            rows.append(_moment_row(scene, m))
        elif rows[i]["n"] < m["n"]:
            rows[i] = _moment_row(scene, m)
    return pd.DataFrame(rows, columns=MOMENT_COLUMNS)


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


def _run_auto(plan: Plan, runs: Runs, outputs: list[str], options: dict[str, Any]) -> list[SobolResult]:
    """``method: auto`` in every scene at once: each stage's points of all scenes go to the runner together."""
    study = plan.study
    assert study.space is not None
    names, aggregate = study.space.names, study.spec.scenes.aggregate
    autos = [AutoSobol(study.space, outputs, **options) for _ in plan.scenes]
    pending = {i: a.start() for i, a in enumerate(autos)}
    while pending:
        tasks = [plan.task(plan.scenes[i], scene, p) for i, x in pending.items()
                 for scene in plan.scenes[i].scenes for p in plan_points(study, x, names)]
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


def _followups(plan: Plan, runs: Runs, designs: list[tuple[str, Design]], raw: list[str]
               ) -> dict[tuple[int, int], Design]:
    """The methods' second rounds (:meth:`GsaMethod.followup`: M-DRM's inert check) per (design, scene
    position), decided from the pooled block's values and run together; the same as :func:`ddgsa.sobol`."""
    study = plan.study
    assert study.space is not None
    pooled, names = plan.blocks["gsa"]
    out: dict[tuple[int, int], Design] = {}
    tasks = []
    for k, ps in enumerate(plan.scenes):
        y, outputs = with_targets(plan.values(runs.store, "gsa", ps, raw, study.spec.scenes.aggregate), raw,
                                  study.targets)
        for j, (name, design) in enumerate(designs):
            more = get_method(name).followup(study.space, design, y[row_index(pooled, design.points)], outputs)
            if more is not None:
                out[(j, k)] = more
                pts = plan_points(study, more.points[design.n_points:], names)
                tasks += [plan.task(ps, scene, p) for scene in ps.scenes for p in pts]
    if tasks:
        plan.tasks += tasks
        runs(tasks)
    return out


def _analyse(plan: Plan, store: EvaluationStore, designs: list[tuple[str, Design]], outputs: list[str],
             result: GsaResult, auto: list[list[SobolResult]],
             followups: dict[tuple[int, int], Design] | None = None) -> None:
    study = plan.study
    assert study.space is not None
    pooled, names = plan.blocks["gsa"]
    rows, diag_rows, moment_rows = [], [], []
    raw = outputs
    followups = followups or {}
    for k, ps in enumerate(plan.scenes):
        aggregate = study.spec.scenes.aggregate
        y, outputs = with_targets(plan.values(store, "gsa", ps, raw, aggregate), raw, study.targets)
        ys = [y[row_index(pooled, design.points)] for _, design in designs]
        scene_results = []
        for j, ((name, design), yd) in enumerate(zip(designs, ys)):
            more = followups.get((j, k))
            if more is not None:
                extra = with_targets(plan.values_at(store, more.points[design.n_points:], names, ps, raw, aggregate),
                                     raw, study.targets)[0]
                design, yd = more, np.vstack([yd, extra])
            scene_results.append(get_method(name).analyze(study.space, design, yd, outputs=outputs))
        scene_results += pooled_crosscheck(study, designs, pooled, y, outputs)
        found = [m for m in (moments(study.space, name, design, yd, res, outputs)
                             for (name, design), yd, res in zip(designs, ys, scene_results)) if m]
        found += [auto_moments(per_scene[k], outputs) for per_scene in auto]
        moment_rows += [_moment_row(ps.index, m)
                        for m in max(found, key=lambda ms: ms[0]["n"], default=[])]      # the largest sample
        for res in scene_results + [per_scene[k] for per_scene in auto]:
            _add_result(study, ps, res, result, rows, diag_rows)
    result.indices = pd.concat(rows, ignore_index=True)
    result.moments = pd.DataFrame(moment_rows, columns=MOMENT_COLUMNS)
    result.diagnostics = (pd.concat(diag_rows, ignore_index=True) if diag_rows else
                          pd.DataFrame(columns=["scene", "method", "name", "severity", "output", "parameter",
                                                "value", "message"]))


def _signals_and_convergence(plan: Plan, store: EvaluationStore, designs: list[tuple[str, Design]],
                             outputs: list[str], result: GsaResult) -> None:
    """Indices of the study's signals and the convergence curves of its outputs (:mod:`ddgsa.execute.signals`)."""
    study = plan.study
    pooled, names = plan.blocks["gsa"]
    rows = [row_index(pooled, d.points) for _, d in designs]
    pts = plan_points(study, pooled, names)
    result.signal_indices, result.signal_generalised = analyse_signals(
        study, plan.scenes, lambda ps, scene: [plan.task(ps, scene, p).key for p in pts], store, designs, rows)
    result.convergence = analyse_convergence(
        study, plan.scenes, lambda ps: plan.values(store, "gsa", ps, outputs, study.spec.scenes.aggregate),
        designs, rows, outputs)


def _add_result(study: Study, ps: PlannedScene, res: SobolResult, result: GsaResult, rows: list[pd.DataFrame],
                diag_rows: list[pd.DataFrame]) -> None:
    """One scene's result with the study's ranking rule (``ranking:``): kept, its table with the scene
    fields, its diagnostics."""
    if study.spec.ranking.pair != (None, None):
        res = res.rerank(*study.spec.ranking.pair)
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


class WallBudget:
    """``confirm: {time}``: the wall time the escalation may spend [s] (None: no limit) and the measured
    wall time per model run [s] (from the study's runs so far, then from each stage), which decide which
    pending stages still fit: the smallest first, so the time goes to the pairs cheapest to confirm."""

    def __init__(self, limit: float | None, per_task: float) -> None:
        self.limit, self.per_task = limit, per_task
        self.start = time.monotonic()

    def left(self) -> float:
        """Seconds left of the limit (inf without one)."""
        return np.inf if self.limit is None else self.limit - (time.monotonic() - self.start)

    def fitting(self, sizes: dict[int, int]) -> list[int]:
        """The pending escalations (their stages' runs in ``sizes``) to run now: every one without a
        limit; with one, the smallest first while the estimated wall time fits in what is left (with no
        estimate yet, the smallest alone, to measure one)."""
        if self.limit is None:
            return list(sizes)
        left, out = self.left(), []
        for i in sorted(sizes, key=lambda i: (sizes[i], i)):
            need = sizes[i] * self.per_task
            if np.isfinite(need) and need <= left:
                out.append(i)
                left -= need
            elif not np.isfinite(need) and not out and left > 0:
                out.append(i)
                left = 0.0
        return out

    def stopped(self, runs: int) -> str:
        """The log line of an escalation the time budget stops."""
        need = runs * self.per_task
        return (f"stopped by the time budget ({self.limit:g} s): the next stage's {runs} runs would take "
                f"~{need:.3g} s, {max(self.left(), 0.0):.3g} s were left")

    @contextmanager
    def timing(self, runs: int) -> Iterator[None]:
        """Time a stage of ``runs`` model runs; the per-run estimate becomes the largest measured (wall)."""
        t0 = time.monotonic()
        yield
        measured = (time.monotonic() - t0) / max(runs, 1)
        self.per_task = measured if not np.isfinite(self.per_task) else max(self.per_task, measured)


def _seconds_per_task(runs: Runs, tasks: list[Any], jobs: int | None) -> float:
    """Wall seconds per model run estimated from the stored run times of ``tasks`` (the median, over
    the workers; NaN when none is stored: the first confirm stage measures it)."""
    got = runs.store.get(t.key for t in tasks[-2000:])
    sec = np.array([o.seconds for o in got.values() if o.seconds is not None and o.seconds > 0], dtype=float)
    return float(np.median(sec)) / max(1, int(jobs or 1)) if len(sec) else float("nan")


def _confirm(plan: Plan, runs: Runs, designs: list[tuple[str, Design]], outputs: list[str],
             result: GsaResult) -> list[dict[str, Any]]:
    """``confirm: {budget}``: per scene, an :class:`~ddgsa.gsa.escalate.Escalation` from every point
    of the scene (every design, ``auto``'s stages included, each point once) and every result there; each stage's points of all scenes go to the runner together. The
    escalations' results are added beside the methods', and the moments of an output become those of the
    escalation's draws of the inputs (PCE points, Saltelli rows) where they outnumber the methods' sample;
    returns their logs (provenance ``confirm``)."""
    study = plan.study
    spec = study.spec.confirm
    assert study.space is not None and spec is not None
    names, aggregate = study.space.names, study.spec.scenes.aggregate
    pooled, _ = plan.blocks["gsa"]
    tol = min([d.options.get("tolerance", DEFAULT_TOLERANCE) for _, d in designs] or [DEFAULT_TOLERANCE])
    salt = next((d for name, d in designs if name == "saltelli"), None)
    model = study.make_model()
    resolution = {o: study.output_declaration(model, o).resolution for o in outputs}
    escs, pending = [], {}
    budgets = [study.spec.confirm_budget(ps.fields) for ps in plan.scenes]    # per scene (None: time only)
    features: list[list[str]] = []                       # per scene, the model's control features there
    for i, ps in enumerate(plan.scenes):
        y = plan.values(runs.store, "gsa", ps, outputs, aggregate)
        have = [r for p_, r in result.results if p_.index == ps.index]
        x_all = np.vstack([pooled] + [ax for ax, _ in plan.auto_points.get(i, [])])
        y_all = np.vstack([y] + [ay for _, ay in plan.auto_points.get(i, [])])
        _, first = np.unique(x_all, axis=0, return_index=True)     # a point twice would flatter the LOO error
        keep = np.sort(first)
        features.append([str(f) for f in model.control_features(ps.scenes[0])])
        esc = Escalation(study.space, outputs, TIME_ONLY if budgets[i] is None else budgets[i], x_all[keep],
                         y_all[keep], have, tol, seed=spec.seed,
                         saltelli=None if salt is None else (salt, y[row_index(pooled, salt.points)]),
                         resolution=resolution, ranking=study.spec.ranking.pair,
                         features=_features_at(plan, runs, x_all[keep], ps, features[i]))
        escs.append(esc)
        x = esc.start()
        if x is not None:
            pending[i] = x
    told = [0] * len(escs)

    def tell() -> None:
        """Each escalation's new log lines on the console (a confirm stage can take minutes)."""
        for i, esc in enumerate(escs):
            if not runs.run_opts.get("quiet", False):
                for line in esc.log[told[i]:]:
                    print(f"ddgsa: confirm, scene {plan.scenes[i].index}: {line}", file=sys.stderr, flush=True)
            told[i] = len(esc.log)

    tell()
    clock = WallBudget(spec.time, _seconds_per_task(runs, plan.tasks, runs.run_opts.get("jobs")))
    timed_out: set[int] = set()                         # the escalations the time limit stopped
    while pending:
        stage = {i: [plan.task(plan.scenes[i], scene, p) for scene in plan.scenes[i].scenes
                     for p in plan_points(study, x, names)] for i, x in pending.items()}
        fits = clock.fitting({i: len(t) for i, t in stage.items()})
        for i in set(pending) - set(fits):
            escs[i].log.append(clock.stopped(len(stage[i])))
            timed_out.add(i)
        pending = {i: pending[i] for i in fits}
        tasks = [t for i in fits for t in stage[i]]
        if not tasks:
            break
        plan.tasks += tasks
        with clock.timing(len(tasks)):
            runs(tasks)
        pending = {i: nxt for i, x in pending.items() if (nxt := escs[i].feed(
            plan.values_at(runs.store, x, names, plan.scenes[i], outputs, aggregate),
            _features_at(plan, runs, x, plan.scenes[i], features[i]))) is not None}
        tell()
    tell()
    rows, diag_rows = [result.indices], [result.diagnostics] if len(result.diagnostics) else []
    for ps, esc in zip(plan.scenes, escs):
        for res in esc.stages:
            _add_result(study, ps, res, result, rows, diag_rows)
        drawn = sample_moments(esc.drawn_values(), "confirm: escalation's draws", outputs)
        if drawn and result.moments is not None:          # its draws, where more than the methods' sample
            result.moments = _larger_moments(result.moments, ps.index, drawn)
    result.indices = pd.concat(rows, ignore_index=True)
    if diag_rows:
        result.diagnostics = pd.concat(diag_rows, ignore_index=True)
    return [{"scene": ps.index, "budget": budget, "time_s": spec.time, "spent": esc.spent, "log": esc.log,
             "asks": esc.asks(), "stopped_by_time": i in timed_out}
            for i, (ps, esc, budget) in enumerate(zip(plan.scenes, escs, budgets))]


def _features_at(plan: Plan, runs: Runs, x: np.ndarray, ps: PlannedScene, names: list[str]) -> np.ndarray | None:
    """The control features ``names`` (:meth:`ddgsa.models.base.Model.control_features`) stored with the runs
    at points ``x`` of scene ``ps``, aggregated over its realisations (their mean); None without features or
    where a stored run lacks them (a store written before the model declared them)."""
    if not names:
        return None
    try:
        arr = plan.realisations_at(runs.store, x, plan.study.space.names, ps, names)
    except KeyError:
        return None
    return arr.mean(axis=0)


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
    given = given_data_s1(study.space, drawn, y[row_index(x, drawn)], outputs, tol)
    return out + ([given] if given is not None else [])



class GsaKind:
    """``kind: gsa``: the pooled designs of the study's methods in every scene, then ``auto``'s
    stages; indices, cross-checks, moments, ``confirm:``, signals and convergence."""

    def __init__(self, study: Study) -> None:
        self.study = study
        self.designs = method_designs(study)
        self.auto: list[list[SobolResult]] = []
        self.followups: dict[tuple[int, int], Design] = {}
        self.confirm_log: list[dict[str, Any]] = []

    def plan(self, plan: Plan) -> None:
        space = self.study.space
        assert space is not None
        pooled = np.unique(np.vstack([d.points for _, d in self.designs] + [np.zeros((0, space.dim))]), axis=0)
        plan.add_block("gsa", pooled, space.names)

    def run(self, plan: Plan, runs: Runs) -> None:
        self.auto = [_run_auto(plan, runs, self.study.outputs, m.options)
                     for m in self.study.spec.methods if m.method == "auto"]
        self.followups = _followups(plan, runs, self.designs, self.study.outputs)

    result_type: type[GsaResult] = GsaResult

    def analyse(self, plan: Plan, runs: Runs) -> GsaResult:
        result = self.result_type(self.study, pd.DataFrame(), pd.DataFrame(), pd.DataFrame(), {})
        outputs = self.study.outputs
        _analyse(plan, runs.store, self.designs, outputs, result, self.auto, self.followups)
        if self.study.spec.confirm is not None:
            self.confirm_log = _confirm(plan, runs, self.designs, outputs, result)
        _signals_and_convergence(plan, runs.store, self.designs, outputs, result)
        return result

    def provenance(self, provenance: dict[str, Any]) -> None:
        if self.confirm_log:
            provenance["confirm"] = self.confirm_log
