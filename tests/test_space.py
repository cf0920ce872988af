"""ParameterSpace: distributions against scipy, shorthand, sampling, validation messages."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

import ddgsa
from ddgsa import ParameterSpace, SpaceError

SPECS = {
    "u": {"dist": "uniform", "low": 2.0, "high": 5.0},
    "n": {"dist": "normal", "mean": 1e10, "std": 1e9, "unit": "N/m"},
    "ln": {"dist": "lognormal", "mu": 0.5, "sigma": 0.4},
    "tn": {"dist": "truncnormal", "mean": 1.0, "std": 2.0, "low": -1.0, "high": 2.0},
    "tr": {"dist": "triangular", "low": 0.0, "mode": 0.3, "high": 1.0},
}
SCIPY = {
    "u": stats.uniform(2.0, 3.0),
    "n": stats.norm(1e10, 1e9),
    "ln": stats.lognorm(s=0.4, scale=np.exp(0.5)),
    "tn": stats.truncnorm(-1.0, 0.5, loc=1.0, scale=2.0),
    "tr": stats.triang(0.3, loc=0.0, scale=1.0),
}


@pytest.mark.parametrize("name", list(SPECS))
def test_moments_and_quantiles_match_scipy(name: str) -> None:
    p = ParameterSpace.from_dict({name: SPECS[name]})[name]
    ref = SCIPY[name]
    assert p.mean == pytest.approx(ref.mean(), rel=1e-10)
    assert p.std == pytest.approx(ref.std(), rel=1e-8)
    u = np.array([0.01, 0.3, 0.5, 0.9, 0.999])
    np.testing.assert_allclose(p.ppf(u), ref.ppf(u), rtol=1e-8)
    assert p.nominal == pytest.approx(ref.mean(), rel=1e-10)


def test_spread_shorthand_and_string_numbers() -> None:
    space = ParameterSpace.from_dict({
        "c_gen": {"nominal": 8.28e5, "spread": 0.1},
        "k": {"dist": "normal", "nominal": "1e10", "spread": "0.05"},   # PyYAML gives strings
        "t": {"dist": "triangular", "nominal": -2.0, "spread": 0.5},
    })
    assert space["c_gen"].args == pytest.approx({"low": 8.28e5 * 0.9, "high": 8.28e5 * 1.1})
    assert space["k"].args == pytest.approx({"mean": 1e10, "std": 5e8})
    assert space["t"].args == pytest.approx({"low": -3.0, "high": -1.0, "mode": -2.0})
    assert space.nominal == pytest.approx({"c_gen": 8.28e5, "k": 1e10, "t": -2.0})


def test_sampling_is_reproducible_and_in_distribution() -> None:
    space = ParameterSpace.from_dict(SPECS)
    a, b = space.sample(256, seed=3), space.sample(256, seed=3)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, space.sample(256, seed=4))
    big = space.sample(2 ** 14, seed=0)
    np.testing.assert_allclose(big.mean(axis=0), space.means, rtol=2e-3)
    assert big[:, 0].min() >= 2.0 and big[:, 0].max() <= 5.0
    for rule in ("random", "lhs", "halton"):
        assert space.sample(8, seed=1, rule=rule).shape == (8, 5)


def test_roundtrip_and_salib_export() -> None:
    space = ParameterSpace.from_dict(SPECS)
    assert ParameterSpace.from_dict(space.to_dict()) == space
    prob = space.to_salib()
    assert prob["dists"] == ["unif", "norm", "lognorm", "truncnorm", "triang"]
    assert prob["bounds"][4] == pytest.approx([0.0, 1.0, 0.3])


@pytest.mark.parametrize("specs, match", [
    ({"a": {"dist": "unifrom", "low": 0, "high": 1}}, r"parameter 'a': unknown dist 'unifrom'; allowed: uniform"),
    ({"a": {"dist": "uniform", "low": 1, "high": 1}}, r"parameter 'a': low \(1.0\) must be < high \(1.0\)"),
    ({"a": {"dist": "normal", "mean": 0, "std": 0}}, r"parameter 'a': std must be > 0, got 0.0"),
    ({"a": {"dist": "normal", "mean": 0}}, r"parameter 'a': dist 'normal' needs keys"),
    ({"a": {"dist": "uniform", "low": 0, "high": 1, "hihg": 2}}, r"parameter 'a': unknown key\(s\) \['hihg'\]"),
    ({"a": {"dist": "uniform", "low": "zero", "high": 1}}, r"parameter 'a': 'low' must be a number"),
    ({"a": {"dist": "lognormal", "mu": 0, "sigma": -1}}, r"parameter 'a': sigma must be > 0"),
    ({"a": {"dist": "triangular", "low": 0, "mode": 2, "high": 1}}, r"parameter 'a': mode \(2.0\) must lie in"),
    ({"a": {"spread": 0.1}}, r"parameter 'a': 'spread' needs 'nominal'"),
    ({"a": {"nominal": 0.0, "spread": 0.1}}, r"parameter 'a': 'spread' is a fraction of \|nominal\|"),
    ({"a": {"low": 0, "high": 1, "nominal": 3}}, r"parameter 'a': nominal 3.0 lies outside the support"),
    ({"a b": {"low": 0, "high": 1}}, r"parameter name 'a b' must be an identifier"),
    ({"a": [0, 1]}, r"parameter 'a': expected a mapping"),
    ({}, r"at least one parameter"),
])
def test_invalid_specs_name_parameter_and_problem(specs: dict, match: str) -> None:
    with pytest.raises(SpaceError, match=match):
        ParameterSpace.from_dict(specs)


def test_duplicates_and_unknown_lookup() -> None:
    p = ParameterSpace.from_dict({"a": {"low": 0, "high": 1}})["a"]
    with pytest.raises(SpaceError, match=r"duplicate parameter name\(s\): \['a'\]"):
        ParameterSpace.from_parameters([p, p])
    with pytest.raises(SpaceError, match="unknown parameter 'b'; known: a"):
        ParameterSpace.from_parameters([p])["b"]
    assert issubclass(SpaceError, ValueError) and issubclass(SpaceError, ddgsa.DdgsaError)
