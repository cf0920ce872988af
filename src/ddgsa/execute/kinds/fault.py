"""The ``fault`` study kind: the ``gsa`` kind over all parameters, plus per fault level a detection
sample and each method's design over the other parameters; detection statistics (POD, AUC), the
smallest detectable fault and the indices per fault level (:mod:`ddgsa.detection`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from ddgsa.detection import DetectionSettings, FaultDetectability, add_noise, assess
from ddgsa.errors import StudyError
from ddgsa.gsa.base import get_method
from ddgsa.execute.kinds.common import Plan, Runs, method_designs
from ddgsa.execute.kinds.gsa import GsaKind, GsaResult
from ddgsa.runner import EvaluationStore
from ddgsa.gsa.space import ParameterSpace
from ddgsa.study.spec import PlannedScene, Study


@dataclass
class FaultResult(GsaResult):
    """A ``fault`` study's result: the ``gsa`` result over all parameters, plus the detection
    statistics per scene, fault level and output, the smallest detectable fault, the sensor
    subsets and the other parameters' indices per fault level."""

    fault: pd.DataFrame | None = None
    fault_smallest: pd.DataFrame | None = None
    fault_indices: pd.DataFrame | None = None
    fault_detection: list[tuple[PlannedScene, FaultDetectability]] = field(default_factory=list)
    fault_subsets: pd.DataFrame | None = None


def _fault_space(study: Study) -> tuple[ParameterSpace, str]:
    assert study.space is not None and study.spec.fault is not None
    name = study.spec.fault.parameter
    others = [p for p in study.space.parameters if p.name != name]
    if not others:
        raise StudyError(f"{study.path or '<study>'}: field 'parameters': a fault study needs uncertain parameters "
                         "besides the fault parameter")
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


def _add_fault_blocks(study: Study, plan: Plan) -> None:
    """Per fault level: the detection sample over the other parameters, and each method's design over them."""
    fault = study.spec.fault
    assert fault is not None
    others, name = _fault_space(study)
    base = others.sample(fault.samples, seed=_fault_stream(study, 0), rule="sobol")
    designs = method_designs(study, others)
    for level in _fault_levels(study):
        plan.add_block(f"fault:{level!r}", np.column_stack([base, np.full(len(base), level)]), (*others.names, name))
        for method, design in designs:
            x = np.column_stack([design.points, np.full(len(design.points), level)])
            plan.add_block(f"fault:{method}:{level!r}", x, (*others.names, name))


def _fault_measurements(plan: Plan, store: EvaluationStore, ps: PlannedScene, level: float, k: int,
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


def _fault_verdicts(plan: Plan, store: EvaluationStore, outputs: list[str], result: FaultResult) -> None:
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


def _fault_indices(plan: Plan, store: EvaluationStore, outputs: list[str]) -> pd.DataFrame:
    """Sobol indices of the other parameters in each population (healthy and every faulty level), per
    scene and method, with their change from the healthy population (``dS1``, ``dST``)."""
    study = plan.study
    fault = study.spec.fault
    assert fault is not None
    others, _ = _fault_space(study)
    rows = []
    for ps in plan.scenes:
        for method, design in method_designs(study, others):
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



class FaultKind(GsaKind):
    """``kind: fault``: :class:`~ddgsa.execute.kinds.gsa.GsaKind`, then the fault levels' blocks and verdicts."""

    def plan(self, plan: Plan) -> None:
        super().plan(plan)
        _add_fault_blocks(self.study, plan)

    result_type: type[FaultResult] = FaultResult

    def analyse(self, plan: Plan, runs: Runs) -> FaultResult:
        result = super().analyse(plan, runs)
        assert isinstance(result, FaultResult)
        _fault_verdicts(plan, runs.store, self.study.outputs, result)
        return result

    def provenance(self, provenance: dict[str, Any]) -> None:
        super().provenance(provenance)
        provenance["seeds"]["fault"] = fault_seed(self.study)
