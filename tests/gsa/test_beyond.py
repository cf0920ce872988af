"""Groups, dependent inputs (Shapley), target sensitivity and HSIC against analytic answers and OpenTURNS."""

from __future__ import annotations

from itertools import combinations
from math import factorial

import numpy as np
import pytest

import ddgsa
from ddgsa.errors import MethodError, SpaceError
from ddgsa.gsa.target import Target, target_function
from ddgsa.gsa.testfunctions import ishigami

# Ishigami (a = 7, b = 0.1): S1 = 0.3139, S2 = 0.4424, S3 = 0, S13 = 0.2437, no other interaction
_S1, _S2, _S13 = 0.31391, 0.44241, 0.24368




def _check_groups(res: ddgsa.SobolResult, truth: np.ndarray, tol: float) -> None:
    g = res.groups.set_index("group")
    assert list(g.columns[:2]) == ["output", "members"] and g.loc["x12", "members"] == "x1 x2"
    est = g[["S_closed", "ST"]].to_numpy(float)
    np.testing.assert_allclose(est, truth, atol=tol)
    assert np.all(np.abs(est - truth) <= g[["S_closed_conf", "ST_conf"]].to_numpy(float) + 0.005)  # honest bounds


_ISHIGAMI_GROUPS = np.array([[_S1 + _S2, 1.0], [0.0, _S13]])
"""{x1, x2}: closed = S1 + S2 + S12 = 0.756, total = 1 - closed{x3} = 1; {x3}: closed 0, total S13."""


def test_saltelli_group_indices_of_ishigami() -> None:
    tf = ishigami()
    space = ddgsa.ParameterSpace.from_dict(tf.space.to_dict(), groups={"x12": ["x1", "x2"], "x3only": ["x3"]})
    res = ddgsa.sobol(tf.f, space, method="saltelli", n=2048)
    _check_groups(res, _ISHIGAMI_GROUPS, 0.04)
    assert res.n_evals == 2048 * (3 + 2 + 1)          # one extra matrix for the one group of two


@pytest.mark.slow
def test_pce_group_indices_of_ishigami() -> None:
    tf = ishigami()
    space = ddgsa.ParameterSpace.from_dict(tf.space.to_dict(), groups={"x12": ["x1", "x2"], "x3only": ["x3"]})
    _check_groups(ddgsa.sobol(tf.f, space, method="pce", order=9, fit="sparse", n=512), _ISHIGAMI_GROUPS, 0.02)


def test_pce_group_indices_of_a_polynomial_with_an_interaction() -> None:
    """Y = x1 + x2 + x1 x3, x ~ U(-1, 1): variances 1/3, 1/3, 1/9 of 7/9, so {x1, x2} has closed
    index 6/7 and total 1, {x3} closed 0 and total 1/7 (the PCE of order 2 is exact)."""
    space = ddgsa.ParameterSpace.from_dict({f"x{i}": {"low": -1, "high": 1} for i in (1, 2, 3)},
                                           groups={"x12": ["x1", "x2"], "x3only": ["x3"]})
    res = ddgsa.sobol(lambda x: x[:, 0] + x[:, 1] + x[:, 0] * x[:, 2], space, method="pce", order=2)
    _check_groups(res, np.array([[6 / 7, 1.0], [0.0, 1 / 7]]), 1e-9)


