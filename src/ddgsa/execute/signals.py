"""A study's indices of signals and its convergence curves, from the evaluations already stored.

Both read the pooled design of a planned study (:mod:`ddgsa.execute.pipeline` passes how to reach it) and
run no model:

* :func:`analyse_signals`: for every scene, signal of ``signals:`` and fixed-design method, the
  per-bin and generalised indices (:mod:`ddgsa.gsa.signal`) of the signal vectors the runner
  stored beside the evaluations (:meth:`ddgsa.runner.EvaluationStore.get_signals`), realisations
  aggregated bin by bin as the scalar outputs are (``scenes.aggregate``).
* :func:`analyse_convergence`: for every scene and method whose design nests, the indices of the
  study's outputs against the runs on nested sub-samples (:mod:`ddgsa.gsa.convergence`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pandas as pd

from ddgsa.gsa.base import Design
from ddgsa.gsa.convergence import convergence, nested_sizes
from ddgsa.gsa.signal import SignalAxis, signal_indices
from ddgsa.runner import EvaluationStore
from ddgsa.study.spec import PlannedScene, Study

_AGGREGATE = {"mean": np.mean, "median": np.median, "max": np.max}


def _scene_columns(table: pd.DataFrame, ps: PlannedScene, method: str) -> pd.DataFrame:
    """``table`` with the scene index, its fields and the method in front."""
    table.insert(0, "method", method)
    for key, v in reversed(list(ps.fields.items())):
        table.insert(0, key, v)
    table.insert(0, "scene", ps.index)
    return table


def analyse_signals(study: Study, scenes: list[PlannedScene], keys: Callable[[PlannedScene, Any], list[str]],
                    store: EvaluationStore, designs: list[tuple[str, Design]],
                    rows: list[np.ndarray]) -> tuple[pd.DataFrame | None, pd.DataFrame | None]:
    """Per-bin and generalised indices of the study's ``signals``: ``(bins, generalised)`` tables (None, None
    without signals).

    Parameters
    ----------
    keys : callable
        ``keys(planned_scene, scene)``: the store keys of the pooled points in one realisation.
    designs, rows : list
        The fixed designs and, for each, the rows of the pooled points its points are.
    """
    if not study.spec.signals or not designs:
        return None, None
    assert study.space is not None
    model = study.make_model()
    agg = _AGGREGATE[study.spec.scenes.aggregate]
    bins, gens = [], []
    for ps in scenes:
        for sig in study.spec.signals:
            decl = model.signal_output(sig)
            grid = model.signal_axis(sig, ps.scenes[0])
            per_real = []
            for scene in ps.scenes:
                ks = keys(ps, scene)
                got = store.get_signals(ks, sig)
                per_real.append(np.vstack([got.get(k, np.full(len(grid), np.nan)) for k in ks]))
            y = agg(np.stack(per_real), axis=0)              # a failed realisation makes the bin NaN
            axis = SignalAxis(decl.axis, decl.axis_unit, grid)
            for (name, design), r in zip(designs, rows):
                res = signal_indices(name, study.space, design, y[r], axis, sig)
                for table, out in ((res.bins.copy(), bins), (res.generalised.copy(), gens)):
                    table["unit"] = decl.unit
                    table["axis_name"], table["axis_unit"] = decl.axis, decl.axis_unit
                    table["n_evals"] = res.n_evals
                    out.append(_scene_columns(table, ps, name))
    return pd.concat(bins, ignore_index=True), pd.concat(gens, ignore_index=True)


def analyse_convergence(study: Study, scenes: list[PlannedScene], values: Callable[[PlannedScene], np.ndarray],
                        designs: list[tuple[str, Design]], rows: list[np.ndarray],
                        outputs: list[str]) -> pd.DataFrame | None:
    """Indices of ``outputs`` against runs on nested sub-samples of each nesting design, every scene
    (``values(planned_scene)``: the aggregated values of the pooled points); None when no design nests."""
    assert study.space is not None
    nesting = [(n, d, r) for (n, d), r in zip(designs, rows) if nested_sizes(d, study.space.dim)]
    if not nesting:
        return None
    tables = []
    for ps in scenes:
        y = values(ps)
        for name, design, r in nesting:
            curve = convergence(study.space, design, y[r], outputs)
            tables.append(_scene_columns(curve.drop(columns="method"), ps, name))
    return pd.concat(tables, ignore_index=True)
