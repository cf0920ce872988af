"""SALib and PCE estimators against analytic indices; failed evaluations are refused."""

from __future__ import annotations

import numpy as np
import pytest

import ddgsa
from ddgsa.gsa.testfunctions import ishigami, sobol_g

Z95 = 1.959963984540054   # SALib's conf is the 95 % half-width: one standard error = conf / Z95


@pytest.mark.parametrize("tf", [ishigami(), sobol_g([0.0, 1.0, 4.5, 9.0, 99.0])], ids=["ishigami", "g"])
def test_saltelli_within_three_bootstrap_standard_errors(tf) -> None:
    res = ddgsa.sobol(tf.f, tf.space, "saltelli", n=2 ** 13, seed=1)
    t = res.indices
    assert res.n_evals == 2 ** 13 * (tf.space.dim + 2)
    assert (np.abs(t["S1"] - tf.S1) <= 3 * t["S1_conf"] / Z95 + 1e-12).all()
    assert (np.abs(t["ST"] - tf.ST) <= 3 * t["ST_conf"] / Z95 + 1e-12).all()


def test_saltelli_is_reproducible_for_a_seed_including_zero() -> None:
    tf = ishigami()
    a = ddgsa.sobol(tf.f, tf.space, "saltelli", n=256, seed=0)
    b = ddgsa.sobol(tf.f, tf.space, "saltelli", n=256, seed=0)
    c = ddgsa.sobol(tf.f, tf.space, "saltelli", n=256, seed=1)
    assert a.indices.equals(b.indices)
    assert not a.indices.equals(c.indices)


def test_saltelli_tiny_sample_flags_wide_intervals() -> None:
    tf = ishigami()
    res = ddgsa.sobol(tf.f, tf.space, "saltelli", n=8, seed=2)
    assert "wide_confidence" in res.diagnostic_names()
    assert not res.trusted


@pytest.mark.parametrize("fit, order", [("regression", 8), ("quadrature", 12)])
def test_pce_reproduces_ishigami_within_0_01(fit: str, order: int) -> None:
    tf = ishigami()
    res = ddgsa.sobol(tf.f, tf.space, "pce", order=order, fit=fit, seed=0)
    assert np.abs(res.indices["S1"] - tf.S1).max() < 0.01
    assert np.abs(res.indices["ST"] - tf.ST).max() < 0.01
    assert res.trusted


def test_pce_on_a_discontinuous_output_fires() -> None:
    tf = ishigami()
    res = ddgsa.sobol(lambda x: (x[:, 0] > 0.3).astype(float) + 0.1 * x[:, 1], tf.space, "pce", order=4)
    assert {"pce_loo_error", "pce_unresolved"} & res.diagnostic_names()
    assert not res.trusted


@pytest.mark.parametrize("method, opts", [("fast", {"n": 1024}), ("rbd_fast", {"n": 2048})])
def test_fast_family_close_on_g_function(method: str, opts: dict) -> None:
    tf = sobol_g([1.0, 2.0, 5.0])
    res = ddgsa.sobol(tf.f, tf.space, method, seed=0, **opts)
    assert np.abs(res.indices["S1"] - tf.S1).max() < 0.05     # FAST-family bias is a few 1e-2


@pytest.mark.parametrize("method", ["saltelli", "mdrm", "pce", "rbd_fast"])
def test_nan_outputs_are_refused_not_imputed(method: str) -> None:
    tf = ishigami(shift=10.0)

    def f(x):
        y = tf.f(x)
        y[3] = np.nan
        return np.column_stack([y, tf.f(x)])

    res = ddgsa.sobol(f, tf.space, method, outputs=["broken", "fine"])
    broken = res.indices.query("output == 'broken'")
    assert broken[["S1", "ST"]].isna().all().all()
    assert not broken["trusted"].any()
    assert "nonfinite_values" in res.diagnostic_names()
    assert res.indices.query("output == 'fine'")["S1"].notna().all()
