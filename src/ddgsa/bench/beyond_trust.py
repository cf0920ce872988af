"""False trust of the estimators beyond S1/ST: groups, Shapley effects, target sensitivity, signals, HSIC.

Each estimator's ``trusted`` column (issue 51.4) is the rule of :mod:`ddgsa.gsa.trust` applied to its
own error bound; this module measures whether that promise holds on functions whose answers are known
in closed form, over seeds, as ``ddgsa bench trust`` does for the parameters' rows
(:mod:`ddgsa.bench.calibration`). Every row of every run is scored:

* **false trust**: the row is ``trusted`` and an index in it is off the exact one by more than the
  tolerance;
* **false rank**: the row's place is ``rank_confirmed`` and the exact indices contradict it
  (:func:`ddgsa.bench.calibration.false_rank_claims`).

HSIC has no ``trusted`` row (:mod:`ddgsa.gsa.hsic` says why); its screening claim is scored instead:
the share of seeds in which an inert input is screened in (the test's level ``alpha``, if honest)
and an influential one is not (a miss).

Run ``python -m ddgsa.bench.beyond_trust [--seeds N] [--out DIR]``: ``rows.csv.gz``, ``summary.csv``
and ``hsic.csv`` in ``results/trust_calibration/beyond/`` and the summary table on stdout;
docs/beyond.md quotes it.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from dataclasses import dataclass
from itertools import combinations
from math import factorial
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

import ddgsa
from ddgsa.bench.calibration import false_rank_claims
from ddgsa.gsa.signal import SignalAxis, sobol_signal
from ddgsa.gsa.target import target_function
from ddgsa.gsa.testfunctions import ishigami
from ddgsa.gsa.trust import DEFAULT_TOLERANCE

OUT = Path("results") / "trust_calibration" / "beyond"
Func = Callable[[NDArray[np.float64]], NDArray[np.float64]]


@dataclass(frozen=True)
class Scored:
    """One run's rows: estimates and exact values (n_rows, n_indices), trust, rank claims and labels."""

    est: NDArray[np.float64]
    exact: NDArray[np.float64]
    ranked: NDArray[np.float64]
    ranked_exact: NDArray[np.float64]
    trusted: NDArray[np.bool_]
    claims: NDArray[np.int8]
    ranks: NDArray[np.object_]
    n_evals: int


@dataclass(frozen=True)
class Case:
    """An estimator on a function with known answers: ``run(method, seed, options) -> Scored``."""

    estimator: str
    function: str
    settings: tuple[tuple[str, dict[str, Any]], ...]
    run: Callable[[str, int, dict[str, Any]], Scored]


def _claims(table: pd.DataFrame) -> tuple[NDArray[np.int8], NDArray[np.object_]]:
    """Claim codes (0 none, 1 negligible, 2 placed) and labels of a table with ``rank`` (one output)."""
    ranks = table["rank"].fillna("").astype(str).to_numpy(object)
    codes = np.where(ranks == "negligible", 1, np.where(ranks != "", 2, 0)).astype(np.int8)
    return codes, ranks


def _runner(make: Callable[[str], tuple[ddgsa.ParameterSpace, Func, NDArray[np.float64]]], name: str,
            groups: bool, columns: list[str], ranked: str) -> Callable[[str, int, dict[str, Any]], Scored]:
    """``run(method, seed, options)`` of ``ddgsa.sobol`` on case ``name`` of ``make``, scoring the table's
    ``columns`` (the parameters' rows, or ``res.groups`` with ``groups``) and its rank by ``ranked``."""
    def run(method: str, seed: int, opts: dict[str, Any]) -> Scored:
        space, f, exact = make(name)
        res = ddgsa.sobol(f, space, method=method, seed=seed, **opts)
        t = res.groups if groups else res.indices
        codes, ranks = _claims(t)
        return Scored(t[columns].to_numpy(float), exact, t[ranked].to_numpy(float), exact[:, columns.index(ranked)],
                      t["trusted"].to_numpy(bool), codes, ranks, res.n_evals)
    return run


# ---------------------------------------------------------------- groups

_ADDITIVE_A = np.array([4.0, 3.0, 2.0, 2.0, 1.0])
_ADDITIVE_GROUPS = {"g04": ["x0", "x4"], "g1": ["x1"], "g23": ["x2", "x3"]}
_ISHIGAMI_GROUPS = {"x12": ["x1", "x2"], "x3only": ["x3"]}
_S1, _S2, _S13 = 0.31391, 0.44241, 0.24368          # Ishigami (a = 7, b = 0.1)
_PRODUCT_A = np.array([1.0, 2.0, 0.5, 1.5])
_PRODUCT_GROUPS = {"g01": ["x0", "x1"], "g2": ["x2"], "g3": ["x3"]}


