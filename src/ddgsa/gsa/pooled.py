"""A cross-check at zero extra runs: a sparse PCE fitted on every point a scene already has.

A study's methods evaluate their own designs (M-DRM's cut lines and check sample, PCE and
Saltelli samples). Pooled, with each point at its true input values, they are one scattered
design on which a sparse PCE (least-angle regression, :mod:`ddgsa.gsa.pce`) can be fitted; its
indices carry the same leave-one-out error bound as any sparse PCE (the rule ``auto`` uses on
exactly such pooled designs, calibrated by ``ddgsa bench trust``). The result is reported as
method ``pooled_pce`` beside the study's own.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ddgsa.gsa.base import Design, get_method
from ddgsa.gsa.pce import _MAX_MATRIX_ENTRIES, n_terms
from ddgsa.gsa.result import SobolResult
from ddgsa.gsa.trust import DEFAULT_TOLERANCE
from ddgsa.gsa.space import ParameterSpace

NAME = "pooled_pce"
MAX_ORDER = 5


def pooled_order(dim: int, n_points: int, max_order: int = MAX_ORDER, max_entries: int = _MAX_MATRIX_ENTRIES) -> int:
    """The highest total degree (<= ``max_order``) whose basis is at most twice the points (sparse
    regression selects a few terms of it) and whose matrix (points x terms) holds at most
    ``max_entries``; 0 if none."""
    order = 0
    for q in range(1, max_order + 1):
        p = n_terms(dim, q)
        if p <= 2 * n_points and p * n_points <= max_entries:
            order = q
    return order


def pooled_pce(space: ParameterSpace, x: NDArray[np.float64], y: NDArray[np.float64], outputs: list[str],
               tolerance: float = DEFAULT_TOLERANCE, max_order: int = MAX_ORDER,
               max_entries: int = _MAX_MATRIX_ENTRIES, drawn: NDArray[np.bool_] | None = None) -> SobolResult | None:
    """Sparse-PCE indices from the pooled points ``x`` (n, d) and values ``y`` (n, k) (an output
    with a failed point is refused, as by every method), of the order :func:`pooled_order` picks;
    None when the points are too few even for order 1 (``d + 1`` terms > ``2 n``). ``drawn`` (n,)
    marks the points drawn from the input distribution: the leave-one-out error is then their mean
    square only (:func:`ddgsa.gsa.pce._sparse_fit`)."""
    order = pooled_order(space.dim, len(x), max_order, max_entries)
    if order == 0:
        return None
    m = get_method("pce")
    design = Design("pce", x, {**m.defaults, "order": order, "fit": "sparse", "n": len(x), "seed": 0,
                               "tolerance": tolerance}, {} if drawn is None else {"drawn": drawn})
    res = m.analyze(space, design, y, outputs=outputs)
    res.method = NAME
    return res
