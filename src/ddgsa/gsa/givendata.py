"""First-order indices from data already run, at zero extra model runs.

**Rank estimator** (Gamboa, Janon, Klein & Lagnoux 2022, *Bernoulli* 28; the idea behind
Chatterjee's rank correlation): sort a sample of ``(x_i, y)`` by ``x_i`` and pair each output with
its neighbour's,

.. math:: S_i \\approx \\frac{\\frac1n \\sum_j y_{(j)} y_{(j+1)} - \\bar y^2}{\\frac1n \\sum_j y_j^2 - \\bar y^2}

(cyclically, ``y_{(n+1)} = y_{(1)}``; OpenTURNS' ``RankSobolSensitivityAlgorithm``). Neighbours in
``x_i`` share ``E[y | x_i]`` and, for *independent* draws, nothing else. The study's samples are
quasi-random (scrambled Sobol'): there neighbours in ``x_i`` have strongly related other
coordinates, and the estimator is wrong by up to 0.5 on Ishigami at 2 048 points. So the sample
is tested first: the rank estimator of each coordinate ``x_k`` given ``x_i`` (exactly 0 for
independent draws) must stay below ``INDEPENDENT_Z / sqrt(n)``.

**Binned estimator** (the correlation ratio), for a sample that fails the test: ``x_i`` split into
``round(sqrt(n))`` bins of equal count; ``S_i`` is the between-bin variance of the bin means less
its sampling part ``(B - 1) s_w^2 / n`` (``s_w^2`` the within-bin variance), over the output's
variance. Stratified other coordinates make its bin means better, not worse.

Any sample of points *drawn from the input distribution* serves -- M-DRM's check sample,
Saltelli's ``A`` and ``B`` matrices, PCE samples -- but not M-DRM's cut lines or Saltelli's
``AB`` rows (their coordinates repeat other points'): :func:`drawn_rows`.

Error bound: the estimator on :data:`HALVES` random halves of the sample (without replacement)
differs from the whole sample's by about the whole sample's standard deviation and, on average,
by its bias (which grows as ``1/n``); the bound is ``|mean difference| + Z_HALVES sd(difference)``
(``ddgsa bench trust`` reports its coverage). The estimators give no total index, so the rows are
never ``trusted`` (which needs S1 and ST): method ``given_data_s1`` is a cross-check shown beside
the study's methods.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ddgsa.gsa.base import Design, standardise
from ddgsa.gsa.result import Diagnostic, SobolResult
from ddgsa.gsa.trust import DEFAULT_TOLERANCE
from ddgsa.gsa.space import ParameterSpace

NAME = "given_data_s1"
HALVES = 40
Z_HALVES = 4.0
INDEPENDENT_Z = 4.0
MIN_POINTS = 16


def rank_s1(x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.float64]:
    """The rank estimator of every first-order index: (n_outputs, d) from points ``x`` (n, d) and
    finite values ``y`` (n, k) (see the module). Ties in ``x_i`` are ordered by position."""
    y = np.asarray(y, dtype=float)
    yc = y - y.mean(axis=0)
    var = (yc ** 2).mean(axis=0)
    out = np.empty((y.shape[1], x.shape[1]))
    for i in range(x.shape[1]):
        order = np.argsort(x[:, i], kind="stable")
        ys = yc[order]
        out[:, i] = (ys * np.roll(ys, -1, axis=0)).mean(axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        return out / var[:, None]


def binned_s1(x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.float64]:
    """The binned (correlation-ratio) estimator of every first-order index: (k, d) (see the module)."""
    y = np.asarray(y, dtype=float)
    n = len(x)
    n_bins = max(2, int(round(np.sqrt(n))))
    yc = y - y.mean(axis=0)
    var = (yc ** 2).mean(axis=0)
    edges = np.linspace(0, n, n_bins + 1).astype(int)
    counts = np.diff(edges)[:, None]
    out = np.empty((y.shape[1], x.shape[1]))
    for i in range(x.shape[1]):
        ys = yc[np.argsort(x[:, i], kind="stable")]
        sums = np.add.reduceat(ys, edges[:-1], axis=0)
        means = sums / counts
        between = (counts * means ** 2).sum(axis=0) / n
        within = ((ys ** 2).sum(axis=0) - (counts * means ** 2).sum(axis=0)) / (n - n_bins)
        out[:, i] = between - (n_bins - 1) / n * within
    with np.errstate(divide="ignore", invalid="ignore"):
        return out / var[:, None]


def independent(x: NDArray[np.float64]) -> bool:
    """Whether neighbours in each coordinate look independent in the others: the rank estimator of
    every ``x_k`` given ``x_i`` (``i != k``; 0 in expectation for independent draws, noise about
    ``1 / sqrt(n)``) below ``INDEPENDENT_Z / sqrt(n)``."""
    if x.shape[1] < 2:
        return True
    s = rank_s1(x, (x - x.mean(axis=0)) / np.where(x.std(axis=0) > 0, x.std(axis=0), 1.0))
    np.fill_diagonal(s, 0.0)
    return bool(np.abs(s).max() <= INDEPENDENT_Z / np.sqrt(len(x)))


def s1_with_bound(x: NDArray[np.float64], y: NDArray[np.float64], seed: int = 0
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64], str]:
    """Indices (k, d), their error bounds (k, d) from :data:`HALVES` random halves, and the
    estimator used (``rank`` for an independent sample, else ``binned``; see the module)."""
    kind = "rank" if independent(x) else "binned"
    est = rank_s1 if kind == "rank" else binned_s1
    full = est(x, y)
    rng = np.random.default_rng(seed)
    n = len(x)
    diffs = np.array([est(x[idx], y[idx]) - full
                      for idx in (rng.choice(n, n // 2, replace=False) for _ in range(HALVES))])
    bound = np.abs(diffs.mean(axis=0)) + Z_HALVES * diffs.std(axis=0, ddof=1)
    return full, bound, kind


def drawn_rows(design: Design) -> NDArray[np.bool_]:
    """Rows of ``design.points`` that are draws from the input distribution, none sharing
    coordinates with another: M-DRM's check sample, Saltelli's ``A`` and ``B`` rows (and a control
    variate's pilot), a PCE regression sample; nothing of the others (quadrature, cut lines, a group's
    ``AB_u`` rows, FAST's search curve)."""
    n = design.n_points
    mask = np.zeros(n, dtype=bool)
    o = design.options
    if design.method == "mdrm" and o.get("check"):
        mask[n - int(o["check"]):] = True
    elif design.method == "saltelli":
        d = design.points.shape[1]
        rows = int(o["n"]) * (d + 2)                  # then a group's AB_u rows or a control variate's pilot
        block = np.arange(rows) % (d + 2)
        mask[:rows] = (block == 0) | (block == d + 1)
        pilot = int(design.meta.get("pilot", 0))
        if pilot:
            mask[n - pilot:] = True
    elif design.method == "pce" and o.get("fit") != "quadrature":
        mask[:] = True
    return mask


def given_data_s1(space: ParameterSpace, x: NDArray[np.float64], y: NDArray[np.float64], outputs: list[str],
                  tolerance: float = DEFAULT_TOLERANCE, seed: int = 0) -> SobolResult | None:
    """Given-data S1 with bounds (``S1_conf``) from drawn points ``x`` (n, d) and values
    ``y`` (n, k); outputs with a failed point or no spread get NaN and a diagnostic, as by every
    method; None below :data:`MIN_POINTS` points."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float).reshape(len(x), len(outputs))
    if len(x) < MIN_POINTS:
        return None
    S1 = np.full((len(outputs), space.dim), np.nan)
    bound = np.full_like(S1, np.nan)
    kind = "rank" if independent(x) else "binned"
    diags = [Diagnostic("given_data_first_order_only", f"the {kind} estimator gives first-order indices only, "
                        f"from {len(x)} drawn points at no extra runs: a cross-check, never trusted"
                        + ("" if kind == "rank" else " (binned: the points are quasi-random, neighbours in one "
                           "input are not independent in the others, which the rank estimator needs)"),
                        "untrusted")]
    usable = np.isfinite(y).all(axis=0) & (np.nanstd(y, axis=0) > 0)
    for j in np.flatnonzero(~usable):
        diags.append(Diagnostic("given_data_unusable", f"output {outputs[j]!r}: a failed point or no spread among "
                                f"the {len(x)} drawn points", "untrusted", output=outputs[j]))
    if usable.any():
        cols = np.flatnonzero(usable)
        shift, scale = standardise(y[:, cols])
        S1[cols], bound[cols], _ = s1_with_bound(x, (y[:, cols] - shift) / scale, seed)
    return SobolResult.from_arrays(outputs=outputs, parameters=space.names, S1=S1, ST=np.full_like(S1, np.nan),
                                   S1_conf=bound, n_evals=len(x), method=NAME,
                                   options={"n": len(x), "estimator": kind, "halves": HALVES, "tolerance": tolerance},
                                   diagnostics=diags)