def _product_closed(members: list[int]) -> float:
    """Closed index of a group of prod (1 + a_i x_i^2), x ~ U(0, 1) [-]."""
    m, e2 = 1.0 + _PRODUCT_A / 3.0, 1.0 + 2.0 * _PRODUCT_A / 3.0 + _PRODUCT_A ** 2 / 5.0
    rest = [i for i in range(len(_PRODUCT_A)) if i not in members]
    var = np.prod(e2) - np.prod(m ** 2)
    return float(np.prod(m[rest] ** 2) * (np.prod(e2[members]) - np.prod(m[members] ** 2)) / var)


def _group_case(name: str) -> tuple[ddgsa.ParameterSpace, Func, NDArray[np.float64]]:
    """Space, function and exact (closed, total) index of each group."""
    if name == "additive":
        space = ddgsa.ParameterSpace.from_dict({f"x{i}": {"low": 0.0, "high": 1.0} for i in range(5)},
                                               groups=_ADDITIVE_GROUPS)
        return space, lambda x: x @ _ADDITIVE_A, np.array([[17 / 34] * 2, [9 / 34] * 2, [8 / 34] * 2])
    if name == "ishigami":
        tf = ishigami()
        space = ddgsa.ParameterSpace.from_dict(tf.space.to_dict(), groups=_ISHIGAMI_GROUPS)
        return space, tf.f, np.array([[_S1 + _S2, 1.0], [0.0, _S13]])
    space = ddgsa.ParameterSpace.from_dict({f"x{i}": {"low": 0.0, "high": 1.0} for i in range(4)},
                                           groups=_PRODUCT_GROUPS)
    idx = {"g01": [0, 1], "g2": [2], "g3": [3]}
    exact = np.array([[_product_closed(m), 1.0 - _product_closed([i for i in range(4) if i not in m])]
                      for m in idx.values()])
    return space, lambda x: np.prod(1.0 + _PRODUCT_A * x ** 2, axis=1), exact


# ---------------------------------------------------------------- Shapley

def _gaussian_v(beta: NDArray[np.float64], cov: NDArray[np.float64], j: tuple[int, ...]) -> float:
    """Var E[Y | X_J] of Y = beta . X, X ~ N(0, cov)."""
    if not j:
        return 0.0
    s = cov[:, list(j)]
    return float(beta @ s @ np.linalg.solve(cov[np.ix_(j, j)], s.T @ beta))


def exact_shapley(v: Callable[[tuple[int, ...]], float], d: int) -> NDArray[np.float64]:
    """Shapley effects, full first-order and independent total indices, (d, 3), from the closed-form
    ``v(J) = Var E[Y | X_J]`` of every subset (``v`` of all inputs is Var Y)."""
    full = tuple(range(d))
    var = v(full)
    out = np.zeros((d, 3))
    for i in range(d):
        others = [q for q in range(d) if q != i]
        for k in range(d):
            for j in combinations(others, k):
                w = factorial(k) * factorial(d - k - 1) / factorial(d)
                out[i, 0] += w * (v(tuple(sorted((*j, i)))) - v(j))
        out[i, 1] = v((i,))
        out[i, 2] = var - v(tuple(others))
    return out / var


def _shapley_case(name: str) -> tuple[ddgsa.ParameterSpace, Func, NDArray[np.float64]]:
    """Space, function and exact (Sh, full S1, independent ST) per input."""
    if name == "linear_gaussian":         # Iooss & Prieur 2019 eq. 11: sd (1, 1, 2), rho(x2, x3) = 0.6
        sd, rho = np.array([1.0, 1.0, 2.0]), 0.6
        space = ddgsa.ParameterSpace.from_dict({f"x{i + 1}": {"dist": "normal", "mean": 0.0, "std": s}
                                                for i, s in enumerate(sd)}, correlation=[("x2", "x3", rho)])
        cov = np.diag(sd ** 2)
        cov[1, 2] = cov[2, 1] = rho * sd[1] * sd[2]
        beta = np.ones(3)
        return space, lambda x: x @ beta, exact_shapley(lambda j: _gaussian_v(beta, cov, j), 3)
    tf = ishigami()                       # independent: Sh = S_i + half the shared S13
    exact = np.array([[_S1 + _S13 / 2, _S1, _S1 + _S13], [_S2, _S2, _S2], [_S13 / 2, 0.0, _S13]])
    return tf.space, tf.f, exact


