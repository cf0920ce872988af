"""HSIC screening: which inputs the output depends on at all, with a permutation-test p-value.

The Hilbert-Schmidt independence criterion between an input :math:`X_i` and the output
:math:`Y` (Gretton et al. 2005; Da Veiga 2015, *J. Stat. Comput. Simul.* 85) is zero exactly
when they are independent (for characteristic kernels). With Gaussian kernels
:math:`k(a, b) = \\exp(-(a - b)^2 / (2 \\sigma^2))`, :math:`\\sigma` each variable's sample
standard deviation, the V-statistic on ``n`` draws is

.. math::

    \\widehat{HSIC}(X_i, Y) = \\frac{1}{n^2} \\mathrm{tr}(K_i H L H), \\qquad H = I - \\tfrac{1}{n} 1 1^T,

and :math:`R^2_{HSIC,i} = HSIC(X_i, Y) / \\sqrt{HSIC(X_i, X_i)\\, HSIC(Y, Y)}` in [0, 1]
normalises it (columns ``HSIC``, ``R2_HSIC``). The p-value of "Y does not depend on X_i" is a
permutation test (``permutations`` shuffles of Y; column ``p_value``): screening keeps the
inputs with ``p_value < alpha``. These are the estimators of OpenTURNS'
``HSICEstimatorGlobalSensitivity`` with ``HSICVStat`` and ``SquaredExponential`` kernels of
scale :math:`\\sigma` (the tests compare with it).

HSIC is a dependence measure, not a share of variance: the rows carry no S1/ST (diagnostic
``hsic_screening``), and it needs far fewer runs than Sobol indices (one sample of ``n``
points for all inputs; ``n`` = 100-300 screens tens of inputs). For target sensitivity combine
it with an indicator output (:mod:`ddgsa.gsa.target`).

**Why no row is ever trusted** (issue 51.4: every estimator carries the same trust rule). ``trusted``
promises every index of the row within the tolerance of the truth. HSIC's rows hold no Sobol index,
and its own index has no error bound to judge: the V-statistic is biased upward by O(1/n) (an inert
input's R2_HSIC averages 0.014 at n = 150, its exact value 0: ``python -m ddgsa.bench.beyond_trust``),
and a bootstrap cannot bound it (resampling with replacement repeats points, which inflates a
V-statistic further). What HSIC does claim is the screening, and that claim is calibrated by
construction: an inert input is screened in with probability ``alpha`` (3 of 100 seeds at 0.05;
tested over seeds), while ``screened_in = 0`` is absence of evidence, never a confirmed independence
(Ishigami's x2, S1 = 0.44 through sin^2 x2, is screened in 5 times in 100: a kernel as wide as the
input's standard deviation does not see a period-pi effect).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ddgsa.gsa.base import Design, GsaMethod, PartialIndices, check_fraction, check_int, register
from ddgsa.gsa.result import Diagnostic
from ddgsa.gsa.space import ParameterSpace


def gaussian_gram(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """Centred Gram matrix ``H K H`` (n, n) of a Gaussian kernel with the sample standard deviation as scale."""
    s = v.std(ddof=1)
    k = np.exp(-((v[:, None] - v[None, :]) ** 2) / (2.0 * s * s)) if s > 0 else np.ones((v.size, v.size))
    return k - k.mean(axis=0) - k.mean(axis=1)[:, None] + k.mean()


def hsic_v(kc: NDArray[np.float64], lc: NDArray[np.float64]) -> float:
    """V-statistic ``tr(K H L H) / n^2`` from two centred Gram matrices."""
    return float((kc * lc).sum() / kc.shape[0] ** 2)


@register("hsic")
class HSIC(GsaMethod):
    """HSIC and R2-HSIC of every input with each output, with permutation p-values.

    Options: ``n`` (sample size, default 200), ``permutations`` (default 500), ``alpha``
    (screening level for the ``screened_in`` column, default 0.05), ``seed``.
    """

    defaults = {"n": 200, "permutations": 500, "alpha": 0.05, "seed": 0}
    gives_st = False
    gives_sobol = False

    def check_options(self, space: ParameterSpace, opts: dict[str, Any]) -> None:
        check_int(self.name, "n", opts["n"], 10, 5000)
        check_int(self.name, "permutations", opts["permutations"], 20)
        check_fraction(self.name, "alpha", opts["alpha"])
        check_int(self.name, "seed", opts["seed"], 0)

    def _n_points(self, space: ParameterSpace, opts: dict[str, Any]) -> int:
        return int(opts["n"])

    def _design(self, space: ParameterSpace, opts: dict[str, Any]) -> Design:
        return Design(self.name, space.sample(opts["n"], seed=opts["seed"], rule="lhs"), opts)

    def _analyze(self, space: ParameterSpace, design: Design, y: NDArray[np.float64],
                 outputs: list[str]) -> PartialIndices:
        o = design.options
        k, d = y.shape[1], space.dim
        grams = np.stack([gaussian_gram(design.points[:, i]) for i in range(d)])     # (d, n, n)
        self_x = np.array([hsic_v(g, g) for g in grams])
        out = {q: np.full((k, d), np.nan) for q in ("HSIC", "R2_HSIC", "p_value")}
        rng = np.random.default_rng([o["seed"], 3])
        perms = [rng.permutation(design.n_points) for _ in range(o["permutations"])]
        for j in range(k):
            lc = gaussian_gram(y[:, j])
            self_y = hsic_v(lc, lc)
            h = np.einsum("iab,ab->i", grams, lc) / design.n_points ** 2
            null = np.stack([np.einsum("iab,ab->i", grams, lc[p][:, p]) for p in perms]) / design.n_points ** 2
            out["HSIC"][j] = h
            out["R2_HSIC"][j] = h / np.sqrt(self_x * self_y) if self_y > 0 else np.nan
            out["p_value"][j] = (1 + np.sum(null >= h * (1 - 1e-12), axis=0)) / (1 + len(perms))
        diag = Diagnostic("hsic_screening", f"HSIC screening on {design.n_points} points: dependence measures "
                          "(HSIC, R2_HSIC) and permutation p-values, not Sobol indices (no S1/ST); never trusted "
                          "(R2_HSIC is biased upward by O(1/n) and has no error bound), the screening is a test at "
                          f"level alpha = {o['alpha']:g}", "untrusted")
        nan = np.full((k, d), np.nan)
        columns = {**out, "screened_in": (out["p_value"] < o["alpha"]).astype(float)}
        # the output's scale does not change R2_HSIC or the p-value; HSIC itself is of the standardised output
        return PartialIndices(S1=nan, ST=nan.copy(), diagnostics=[diag], columns=columns)