def test_mdrm_closed_group_indices_of_a_product() -> None:
    """A product of independent factors: Var E[Y|X_u] = prod_{not u} m^2 (prod_u E f^2 - prod_u m^2)."""
    a = np.array([1.0, 2.0, 0.5])
    space = ddgsa.ParameterSpace.from_dict({f"x{i}": {"low": 0.0, "high": 1.0} for i in range(3)},
                                           groups={"g01": ["x0", "x1"], "g2": ["x2"]})
    f = lambda x: np.prod(1.0 + a * x ** 2, axis=1)                   # noqa: E731
    m = 1.0 + a / 3.0                                                 # E[1 + a x^2]
    e2 = 1.0 + 2.0 * a / 3.0 + a ** 2 / 5.0                           # E[(1 + a x^2)^2]
    var = np.prod(e2) - np.prod(m ** 2)

    def closed(u: list[int]) -> float:
        rest = [i for i in range(3) if i not in u]
        return float(np.prod(m[rest] ** 2) * (np.prod(e2[u]) - np.prod(m[u] ** 2)) / var)

    res = ddgsa.sobol(f, space, method="mdrm", points=4)
    g = res.groups.set_index("group")
    np.testing.assert_allclose(g.loc["g01", "S_closed"], closed([0, 1]), atol=1e-10)
    np.testing.assert_allclose(g.loc["g01", "ST"], 1.0 - closed([2]), atol=1e-10)
    np.testing.assert_allclose(g.loc["g2", "S_closed"], closed([2]), atol=1e-10)
    assert (g["S_closed_conf"] < 0.01).all()
    assert g["trusted"].all() and g["rank"].tolist() == ["1", "2"]       # ST 0.79 and 0.31, bounds < 0.01


_ADDITIVE_A = np.array([4.0, 3.0, 2.0, 2.0, 1.0])
_ADDITIVE_GROUPS = {"g04": ["x0", "x4"], "g1": ["x1"], "g23": ["x2", "x3"]}


def _additive_groups() -> tuple[ddgsa.ParameterSpace, np.ndarray]:
    """Y = 4 x0 + 3 x1 + 2 x2 + 2 x3 + x4, x ~ U(0, 1): no interaction, so a group's closed and total
    indices both equal its members' share of sum a_i^2 = 34: {x0, x4} 17/34, {x1} 9/34, {x2, x3} 8/34."""
    space = ddgsa.ParameterSpace.from_dict({f"x{i}": {"low": 0.0, "high": 1.0} for i in range(5)},
                                           groups=_ADDITIVE_GROUPS)
    return space, np.array([[17 / 34] * 2, [9 / 34] * 2, [8 / 34] * 2])


@pytest.mark.parametrize("method,options", [("pce", {"order": 2}), ("saltelli", {"n": 4096, "seed": 1}),
                                            ("mdrm", {"points": 3})])
def test_group_rows_are_trusted_and_ranked_only_within_their_bounds(method: str, options: dict) -> None:
    """Every trusted group row is within the tolerance (0.02) of the closed form and every rank claimed
    is the exact one (17/34 > 9/34 > 8/34, the last two 0.029 apart). PCE of order 2 is exact (bounds
    0, all trusted and ranked); Saltelli's bounds at n = 4 096 (0.02-0.03) hold the error; M-DRM's product
    form is off by up to 0.012 on an additive function, which its check sample bounds by ~0.19 and its
    cross-check (a sparse PCE on the same points, exact here) by the distance to it: trusted and ranked."""
    space, truth = _additive_groups()
    res = ddgsa.sobol(lambda x: x @ _ADDITIVE_A, space, method=method, **options)
    g = res.groups.set_index("group")
    est = g[["S_closed", "ST"]].to_numpy(float)
    assert np.all(np.abs(est - truth)[g["trusted"].to_numpy()] <= 0.02)
    placed = g[g["rank_confirmed"]]
    assert placed["rank"].tolist() == [{"g04": "1", "g1": "2", "g23": "3"}[k] for k in placed.index]
    if method == "pce":
        np.testing.assert_allclose(est, truth, atol=1e-9)
        assert g["trusted"].all() and g["rank"].tolist() == ["1", "2", "3"]
    elif method == "saltelli":
        assert np.all(np.abs(est - truth) <= g[["S_closed_conf", "ST_conf"]].to_numpy(float))
        assert g["rank"].tolist() == ["1", "2", "3"]
    else:
        assert np.all(np.abs(est - truth) <= g[["S_closed_conf", "ST_conf"]].to_numpy(float) + 1e-9)
        assert g["trusted"].all() and g["rank"].tolist() == ["1", "2", "3"]
        assert np.abs(est - truth).max() > 0.005              # not exact: the bound is the cross-check's