# ---------------------------------------------------------------- target sensitivity

def _target_case(name: str) -> tuple[ddgsa.ParameterSpace, Func, NDArray[np.float64]]:
    """Space, transformed function and exact (S1, ST) per input (see tests/gsa/test_beyond.py)."""
    space = ddgsa.ParameterSpace.from_dict({"a": {"low": 0, "high": 1}, "b": {"low": 0, "high": 1}})
    if name == "sum_indicator":           # 1{a + b > 1}: E[.|a] = a
        return space, target_function(lambda x: x[:, 0] + x[:, 1], 1.0), np.array([[1 / 3, 2 / 3]] * 2)
    if name == "sum_excess":              # max(a + b - 1, 0): E[.|a] = a^2 / 2
        return space, target_function(lambda x: x[:, 0] + x[:, 1], 1.0, kind="excess"), np.array([[0.4, 0.6]] * 2)
    q = 0.6                               # 1{min(a, b) > 0.4}: a product of two Bernoulli(0.6)
    return space, target_function(lambda x: np.minimum(x[:, 0], x[:, 1]), 0.4), \
        np.array([[q / (1 + q), 1 / (1 + q)]] * 2)


# ---------------------------------------------------------------- signals

_T = np.linspace(0.0, 0.5, 33)
_W1, _W2 = np.sin(2 * np.pi * 2.0 * _T), np.sin(2 * np.pi * 5.0 * _T)
_VA, _VB = 1.0 / 3.0 + 4.0 / 45.0, 4.0 / 3.0


def _signal(x: NDArray[np.float64]) -> NDArray[np.float64]:
    """y(t) = (x1 + x1^2) sin(4 pi t) + 2 x2 sin(10 pi t), x ~ U(-1, 1), x3 inert (no interaction)."""
    return (x[:, :1] + x[:, :1] ** 2) * _W1 + 2.0 * x[:, 1:2] * _W2


def _run_signal(method: str, seed: int, opts: dict[str, Any]) -> Scored:
    space = ddgsa.ParameterSpace.from_dict({f"x{i}": {"low": -1.0, "high": 1.0} for i in (1, 2, 3)})
    res = sobol_signal(_signal, space, SignalAxis("time", "s", _T), method, signal="y", seed=seed, **opts)
    gen = _VA * (_W1 ** 2).sum() / (_VA * _W1 ** 2 + _VB * _W2 ** 2).sum()
    exact = np.array([[gen, gen], [1 - gen, 1 - gen], [0.0, 0.0]])
    g = res.generalised
    codes, ranks = _claims(g)
    return Scored(g[["S1", "ST"]].to_numpy(float), exact, g["ST"].to_numpy(float), exact[:, 1],
                  g["trusted"].to_numpy(bool), codes, ranks, res.n_evals)


# ---------------------------------------------------------------- the suite

_SAMPLING = (("saltelli", {"n": 1024}), ("saltelli", {"n": 4096}))
_SHAPLEY = (("shapley", {}), ("shapley", {"n_v": 4000, "n_o": 4000}), ("shapley", {"n_v": 16000, "n_o": 16000}))
_TARGET_SALTELLI = (("saltelli", {"n": 4096}), ("saltelli", {"n": 16384}))


def _groups(name: str) -> Callable[[str, int, dict[str, Any]], Scored]:
    return _runner(_group_case, name, True, ["S_closed", "ST"], "ST")


def _shapley(name: str) -> Callable[[str, int, dict[str, Any]], Scored]:
    return _runner(_shapley_case, name, False, ["Sh", "S1", "ST"], "Sh")


def _target(name: str) -> Callable[[str, int, dict[str, Any]], Scored]:
    return _runner(_target_case, name, False, ["S1", "ST"], "ST")


CASES = (
    Case("groups", "additive", (*_SAMPLING, ("saltelli", {"n": 16384}), ("pce", {}), ("mdrm", {})),
         _groups("additive")),
    Case("groups", "ishigami", (*_SAMPLING, ("pce", {"order": 9, "fit": "sparse", "n": 512}), ("mdrm", {})),
         _groups("ishigami")),
    Case("groups", "product", (*_SAMPLING, ("pce", {}), ("mdrm", {})), _groups("product")),
    Case("shapley", "linear_gaussian", _SHAPLEY, _shapley("linear_gaussian")),
    Case("shapley", "ishigami", _SHAPLEY, _shapley("ishigami")),
    Case("target", "sum_indicator", (*_TARGET_SALTELLI, ("pce", {}), ("mdrm", {})), _target("sum_indicator")),
    Case("target", "sum_excess", (_TARGET_SALTELLI[0], ("pce", {}), ("mdrm", {})), _target("sum_excess")),
    Case("target", "min_indicator", (*_TARGET_SALTELLI, ("mdrm", {})), _target("min_indicator")),
    Case("signal", "additive", (("saltelli", {"n": 1024, "num_resamples": 50}), ("pce", {"order": 3})), _run_signal),
)


