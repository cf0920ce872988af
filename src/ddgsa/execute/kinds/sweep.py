"""The ``sweep`` study kind: every point of a full-factorial ``grid`` in every scene and realisation,
tabulated as it is (no indices)."""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from ddgsa.errors import StudyError
from ddgsa.gsa.base import Design
from ddgsa.execute.kinds.common import Plan, Runs, StudyResult, plan_points
from ddgsa.runner import EvaluationStore
from ddgsa.study.spec import Study


@dataclass
class SweepResult(StudyResult):
    """A ``sweep`` study's result: the table of every grid point, scene and realisation."""

    sweep: pd.DataFrame | None = None
    """Per scene, grid point and realisation: outputs and failure reason (and ``variant`` with ``model.variants``)."""


def _grid(study: Study) -> tuple[np.ndarray, tuple[str, ...]]:
    """The sweep's parameter points: the full factorial of ``grid`` (one empty point without one)."""
    grid = study.spec.grid
    if not grid:
        return np.zeros((1, 0)), ()
    return np.array(list(itertools.product(*grid.values())), dtype=float), tuple(grid)


def _sweep_table(plan: Plan, store: EvaluationStore, outputs: list[str]) -> pd.DataFrame:
    rows = []
    x, names = plan.blocks["nominal"]
    for ps in plan.scenes:
        for r, scene in enumerate(ps.scenes):
            for row, point in zip(x, plan_points(plan.study, x, names)):
                o = store.get([plan.task(ps, scene, point).key])
                if not o:
                    raise StudyError(f"{store.path}: the sweep's evaluations are not in this evaluation store; "
                                     "run the study first (ddgsa run)")
                out = next(iter(o.values()))
                vals = dict(zip(outputs, np.array([(out.outputs or {}).get(name, np.nan) for name in outputs])
                                * plan.study.output_factors(outputs)))
                rows.append({"scene": ps.index, **ps.fields, **dict(zip(names, row)), "realisation": r,
                             "seed": scene.seed, **{name: vals[name] for name in outputs}, "error": out.error})
    return pd.DataFrame(rows)



class SweepKind:
    """``kind: sweep``: the grid (one empty point without one) in every scene; ``result.sweep``."""

    def __init__(self, study: Study) -> None:
        self.study = study
        self.designs: list[tuple[str, Design]] = []

    def plan(self, plan: Plan) -> None:
        plan.add_block("nominal", *_grid(self.study))

    def run(self, plan: Plan, runs: Runs) -> None:
        """Nothing beyond the grid."""

    def analyse(self, plan: Plan, runs: Runs) -> SweepResult:
        return SweepResult(self.study, pd.DataFrame(), pd.DataFrame(), pd.DataFrame(), {},
                           sweep=_sweep_table(plan, runs.store, self.study.outputs))

    def provenance(self, provenance: dict[str, Any]) -> None:
        """Nothing of its own."""
