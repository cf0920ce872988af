"""Where estimators break: each case is either right or a named diagnostic fires (issue: accuracy
against cost, and stability). Cases already covered elsewhere: h(c) = 0 and sign change
(test_mdrm: Ishigami, G with a = 0, rho_nonpositive), |x| kink (test_mdrm), Saltelli at tiny N,
PCE on a discontinuity and NaN outputs (test_crosscheck), output aliasing (test_generator_radial)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import ddgsa
from ddgsa import MethodError, ParameterSpace
from ddgsa.gsa.testfunctions import ishigami, linear, product, sobol_g

LOGNORMAL_1 = {"dist": "lognormal", "mu": 0.0, "sigma": 1.0}


def test_heavy_tailed_inputs_are_untrusted_where_the_nodes_miss_the_bulk() -> None:
    space = ParameterSpace.from_dict({f"x{i}": LOGNORMAL_1 for i in range(3)})
    additive = linear(space, [1.0, 0.5, 0.2], offset=1.0)
    res = ddgsa.sobol(additive.f, space, "mdrm", points=5)
    assert np.abs(res.indices["S1"] - additive.S1).max() > 0.03          # wrong (0.055, measured) ...
    coverage = [d for d in res.diagnostics if d.name == "mdrm_quadrature_coverage"]
    assert coverage and all(d.severity == "untrusted" for d in coverage)  # ... and says so
    assert not res.indices["trusted"].any()
    # a moderate tail keeps its answer and its trust
    mild = ParameterSpace.from_dict({f"x{i}": {**LOGNORMAL_1, "sigma": 0.3} for i in range(3)})
    mild_f = linear(mild, [1.0, 0.5, 0.2], offset=1.0)
    ok = ddgsa.sobol(mild_f.f, mild, "mdrm", points=5)
    assert "mdrm_quadrature_coverage" not in ok.diagnostic_names()
    assert (np.abs(ok.indices["S1"] - mild_f.S1) <= ok.indices["S1_conf"]).all()   # the bound holds


def test_fifty_parameters_exact_on_a_product_flagged_on_g() -> None:
    space = ParameterSpace.from_dict({f"x{i}": {"low": 0.0, "high": 1.0} for i in range(50)})
    tf = product(space, 0.8 ** np.arange(50))
    res = ddgsa.sobol(tf.f, space, "mdrm", points=5)
    assert res.n_evals == 50 * 5 + 1 + 32
    np.testing.assert_allclose(res.indices["ST"], tf.ST, atol=1e-12)
    g = sobol_g(np.arange(50) + 1.0)                  # kinks in every input
    res = ddgsa.sobol(g.f, g.space, "mdrm", points=5)
    assert "mdrm_unresolved" in res.diagnostic_names() and not res.trusted


def test_step_output_is_flagged() -> None:
    space = ParameterSpace.from_dict({"x1": {"low": -1.0, "high": 1.0}, "x2": {"low": 1.0, "high": 2.0}})
    res = ddgsa.sobol(lambda x: (1.0 + (x[:, 0] > 0.1)) * x[:, 1], space, "mdrm", points=5)
    assert ("mdrm_unresolved", "x1") in {(d.name, d.parameter) for d in res.diagnostics}
    assert not res.trusted


def test_auto_stops_at_mdrm_on_a_product() -> None:
    space = ParameterSpace.from_dict({f"x{i}": {"low": 1.0, "high": 2.0} for i in range(4)})
    tf = product(space, [0.5, 0.3, 0.2, 0.1])
    res = ddgsa.sobol(tf.f, space, "auto", budget=2000)
    assert res.n_evals == 4 * 5 + 1 + 32                       # n N + 1 plus the check sample
    assert set(res.indices["source"]) == {"mdrm"} and res.trusted
    assert res.extras["auto_log"] == ["mdrm (53 runs): all outputs trusted"]
    np.testing.assert_allclose(res.indices["ST"], tf.ST, atol=1e-12)


def test_auto_escalates_on_ishigami_and_ends_within_0_02() -> None:
    tf = ishigami()
    res = ddgsa.sobol(tf.f, tf.space, "auto", budget=2000)
    assert res.extras["stages"][0].startswith("mdrm") and set(res.indices["source"]) == {"pce"}
    assert "auto_escalated" in res.diagnostic_names() and res.trusted
    assert np.abs(res.indices["S1"] - tf.S1).max() < 0.02
    assert np.abs(res.indices["ST"] - tf.ST).max() < 0.02
    assert res.n_evals <= 2000


def test_auto_reuses_evaluations() -> None:
    """Every point the function saw is used: the final PCE is fitted on all of them."""
    tf = ishigami()
    seen: list[np.ndarray] = []

    def f(x: np.ndarray) -> np.ndarray:
        seen.append(x)
        return tf.f(x)

    res = ddgsa.sobol(f, tf.space, "auto", budget=2000)
    assert sum(len(x) for x in seen) == res.n_evals
    assert len(np.unique(np.vstack(seen), axis=0)) >= res.n_evals - 3 * 1   # only cut-point repeats


def test_auto_mixes_sources_per_output_and_reports_an_exhausted_budget() -> None:
    tf = ishigami()
    space = tf.space
    both = lambda x: np.column_stack([tf.f(x), np.exp(0.1 * x[:, 0]) * (3 + 0.1 * x[:, 1] ** 2)])  # noqa: E731
    res = ddgsa.sobol(both, space, "auto", budget=2000, outputs=["ishigami", "product"])
    t = res.indices.set_index("output")
    assert set(t.loc["ishigami", "source"]) == {"pce"} and t["trusted"].all()
    # each row keeps its trusted estimate with the smallest error bound: the product's from M-DRM's
    # 33 points or the PCE fitted for Ishigami, whichever bounds it tighter
    assert (t.loc["product", "ST_conf"] <= 0.02).all()
    g = sobol_g([0.0, 0.0, 0.0])
    poor = ddgsa.sobol(g.f, g.space, "auto", budget=200)
    assert "auto_budget_exhausted" in poor.diagnostic_names() and not poor.trusted
    assert poor.n_evals <= 200


def test_auto_options_are_validated() -> None:
    tf = ishigami()
    with pytest.raises(MethodError, match="option 'budget' must be"):
        ddgsa.sobol(tf.f, tf.space, "auto", budget=10)
    with pytest.raises(MethodError, match=r"unknown option\(s\) \['buget'\]"):
        ddgsa.sobol(tf.f, tf.space, "auto", buget=10)


def test_integration_step_coarser_than_the_lowest_mode_warns() -> None:
    from ddgsa import models
    from ddgsa.loads.scene import Scene
    from ddgsa.mbs.sampling import AliasingWarning

    scene = Scene(wind_speed=11.0, duration=2.0)
    with pytest.warns(AliasingWarning, match="direct_drive integration step 0.05 s"):
        models.get("direct_drive", fidelity="rigid", time_step=0.05).simulate(scene)
    with warnings.catch_warnings():
        warnings.simplefilter("error", AliasingWarning)
        models.get("direct_drive", fidelity="rigid").simulate(scene)


def test_two_symmetric_nodes_on_a_kink_give_undefined_not_trusted_nan() -> None:
    g = sobol_g([1.0, 2.0, 5.0])
    res = ddgsa.sobol(g.f, g.space, "mdrm", points=2, check=0)
    assert res.indices["S1"].isna().all()
    assert "mdrm_zero_variance" in res.diagnostic_names() and not res.indices["trusted"].any()


def test_auto_keeps_the_richest_stage_when_none_is_trusted() -> None:
    g = sobol_g([1.0, 2.0, 5.0, 10.0, 20.0, 50.0])
    res = ddgsa.sobol(g.f, g.space, "auto", budget=2000)
    assert "auto_budget_exhausted" in res.diagnostic_names()
    assert set(res.indices["source"]) == {"pce"}                    # the 1 055-point PCE, not a thin Saltelli
    assert np.abs(res.indices["S1"] - g.S1).max() < 0.03
