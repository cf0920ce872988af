"""Convergence you can see: indices against sample size on sub-samples of the runs already made.

A sampling design nests where its first ``m`` points are themselves a valid design of the same
method (no new model run is needed to analyse them):

* ``saltelli``: SALib lays the sample out in blocks of ``d + 2`` rows per base point, and the first
  ``n / 2^j`` base points of a scrambled Sobol' sequence are balanced: the first ``n / 2^j (d + 2)``
  rows are the Saltelli design of ``n / 2^j`` (the sub-sample the method's half-sample check uses).
* ``pce`` with ``fit: regression`` or ``sparse``: the first ``n / 2^j`` points of the scrambled
  Sobol' sample (at least 1.5 times the basis terms for ``regression``, 32 points for ``sparse``).
* ``rbd_fast``: the first ``n / 2^j`` rows of its sample (as its half-sample check does).

Each sub-design is analysed by the method's own ``analyze``, so each point of a curve carries the
method's own error bound (``S1_conf``, ``ST_conf``: PCE's leave-one-out bound; for SALib's methods the
error estimate their trust rule uses, the larger of the bootstrap half-width and twice the
half-sample difference) and the last point *is* the study's index.
M-DRM (Gauss nodes of ``N - 1`` points are not a subset of those of ``N``), PCE by quadrature
(tensor grids do not nest) and FAST (its frequencies fix ``n``) have no sub-sample: they get no
curve, and :func:`nested_sizes` says so by returning none.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ddgsa.gsa.base import Design, get_method
from ddgsa.gsa.pce import n_terms
from ddgsa.gsa.space import ParameterSpace

MAX_LEVELS = 6
"""Sub-sample sizes per curve: the design and up to five halvings of it."""
COLUMNS = ["method", "output", "parameter", "n_evals", "S1", "S1_conf", "ST", "ST_conf", "trusted"]


def nested_sizes(design: Design, dim: int) -> list[int]:
    """Base sizes ``m`` (ascending, the design's own last) whose first points form a valid design of the
    method; empty where the design does not nest (see the module docstring)."""
    o = design.options
    if design.method == "saltelli":
        n, low = int(o["n"]), 4
    elif design.method == "pce" and o.get("fit") in ("regression", "sparse"):
        n = int(o["n"])
        low = max(32, int(np.ceil(1.5 * n_terms(dim, int(o["order"]))))) if o["fit"] == "regression" else 32
    elif design.method == "rbd_fast":
        n, low = int(o["n"]), max(2 * int(o["M"]) + 2, 128)
    else:
        return []
    sizes = [n // 2 ** j for j in range(MAX_LEVELS) if n % 2 ** j == 0 and n // 2 ** j >= low]
    return sorted(sizes) if len(sizes) > 1 else []


def sub_rows(design: Design, m: int, dim: int) -> NDArray[np.int64]:
    """Rows of ``design`` that form its sub-design of the first ``m`` base points: the first ``m``
    points, or Saltelli's first ``m (d + 2)`` rows -- followed, for a Saltelli design with a control
    variate (``control: gp``), by its whole pilot (the last rows), which the process is fitted on."""
    if design.method != "saltelli":
        return np.arange(m)
    rows = np.arange(m * (dim + 2))
    pilot = int(design.meta.get("pilot", 0))
    return np.concatenate([rows, np.arange(design.n_points - pilot, design.n_points)]) if pilot else rows


def sub_design(design: Design, m: int, dim: int) -> Design:
    """The design of the first ``m`` base points (``m`` one of :func:`nested_sizes`; rows :func:`sub_rows`)."""
    rows = sub_rows(design, m, dim)
    meta = {k: (v[rows] if k == "unit" else v) for k, v in design.meta.items()}
    return Design(design.method, design.points[rows], {**design.options, "n": m}, meta)


def convergence(space: ParameterSpace, design: Design, values: NDArray[np.float64],
                outputs: Sequence[str]) -> pd.DataFrame:
    """Indices of every output against the runs spent, on nested sub-samples of ``design``.

    Parameters
    ----------
    design : Design
        A design of a nesting method (:func:`nested_sizes`); others give an empty table.
    values : ndarray, shape (n_points, n_outputs)
        The model values at ``design.points``.
    outputs : sequence of str

    Returns
    -------
    DataFrame
        :data:`COLUMNS`, one row per (sub-sample, output, parameter); ``n_evals`` the runs of the
        sub-sample, ``*_conf`` the method's error bound there.
    """
    method = get_method(design.method)
    y = np.asarray(values, dtype=float).reshape(design.n_points, -1)
    rows = []
    for m in nested_sizes(design, space.dim):
        sub = sub_design(design, m, space.dim)
        res = method.analyze(space, sub, y[sub_rows(design, m, space.dim)], outputs=list(outputs))
        t = res.indices[["output", "parameter", "S1", "S1_conf", "ST", "ST_conf", "trusted"]].copy()
        for q in ("S1", "ST"):
            err = np.asarray(res.extras.get(f"{q}_error", []), dtype=float)
            if err.size == len(t):                        # SALib's calibrated estimate, all outputs analysed
                t[f"{q}_conf"] = err.ravel()
        t.insert(0, "n_evals", sub.n_points)
        t.insert(0, "method", design.method)
        rows.append(t)
    if not rows:
        return pd.DataFrame(columns=COLUMNS)
    return pd.concat(rows, ignore_index=True)[COLUMNS]
