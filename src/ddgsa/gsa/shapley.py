"""Shapley effects for dependent (Gaussian-copula) inputs, with full and independent Sobol indices.

The Shapley effect of input *i* shares the output variance fairly among correlated inputs
(Owen 2014; Song, Nelson & Staum 2016, *SIAM/ASA J. Uncertain. Quantif.* 4):

.. math::

    Sh_i = \\frac{1}{d!\\,\\mathrm{Var}\\,Y} \\sum_{\\pi} \\bigl[c(P_i(\\pi) \\cup \\{i\\}) - c(P_i(\\pi))\\bigr],
    \\qquad c(J) = E\\bigl[\\mathrm{Var}(Y \\mid X_{-J})\\bigr],

with :math:`P_i(\\pi)` the inputs before *i* in the permutation :math:`\\pi`. The effects are
non-negative and sum to one whatever the dependence. Estimated here as Song et al.'s
Algorithm 1: ``n_v`` joint draws for :math:`\\mathrm{Var}\\,Y`; for every subset :math:`J` the
algorithm needs, ``n_o`` outer draws of :math:`X_{-J}` and ``n_i`` inner draws of
:math:`X_J \\mid X_{-J}` (exact Gaussian conditionals of the normal scores), :math:`c(J)` the
mean of the inner variances. ``permutations="exact"`` visits all :math:`d!` permutations (the
:math:`2^d - 2` subsets once each); an integer ``m`` draws ``m`` random permutations (cost
linear in ``m d``, for many inputs). Cost: ``n_v + n_subsets n_o n_i`` runs.

The same subset costs give the Mara-Tarantola indices that need no reordering: the **full
first-order** index :math:`S^{full}_i = 1 - c(-i)/\\mathrm{Var}\\,Y = \\mathrm{Var}(E[Y|X_i])/\\mathrm{Var}\\,Y`
(column ``S1``; it counts what *i* explains through its correlated partners) and the
**independent total** index :math:`S^{ind}_{T,i} = c(\\{i\\})/\\mathrm{Var}\\,Y` (column ``ST``;
what *i* explains beyond everything it is correlated with). For independent inputs they are
the ordinary S1 and ST, and :math:`S1_i \\le Sh_i \\le ST_i`. The other two (:math:`S^{ind}_i`,
:math:`S^{full}_{T,i}`) need conditional sampling in a reordered Rosenblatt transform and are
not given.

Error: a bootstrap (``num_resamples``) over the outer draws of every subset, the ``n_v`` draws
and, with random permutations, the permutations; its ``conf_level`` half-width is each index's
``_conf``. The error estimate is the sampling methods' rule (:mod:`ddgsa.gsa.salib`): the larger
of the half-width and SALib's ``_CONVERGENCE_FACTOR`` (2) times the difference between the
estimate and the one from the first half of the outer draws, variance sample and permutations
(column ``Sh_error``), with the half-width taken at the level that holds for the row's three
indices at once, since ``trusted`` claims all three (Bonferroni, each at ``1 - (1 - conf_level) / 3``:
1.22 times the 95 % half-width for normal errors). Measured on the linear Gaussian model at
``n_o = 4000``, 40 seeds: the per-index half-width alone covered 96 / 97 / 96 % of Sh / S1 / ST,
and with the half-sample rule still trusted 2 rows in 34 off by 0.022 and 0.028 (3-sigma errors
of S1 and ST, which share the variance sample's error); with the joint level, none in 97 trusted
rows of 720 (docs/beyond.md, "Trust and rank"). Diagnostic ``shapley_index_error`` (untrusted) where the
error estimate of Sh, S1 or ST exceeds ``tolerance``: a ``trusted`` row has all three within it.
The rows are ranked by ``Sh`` (``rank``, ``rank_confirmed``: :func:`~ddgsa.gsa.result.rank_structure`
with ``Sh_error`` as the bound), the importance measure that stays a share of the variance under
dependence.
"""

from __future__ import annotations

from itertools import combinations
from math import factorial
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.stats import norm

from ddgsa.errors import MethodError
from ddgsa.gsa.base import Design, GsaMethod, PartialIndices, check_fraction, check_int, register
from ddgsa.gsa.salib import _CONVERGENCE_FACTOR
from ddgsa.gsa.trust import DEFAULT_TOLERANCE, check_tolerance, error_diagnostics
from ddgsa.gsa.space import ParameterSpace