def test_a_rule_on_a_member_voids_its_group_only() -> None:
    """A rule that voids a parameter's row (M-DRM's unresolved cut function) voids the group holding it,
    not the others; a parameter's own error estimate does not (the group has its own bound), and a
    group bound over the tolerance leaves the row untrusted but its rank claimed."""
    from ddgsa.gsa.groups import GroupIndices, group_frame
    from ddgsa.gsa.result import Diagnostic

    gi = GroupIndices(np.array([[0.6, 0.3]]), np.array([[0.7, 0.35]]), np.full((1, 2), 0.005), np.full((1, 2), 0.005))
    groups = {"a": ("x0", "x1"), "b": ("x2",)}
    clean = group_frame(["y"], groups, gi)
    assert clean["trusted"].tolist() == [True, True] and clean["rank"].tolist() == ["1", "2"]
    voided = group_frame(["y"], groups, gi, [Diagnostic("mdrm_unresolved", "x1 unresolved", "untrusted", "y", "x1"),
                                             Diagnostic("mdrm_index_error", "x2's own bound", "untrusted", "y", "x2")])
    assert voided["trusted"].tolist() == [False, True] and voided["rank"].tolist() == ["", ""]
    loose = group_frame(["y"], groups, GroupIndices(gi.S_closed, gi.ST, np.full((1, 2), 0.03), gi.ST_conf))
    assert loose["trusted"].tolist() == [False, False] and loose["rank"].tolist() == ["1", "2"]


def test_fast_gives_no_group_indices_and_groups_are_validated() -> None:
    tf = ishigami()
    space = ddgsa.ParameterSpace.from_dict(tf.space.to_dict(), groups={"g": ["x1", "x2"]})
    assert ddgsa.sobol(tf.f, space, method="rbd_fast", n=256).groups.empty
    with pytest.raises(SpaceError, match=r"groups.g: 'x9' is not a parameter"):
        ddgsa.ParameterSpace.from_dict(tf.space.to_dict(), groups={"g": ["x1", "x9"]})
    with pytest.raises(SpaceError, match=r"groups.h: 'x1' is already in group 'g'"):
        ddgsa.ParameterSpace.from_dict(tf.space.to_dict(), groups={"g": ["x1"], "h": ["x1", "x2"]})


def _linear_gaussian(rho: float) -> tuple[ddgsa.ParameterSpace, np.ndarray, np.ndarray]:
    sd = np.array([1.0, 1.0, 2.0])
    space = ddgsa.ParameterSpace.from_dict({f"x{i + 1}": {"dist": "normal", "mean": 0.0, "std": s}
                                            for i, s in enumerate(sd)}, correlation=[("x2", "x3", rho)])
    cov = np.diag(sd ** 2)
    cov[1, 2] = cov[2, 1] = rho * sd[1] * sd[2]
    return space, cov, sd


def _exact_shapley(beta: np.ndarray, cov: np.ndarray) -> np.ndarray:
    """Shapley effects from Var E[Y|X_J] = b^T S_.J S_JJ^-1 S_J. b of a Gaussian (Owen & Prieur 2017)."""
    d, var = len(beta), beta @ cov @ beta

    def v(j: tuple[int, ...]) -> float:
        if not j:
            return 0.0
        s = cov[:, list(j)]
        return float(beta @ s @ np.linalg.solve(cov[np.ix_(j, j)], s.T @ beta))
    sh = np.zeros(d)
    for i in range(d):
        for k in range(d):
            for j in combinations([q for q in range(d) if q != i], k):
                w = factorial(k) * factorial(d - k - 1) / factorial(d)
                sh[i] += w * (v(tuple(sorted((*j, i)))) - v(j))
    return sh / var


