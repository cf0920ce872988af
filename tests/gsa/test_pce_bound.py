"""The least-squares PCE's second-order index bound (``ddgsa.gsa.pce.second_order_error``): its
sampling part against the spread of independent replicate fits, and its coverage where the
worst-case bound is loose."""

from __future__ import annotations

import numpy as np

import ddgsa
from ddgsa.gsa.pce import (_LOO_FACTOR, _least_squares, _Sampling, basis_matrix, second_order_error,
                           total_degree_indices)
from ddgsa.gsa.space import ParameterSpace
from ddgsa.gsa.trust import surrogate_index_error
from ddgsa.gsa.testfunctions import ishigami


def _fit_st(tf, order: int, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """ST of a regression PCE on a scrambled Sobol' sample and its delta-method standard errors."""
    alphas = total_degree_indices(tf.space.dim, order)
    x = tf.space.sample(n, seed=seed, rule="sobol")
    psi = basis_matrix(tf.space, alphas, x)
    coef, _, sampling = _least_squares(psi, tf.f(x)[:, None])
    involved = np.vstack([np.zeros((1, tf.space.dim), dtype=bool), alphas[1:] > 0])
    energy = coef[1:, 0] ** 2
    st = (involved[1:].T.astype(float) @ energy) / energy.sum()
    fit = sampling[0]
    assert isinstance(fit, _Sampling)
    return st, fit.index_sd(coef[:, 0], involved)


def test_the_sampling_error_matches_the_spread_of_independent_fits() -> None:
    # Ishigami at order 5 on 128 points: the truncation leaves a residual that aliases into the
    # coefficients; 40 independently scrambled designs give the indices' actual spread
    tf = ishigami()
    fits = [_fit_st(tf, 5, 128, seed) for seed in range(40)]
    spread = np.std([st for st, _ in fits], axis=0, ddof=1)
    predicted = np.median([sd for _, sd in fits], axis=0)
    # HC3 on leave-one-out residuals is conservative by design, never optimistic by much
    assert np.all(predicted >= 0.7 * spread), (predicted, spread)
    assert np.all(predicted <= 4.0 * spread), (predicted, spread)


def test_the_bound_covers_the_error_where_the_worst_case_is_loose() -> None:
    # Ishigami at order 8 on 512 points: errors ~1e-3, leave-one-out error ~2e-3
    tf = ishigami()
    for seed in range(6):
        res = ddgsa.sobol(tf.f, tf.space, "pce", order=8, n=512, seed=seed)
        t = res.indices
        err1, errt = np.abs(t["S1"] - tf.S1), np.abs(t["ST"] - tf.ST)
        assert np.all(err1 <= t["S1_conf"]) and np.all(errt <= t["ST_conf"])
        assert res.trusted
        # the worst case alone (first order in the distance) is several times wider
        eps = np.sqrt(_LOO_FACTOR * res.extras["loo_error"][0])     # Var g = Var y within 1 % here
        assert np.all(surrogate_index_error(t["ST"].to_numpy(), eps) > 2.5 * t["ST_conf"])


def test_the_second_order_term_is_attained_and_tighter_than_eps2() -> None:
    # coefficients (1, sqrt 3) on x1's and x2's terms: S_x1 = 1/4; an outside energy b = 0.2 V moves it
    # to (1 + b) / (4 + b) when all of b is in x1's terms and to 1 / (4 + b) when none is
    var, b = 4.0, 0.8
    shifts = np.array([(1.0 + b) / (var + b) - 0.25, 1.0 / (var + b) - 0.25])
    bound = second_order_error(np.array([0.25]), np.array([0.0]), b / var)[0]
    assert np.isclose(bound, np.abs(shifts).max(), rtol=1e-12)            # attained
    assert bound < (b / var) / (1.0 + b / var) - 0.04                     # the old term: 0.167 for 0.125


def test_the_bound_covers_an_index_moved_by_a_term_outside_the_basis() -> None:
    # f = psi1(x1) + sqrt(3) psi1(x2) + beta psi6(x1) on [-1, 1]^2 (orthonormal Legendre psi_k =
    # sqrt(2k + 1) P_k): at order 5 the psi6 term lies outside the basis and only in x1's part, so
    # the fit reads S_x1 ~ 1/4 against the true (1 + beta^2) / (4 + beta^2)
    space = ParameterSpace.from_dict({"x1": {"low": -1.0, "high": 1.0}, "x2": {"low": -1.0, "high": 1.0}})
    beta = 0.6
    p6 = np.polynomial.legendre.Legendre.basis(6)

    def f(x: np.ndarray) -> np.ndarray:
        return np.sqrt(3.0) * x[:, 0] + 3.0 * x[:, 1] + beta * np.sqrt(13.0) * p6(x[:, 0])

    true_s1 = (1.0 + beta ** 2) / (4.0 + beta ** 2)
    alphas = total_degree_indices(2, 5)
    involved = np.vstack([np.zeros((1, 2), dtype=bool), alphas[1:] > 0])
    alone = involved & (involved.sum(axis=1, keepdims=True) == 1)
    for seed in range(4):
        x = space.sample(1024, seed=seed, rule="sobol")
        y = f(x)[:, None]
        coef, loo, sampling = _least_squares(basis_matrix(space, alphas, x), y)
        energy = coef[1:, 0] ** 2
        s1 = (alone[1:].T.astype(float) @ energy) / energy.sum()
        sd = sampling[0].index_sd(coef[:, 0], alone)
        e2 = _LOO_FACTOR * loo[0] * np.var(y) / energy.sum()
        bound = second_order_error(s1, sd, e2)
        assert abs(s1[0] - true_s1) >= 0.05                                  # the outside term matters
        assert abs(s1[0] - true_s1) <= bound[0]
        assert np.all(bound < 4.0 * sd + e2 / (1.0 + e2) - 0.03)           # tighter than the old term