_MAX_EXACT_DIM = 8


@register("shapley")
class Shapley(GsaMethod):
    """Shapley effects (column ``Sh``), full first-order (``S1``) and independent total (``ST``) indices.

    Options
    -------
    permutations : "exact" or int
        All ``d!`` permutations (default; ``d <= 8``) or that many random ones.
    n_v : int
        Joint draws for the output variance, default 1000.
    n_o, n_i : int
        Outer and inner draws per subset, defaults 200 and 3 (Song et al. recommend ``n_i = 3``).
    seed, num_resamples, conf_level, tolerance
        As for ``saltelli``.
    """

    defaults = {"permutations": "exact", "n_v": 1000, "n_o": 200, "n_i": 3, "seed": 0, "num_resamples": 200,
                "conf_level": 0.95, "tolerance": DEFAULT_TOLERANCE}
    dependent_inputs = True
    rank_by = "Sh"

    def check_options(self, space: ParameterSpace, opts: dict[str, Any]) -> None:
        perms = opts["permutations"]
        if perms == "exact":
            if space.dim > _MAX_EXACT_DIM:
                raise MethodError(f"method 'shapley': permutations 'exact' visits {2 ** space.dim - 2} subsets for "
                                  f"{space.dim} inputs (limit {_MAX_EXACT_DIM} inputs); give a number of random "
                                  "permutations, e.g. permutations: 50")
        else:
            check_int(self.name, "permutations", perms, 1)
        check_int(self.name, "n_v", opts["n_v"], 10)
        check_int(self.name, "n_o", opts["n_o"], 2)
        check_int(self.name, "n_i", opts["n_i"], 2)
        check_int(self.name, "seed", opts["seed"], 0)
        check_int(self.name, "num_resamples", opts["num_resamples"], 10)
        check_fraction(self.name, "conf_level", opts["conf_level"])
        check_tolerance(self.name, opts["tolerance"])

    def _plan(self, space: ParameterSpace, opts: dict[str, Any]) -> tuple[list[tuple[int, ...]], NDArray[np.int64]]:
        """The subsets whose cost is needed (sorted tuples) and the permutations (m, d); exact: none listed."""
        d = space.dim
        if opts["permutations"] == "exact":
            subsets = [c for k in range(1, d) for c in combinations(range(d), k)]
            return subsets, np.zeros((0, d), dtype=np.int64)
        rng = np.random.default_rng([opts["seed"], 1])
        perms = np.array([rng.permutation(d) for _ in range(opts["permutations"])], dtype=np.int64)
        needed = {tuple(sorted(p[:j])) for p in perms for j in range(1, d)}
        needed |= {(i,) for i in range(d)} | {tuple(k for k in range(d) if k != i) for i in range(d)}
        return sorted(needed, key=lambda s: (len(s), s)), perms

    def _n_points(self, space: ParameterSpace, opts: dict[str, Any]) -> int:
        subsets, _ = self._plan(space, opts)
        return opts["n_v"] + len(subsets) * opts["n_o"] * opts["n_i"]

    def _design(self, space: ParameterSpace, opts: dict[str, Any]) -> Design:
        subsets, perms = self._plan(space, opts)
        rng = np.random.default_rng([opts["seed"], 0])
        corr = space.correlation_matrix
        chol = np.linalg.cholesky(corr)
        n_o, n_i, d = opts["n_o"], opts["n_i"], space.dim
        blocks = [space.from_normal(rng.standard_normal((opts["n_v"], d)) @ chol.T)]
        for varied in subsets:
            fixed = [k for k in range(d) if k not in varied]
            v = list(varied)
            outer = rng.standard_normal((n_o, d)) @ chol.T                     # z_{-J} from the joint law
            # z_J | z_{-J} ~ N(A z_{-J}, R_JJ - A R_{-J}J), A = R_J,-J R_-J,-J^-1
            a = np.linalg.solve(corr[np.ix_(fixed, fixed)], corr[np.ix_(fixed, v)]).T
            cond = corr[np.ix_(v, v)] - a @ corr[np.ix_(fixed, v)]
            lc = np.linalg.cholesky(cond + 1e-14 * np.eye(len(v)))
            z = np.repeat(outer, n_i, axis=0)
            z[:, v] = z[:, fixed] @ a.T + rng.standard_normal((n_o * n_i, len(v))) @ lc.T
            blocks.append(space.from_normal(z))
        meta = {"subsets": subsets, "perms": perms}
        return Design(self.name, np.vstack(blocks), opts, meta)

    def _analyze(self, space: ParameterSpace, design: Design, y: NDArray[np.float64],
                 outputs: list[str]) -> PartialIndices:
        o = design.options
        d, n_v, n_o, n_i = space.dim, o["n_v"], o["n_o"], o["n_i"]
        subsets, perms = design.meta["subsets"], design.meta["perms"]
        yv = y[:n_v]                                                           # (n_v, k)
        inner = y[n_v:].reshape(len(subsets), n_o, n_i, -1).var(axis=2, ddof=1)   # (S, n_o, k)
        rng = np.random.default_rng([o["seed"], 2])
        est = _indices(space.dim, subsets, perms, inner.mean(axis=1), yv.var(axis=0, ddof=1))
        reps = []
        for _ in range(o["num_resamples"]):
            pick = rng.integers(0, n_o, size=(len(subsets), n_o))
            cost = np.take_along_axis(inner, pick[:, :, None], axis=1).mean(axis=1)
            var = yv[rng.integers(0, n_v, n_v)].var(axis=0, ddof=1)
            p = perms[rng.integers(0, len(perms), len(perms))] if len(perms) else perms
            reps.append(_indices(d, subsets, p, cost, var))
        alpha = (1.0 - o["conf_level"]) / 2.0
        conf = [np.diff(np.quantile(np.stack([r[q] for r in reps]), [alpha, 1 - alpha], axis=0), axis=0)[0] / 2.0
                for q in range(3)]
        # the sampling methods' rule: the bootstrap half-width or the half-sample difference times
        # SALib's factor, whichever is larger (the first halves of the outer draws, of the variance
        # sample and of random permutations are an estimate of half the size from the same runs);
        # the half-width at the level that holds for the row's three indices at once (Bonferroni:
        # each at 1 - (1 - conf_level) / 3), scaled from the per-index one as normal quantiles are
        half = _indices(d, subsets, perms[:max(1, len(perms) // 2)], inner[:, :n_o // 2].mean(axis=1),
                        yv[:n_v // 2].var(axis=0, ddof=1))
        joint = norm.ppf(1.0 - alpha / 3.0) / norm.ppf(1.0 - alpha)
        err = [np.fmax(joint * conf[q], _CONVERGENCE_FACTOR * np.abs(est[q] - half[q])) for q in range(3)]
        sh, s1, st = est
        diags = error_diagnostics("shapley_index_error", f"bootstrap half-width ({o['num_resamples']} resamples) "
                                  "and half-sample difference", outputs, space.names, np.fmax(err[0], err[1]),
                                  err[2], o["tolerance"])
        return PartialIndices(S1=s1, ST=st, S1_conf=conf[1], ST_conf=conf[2], diagnostics=diags,
                              extras={"Sh_conf": conf[0], "n_subsets": len(subsets), "ST_error": err[2]},
                              columns={"Sh": sh, "Sh_conf": conf[0], "Sh_error": err[0]})


def _indices(d: int, subsets: list[tuple[int, ...]], perms: NDArray[np.int64], cost: NDArray[np.float64],
             var: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Sh, full S1 and independent ST, each (n_outputs, d), from the subset costs (S, k) and Var Y (k,)."""
    c = {s: cost[j] for j, s in enumerate(subsets)}
    c[()] = np.zeros_like(var)
    c[tuple(range(d))] = var
    sh = np.zeros((d, var.size))
    if len(perms):
        for p in perms:
            for j, i in enumerate(p):
                sh[i] += c[tuple(sorted(p[:j + 1]))] - c[tuple(sorted(p[:j]))]
        sh /= len(perms)
    else:                                      # all d! permutations: Shapley's subset weights
        for s in [(), *subsets]:
            w = factorial(len(s)) * factorial(d - len(s) - 1) / factorial(d)
            for i in set(range(d)) - set(s):
                sh[i] += w * (c[tuple(sorted((*s, i)))] - c[s])
    with np.errstate(divide="ignore", invalid="ignore"):
        s1 = np.stack([1.0 - c[tuple(k for k in range(d) if k != i)] / var for i in range(d)])
        st = np.stack([c[(i,)] / var for i in range(d)])
        return (sh / var).T, s1.T, st.T