def test_shapley_effects_of_the_linear_gaussian_model() -> None:
    """Iooss & Prieur 2019 (eq. 11): Y = X1 + X2 + X3, X2-X3 correlated rho, sd (1, 1, 2)."""
    rho, beta = 0.6, np.ones(3)
    space, cov, sd = _linear_gaussian(rho)
    var = beta @ cov @ beta
    closed = np.array([sd[0] ** 2,
                       sd[1] ** 2 * (1 - rho ** 2 / 2) + rho * sd[1] * sd[2] + sd[2] ** 2 * rho ** 2 / 2,
                       sd[2] ** 2 * (1 - rho ** 2 / 2) + rho * sd[1] * sd[2] + sd[1] ** 2 * rho ** 2 / 2]) / var
    np.testing.assert_allclose(_exact_shapley(beta, cov), closed, atol=1e-12)      # the two closed forms agree
    res = ddgsa.sobol(lambda x: x @ beta, space, method="shapley", n_v=2000, n_o=1000, n_i=3, seed=1)
    t = res.indices
    assert res.n_evals == 2000 + 6 * 1000 * 3
    assert np.all(np.abs(t["Sh"] - closed) <= np.maximum(t["Sh_conf"], 0.01) + 0.01)
    assert abs(t["Sh"].sum() - 1.0) < 0.03
    # ranked by Sh (0.12 < 0.33 < 0.56, bounds ~0.02), not by the independent ST (0.12, 0.08, 0.29)
    assert t["rank"].tolist() == ["3", "2", "1"] and res.extras["rank_by"] == "Sh"
    np.testing.assert_allclose(res.extras["rank_error"], t["Sh_error"])
    assert (t["Sh_error"] >= t["Sh_conf"]).all() and not t["trusted"].any()     # S1's errors 0.02-0.08
    # full first-order Var E[Y|X_i] / V and independent total E Var(Y|X_-i) / V in closed form
    s1_full = np.array([(cov[:, i] @ beta) ** 2 / cov[i, i] for i in range(3)]) / var
    st_ind = np.array([1.0 - _v_minus(beta, cov, i) / var for i in range(3)])
    np.testing.assert_allclose(t["S1"], s1_full, atol=0.08)
    np.testing.assert_allclose(t["ST"], st_ind, atol=0.03)


def _v_minus(beta: np.ndarray, cov: np.ndarray, i: int) -> float:
    j = [q for q in range(len(beta)) if q != i]
    s = cov[:, j]
    return float(beta @ s @ np.linalg.solve(cov[np.ix_(j, j)], s.T @ beta))


def test_random_permutation_shapley_and_refusals() -> None:
    space, cov, _ = _linear_gaussian(0.6)
    res = ddgsa.sobol(lambda x: x.sum(axis=1), space, method="shapley", permutations=30, n_v=1000, n_o=300)
    assert np.all(np.abs(res.indices["Sh"] - _exact_shapley(np.ones(3), cov)) <= res.indices["Sh_conf"] + 0.02)
    for method in ("mdrm", "saltelli", "pce", "auto"):
        with pytest.raises(MethodError, match="independent inputs.*use method 'shapley'"):
            ddgsa.sobol(lambda x: x.sum(axis=1), space, method=method)
    with pytest.raises(SpaceError, match="correlation: the correlation matrix is not positive definite"):
        ddgsa.ParameterSpace.from_dict({k: {"low": 0, "high": 1} for k in "abc"},
                                       correlation=[("a", "b", 0.9), ("a", "c", 0.9), ("b", "c", -0.9)])
    with pytest.raises(SpaceError, match=r"correlation\[0\]: rho of \('a', 'b'\) must lie in \(-1, 1\)"):
        ddgsa.ParameterSpace.from_dict({k: {"low": 0, "high": 1} for k in "ab"}, correlation=[("a", "b", 1.0)])


def test_copula_sample_has_the_stated_normal_score_correlation() -> None:
    space, _, _ = _linear_gaussian(0.6)
    x = space.sample(8192, seed=3)
    assert abs(np.corrcoef(x[:, 1], x[:, 2])[0, 1] - 0.6) < 0.03
    assert abs(np.corrcoef(x[:, 0], x[:, 2])[0, 1]) < 0.03