def score(run: Scored, tolerance: float = DEFAULT_TOLERANCE) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """Per row: falsely trusted (an index off by more than ``tolerance``), falsely rank-confirmed."""
    with np.errstate(invalid="ignore"):
        off = ~(np.abs(run.est - run.exact) <= tolerance).all(axis=1)
    wrong_rank = false_rank_claims(run.ranked[None, :], run.ranked_exact[None, :], run.claims[None, :], tolerance,
                                   run.ranks[None, :])[0]
    return run.trusted & off, wrong_rank


def sweep(seeds: range | list[int], cases: tuple[Case, ...] = CASES,
          tolerance: float = DEFAULT_TOLERANCE) -> pd.DataFrame:
    """One line per (case, setting, seed, row): trusted, within (every index within ``tolerance``), false
    trust, rank claimed, false rank, runs and seconds."""
    lines = []
    for case in cases:
        for method, opts in case.settings:
            label = method + "".join(f" {k}={v}" for k, v in opts.items())
            for seed in seeds:
                t0 = time.perf_counter()
                run = case.run(method, seed, opts)
                false_trust, false_rank = score(run, tolerance)
                with np.errstate(invalid="ignore"):
                    within = (np.abs(run.est - run.exact) <= tolerance).all(axis=1)
                for r in range(len(run.trusted)):
                    lines.append({"estimator": case.estimator, "function": case.function, "setting": label,
                                  "seed": seed, "row": r, "trusted": bool(run.trusted[r]), "within": bool(within[r]),
                                  "false_trust": bool(false_trust[r]), "rank_claimed": bool(run.claims[r] > 0),
                                  "false_rank": bool(false_rank[r]), "n_evals": run.n_evals,
                                  "seconds": time.perf_counter() - t0})
    return pd.DataFrame(lines)


def summarise(rows: pd.DataFrame) -> pd.DataFrame:
    """Per (estimator, function, setting): rows, trusted, false trust, within-tolerance rows left untrusted,
    rank claims and false ones, runs per result."""
    g = rows.groupby(["estimator", "function", "setting"], sort=False)
    return pd.DataFrame({
        "seeds": g["seed"].nunique(), "rows": g.size(), "trusted": g["trusted"].sum(),
        "false_trust": g["false_trust"].sum(), "within": g["within"].sum(),
        "within_untrusted": g.apply(lambda t: int((t["within"] & ~t["trusted"]).sum()), include_groups=False),
        "rank_claims": g["rank_claimed"].sum(), "false_rank": g["false_rank"].sum(), "runs": g["n_evals"].first(),
    }).reset_index()


def hsic_screening(seeds: range | list[int], n: int = 150, permutations: int = 200,
                   alpha: float = 0.05) -> pd.DataFrame:
    """HSIC on Ishigami with an inert fourth input, per seed: each input's p-value, R2_HSIC and verdict."""
    tf = ishigami()
    space = ddgsa.ParameterSpace.from_dict({**tf.space.to_dict(), "x4": {"low": -np.pi, "high": np.pi}})
    rows = []
    for seed in seeds:
        t = ddgsa.sobol(lambda x: tf.f(x[:, :3]), space, method="hsic", n=n, permutations=permutations,
                        alpha=alpha, seed=seed).indices
        rows += [{"seed": seed, "parameter": r.parameter, "p_value": r.p_value, "R2_HSIC": r.R2_HSIC,
                  "screened_in": bool(r.screened_in), "inert": r.parameter == "x4"} for r in t.itertuples()]
    return pd.DataFrame(rows)


def main(argv: list[str] | None = None) -> None:
    """Run the sweep and the HSIC screening check; write ``rows.csv.gz``, ``summary.csv``, ``hsic.csv``."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    rows = sweep(range(args.seeds))
    rows.to_csv(args.out / "rows.csv.gz", index=False)
    summary = summarise(rows)
    summary.to_csv(args.out / "summary.csv", index=False)
    hsic = hsic_screening(range(args.seeds * 5))
    hsic.to_csv(args.out / "hsic.csv", index=False)
    print(summary.to_string(index=False))
    print(hsic.groupby("parameter")[["screened_in", "R2_HSIC", "p_value"]].mean().to_string())


if __name__ == "__main__":
    main()