@pytest.mark.parametrize("kind,S1,ST", [("indicator", 1 / 3, 2 / 3), ("excess", 0.4, 0.6)])
def test_target_indices_of_a_known_threshold_problem(kind: str, S1: float, ST: float) -> None:
    """Y = a + b, a, b ~ U(0, 1), limit 1: 1{Y > 1} has E[.|a] = a (S1 = (1/12)/(1/4) = 1/3);
    max(Y - 1, 0) has E[.|a] = a^2/2, Var 1/18, S1 = (1/45)/(1/18) = 0.4."""
    space = ddgsa.ParameterSpace.from_dict({"a": {"low": 0, "high": 1}, "b": {"low": 0, "high": 1}})
    g = target_function(lambda x: x[:, 0] + x[:, 1], limit=1.0, kind=kind)
    res = ddgsa.sobol(g, space, method="saltelli", n=8192)
    np.testing.assert_allclose(res.indices["S1"], [S1, S1], atol=0.02)
    np.testing.assert_allclose(res.indices["ST"], [ST, ST], atol=0.02)
    assert Target("y", 1.0, above=False, kind=kind).name == ("y_below" if kind == "indicator" else "y_shortfall")
    np.testing.assert_array_equal(Target("y", 1.0).apply(np.array([0.5, 1.5, np.nan])), [0.0, 1.0, np.nan])


def _min_indicator(limit: float) -> tuple[ddgsa.ParameterSpace, object, np.ndarray]:
    """1{min(a, b) > t} = 1{a > t} 1{b > t}, a, b ~ U(0, 1): a product of two Bernoulli(q = 1 - t), so
    Var = q^2 (1 - q^2), Var E[.|a] = q^3 (1 - q) and E Var(.|b) = q^2 (1 - q): S1 = q / (1 + q),
    ST = 1 / (1 + q) for both inputs."""
    space = ddgsa.ParameterSpace.from_dict({"a": {"low": 0, "high": 1}, "b": {"low": 0, "high": 1}})
    q = 1.0 - limit
    return space, target_function(lambda x: np.minimum(x[:, 0], x[:, 1]), limit=limit), \
        np.array([[q / (1 + q)] * 2, [1 / (1 + q)] * 2])


@pytest.mark.parametrize("limit", [0.4, 0.6])
def test_target_of_a_product_indicator_is_judged_by_each_methods_bound(limit: float) -> None:
    """The indicator of min(a, b) > t against its closed form (t = 0.4: 1 at the cut point (0.5, 0.5);
    t = 0.6: 0 there). Saltelli (n = 8 192) is within its own bound; M-DRM gives numbers where any input
    axis through the cut point crosses the limit (the indicator of the cut value, 1 there), bounded by its
    check sample (a step is no polynomial: never within 0.02 by it), and otherwise refuses with the fix."""
    space, g, truth = _min_indicator(limit)
    sal = ddgsa.sobol(g, space, method="saltelli", n=8192, seed=3).indices
    est = sal[["S1", "ST"]].to_numpy(float).T
    assert np.all(np.abs(est - truth) <= sal[["S1_conf", "ST_conf"]].to_numpy(float).T + 1e-3)
    assert np.all(np.abs(est - truth)[:, sal["trusted"].to_numpy()] <= 0.02)
    res = ddgsa.sobol(g, space, method="mdrm")
    t = res.indices
    assert "mdrm_indicator" in res.diagnostic_names() and not t["trusted"].any()
    if limit < 0.5:                       # M-DRM: quadrature of the steps on 5 Gauss nodes, q = 0.642 not 0.6
        assert np.all(np.isfinite(t[["S1", "ST"]].to_numpy(float)))
        np.testing.assert_allclose(t[["S1", "ST"]].to_numpy(float).T, truth, atol=0.02)
        assert np.all(np.abs(t[["S1", "ST"]].to_numpy(float).T - truth) <= t[["S1_conf", "ST_conf"]].to_numpy().T)
    else:                                 # 1 - 1{a > t} 1{0.5 > t} = 1 on every axis: nothing to see
        msg = next(d.message for d in res.diagnostics if d.name == "mdrm_zero_variance")
        assert "varies on the check sample but along no input axis" in msg and "saltelli" in msg


def test_hsic_screens_out_an_inert_input() -> None:
    tf = ishigami()
    space = ddgsa.ParameterSpace.from_dict({**tf.space.to_dict(), "x4": {"low": -np.pi, "high": np.pi}})
    f = lambda x: tf.f(x[:, :3])                                       # noqa: E731
    res = ddgsa.sobol(f, space, method="hsic", n=150, permutations=200, seed=0)
    t = res.indices.set_index("parameter")
    assert t.loc["x1", "p_value"] < 0.01 and t.loc["x4", "p_value"] > 0.05
    assert t.loc["x1", "screened_in"] == 1.0 and t.loc["x4", "screened_in"] == 0.0
    assert "hsic_screening" in res.diagnostic_names() and not res.indices["trusted"].any()


@pytest.mark.slow
def test_hsic_screens_an_inert_input_in_at_the_level_alpha_and_never_trusts() -> None:
    """An input the output does not depend on is independent of it: HSIC = 0 exactly, so its permutation
    p-value is uniform and it is screened in at rate alpha = 0.05. 60 seeds: at most 8 screened in (the
    binomial(60, 0.05) 99.6 % quantile), the p-values uniform by a Kolmogorov-Smirnov test (p > 0.001),
    the V-statistic's R2_HSIC of it small (mean < 0.02 at n = 150, its O(1/n) bias) and below x1's and
    x3's; x1 is screened in every time. (x2, S1 = 0.44 through sin^2 x2, is missed as often as the inert
    input: a kernel as wide as the input's standard deviation does not see a period-pi effect; documented
    in docs/beyond.md, not asserted.)"""
    from scipy.stats import kstest

    from ddgsa.bench.beyond_trust import hsic_screening

    h = hsic_screening(range(60))
    inert = h[h["inert"]]
    assert inert["screened_in"].sum() <= 8 and kstest(inert["p_value"], "uniform").pvalue > 1e-3
    assert inert["R2_HSIC"].mean() < 0.02
    mean_r2 = h.groupby("parameter")["R2_HSIC"].mean()
    assert mean_r2["x4"] < mean_r2[["x1", "x3"]].min()
    assert h[h["parameter"] == "x1"]["screened_in"].all()


@pytest.mark.slow
def test_hsic_matches_openturns() -> None:
    ot = pytest.importorskip("openturns")
    tf = ishigami()
    space = ddgsa.ParameterSpace.from_dict({**tf.space.to_dict(), "x4": {"low": -np.pi, "high": np.pi}})
    f = lambda x: tf.f(x[:, :3])                                       # noqa: E731
    t = ddgsa.sobol(f, space, method="hsic", n=150, permutations=1000, seed=0).indices
    x = ddgsa.gsa.get_method("hsic").design(space, n=150, seed=0).points
    X, Y = ot.Sample(x), ot.Sample(f(x)[:, None])
    kernels = [ot.SquaredExponential([X.getMarginal(i).computeStandardDeviation()[0]]) for i in range(4)]
    kernels.append(ot.SquaredExponential([Y.computeStandardDeviation()[0]]))
    est = ot.HSICEstimatorGlobalSensitivity(kernels, X, Y, ot.HSICVStat())
    np.testing.assert_allclose(t["HSIC"], np.array(est.getHSICIndices()), rtol=1e-8)
    np.testing.assert_allclose(t["R2_HSIC"], np.array(est.getR2HSICIndices()), rtol=1e-8)
    est.setPermutationSize(1000)       # two permutation tests of 1000: p-values within 0.05 (2 sd)
    np.testing.assert_allclose(t["p_value"], np.array(est.getPValuesPermutation()), atol=0.05)


def test_shapley_effects_of_ishigami_share_the_interaction_equally() -> None:
    """Independent inputs: Sh_i = sum over the subsets u containing i of S_u / |u| (Owen 2014), so
    Ishigami's Sh = (S1 + S13/2, S2, S13/2) = (0.436, 0.442, 0.122), S1 <= Sh <= ST."""
    tf = ishigami()
    res = ddgsa.sobol(tf.f, tf.space, method="shapley", n_v=4000, n_o=1000, n_i=3, seed=2)
    t = res.indices
    exact = np.array([_S1 + _S13 / 2, _S2, _S13 / 2])
    assert np.all(np.abs(t["Sh"] - exact) <= t["Sh_conf"] + 0.01)
    np.testing.assert_allclose(t["Sh"], exact, atol=0.04)
    assert np.all(np.abs(t["ST"] - tf.ST) <= t["ST_conf"] + 0.01)     # independent total = ordinary ST here
