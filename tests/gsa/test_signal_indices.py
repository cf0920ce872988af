"""Per-bin and generalised (Gamboa et al. 2014) indices of signals built from known components."""

from __future__ import annotations

import numpy as np
import pytest

import ddgsa
from ddgsa.gsa.signal import SignalAxis, generalised, signal_indices
from ddgsa.gsa.base import get_method

# a time series y(t) on 0.5 s, 33 samples, with two components at 2 Hz and 5 Hz
T = np.linspace(0.0, 0.5, 33)
S1_T, S2_T = np.sin(2 * np.pi * 2.0 * T), np.sin(2 * np.pi * 5.0 * T)
AXIS = SignalAxis("time", "s", T)
UNIFORM = ddgsa.ParameterSpace.from_dict({"x1": {"dist": "uniform", "low": -1.0, "high": 1.0},
                                          "x2": {"dist": "uniform", "low": -1.0, "high": 1.0},
                                          "x3": {"dist": "uniform", "low": -1.0, "high": 1.0}})


def additive(x: np.ndarray) -> np.ndarray:
    """y(t) = a(x1) sin(w1 t) + b(x2) sin(w2 t), a = x1 + x1^2, b = 2 x2; x3 inert."""
    return (x[:, :1] + x[:, :1] ** 2) * S1_T + 2.0 * x[:, 1:2] * S2_T


# Var(x + x^2) = 1/3 + 4/45 (x ~ U(-1, 1): Var x = 1/3, Var x^2 = 4/45, Cov = 0); Var(2 x) = 4/3
VA, VB = 1.0 / 3.0 + 4.0 / 45.0, 4.0 / 3.0
V_BIN = VA * S1_T ** 2 + VB * S2_T ** 2
with np.errstate(invalid="ignore", divide="ignore"):
    S_X1_BIN = VA * S1_T ** 2 / V_BIN
GEN_X1 = VA * (S1_T ** 2).sum() / V_BIN.sum()


@pytest.mark.parametrize("method, options, tol", [("pce", {"order": 2, "fit": "quadrature"}, 1e-10),
                                                  ("pce", {"order": 3}, 1e-9),
                                                  ("saltelli", {"n": 2048, "num_resamples": 20}, 0.03)])
def test_additive_signal_matches_the_closed_form(method: str, options: dict, tol: float) -> None:
    res = ddgsa.sobol_signal(additive, UNIFORM, AXIS, method, signal="y", **options)
    b = res.bins
    live = V_BIN > 1e-9                                   # t = 0 (and t = 0.5 s) hold no variance
    for par, exact in (("x1", S_X1_BIN), ("x2", 1.0 - S_X1_BIN), ("x3", np.zeros_like(T))):
        rows = b[b["parameter"] == par]
        np.testing.assert_allclose(rows["S1"].to_numpy()[live], exact[live], atol=tol)
        np.testing.assert_allclose(rows["ST"].to_numpy()[live], exact[live], atol=tol)
    var = b[b["parameter"] == "x1"]["variance"].to_numpy()
    np.testing.assert_allclose(var[live], V_BIN[live], rtol=max(tol, 1e-9) * (3 if method == "saltelli" else 1))
    g = res.generalised.set_index("parameter")
    assert g.loc["x1", "S1"] == pytest.approx(GEN_X1, abs=tol)
    assert g.loc["x2", "ST"] == pytest.approx(1.0 - GEN_X1, abs=tol)
    assert g.loc["x3", "ST"] == pytest.approx(0.0, abs=tol)
    assert (g["S1_conf"] >= 0).all()
    # the ranking of the generalised ST (x2 0.74 > x1 0.26 > x3 0): a claim only where it is the exact one
    exact_rank = {"x2": "1", "x1": "2", "x3": "negligible"}
    assert all(r == exact_rank[p] for p, r in g.loc[g["rank_confirmed"], "rank"].items())
    if method == "pce":          # 0.5 apart: confirmed by any bound < 0.25 (x3's weighted bound, 0.05, is not < 0.02)
        assert (g.loc["x2", "rank"], g.loc["x1", "rank"]) == ("1", "2")


C1, C2 = 0.5 + 0.4 * np.sin(2 * np.pi * 2.0 * T), 0.5 + 0.4 * np.cos(2 * np.pi * 5.0 * T)


def product(x: np.ndarray) -> np.ndarray:
    """y(t) = (1 + c1(t) x1) (1 + c2(t) x2): positive, a product (M-DRM's exact case)."""
    return (1.0 + C1 * x[:, :1]) * (1.0 + C2 * x[:, 1:2]) * (1.0 + 0.0 * x[:, 2:3])


def test_product_signal_mdrm_is_exact_per_bin_and_generalised() -> None:
    v1, v2 = C1 ** 2 / 3.0, C2 ** 2 / 3.0                      # Var(1 + c x), x ~ U(-1, 1)
    var = (1 + v1) * (1 + v2) - 1.0
    res = ddgsa.sobol_signal(product, UNIFORM, AXIS, "mdrm", signal="y", points=4)
    b = res.bins
    x1 = b[b["parameter"] == "x1"]
    np.testing.assert_allclose(x1["S1"], v1 / var, atol=1e-12)
    np.testing.assert_allclose(x1["ST"], (v1 + v1 * v2) / var, atol=1e-12)
    np.testing.assert_allclose(x1["variance"], var, rtol=1e-12)
    g = res.generalised.set_index("parameter")
    assert g.loc["x1", "S1"] == pytest.approx(v1.sum() / var.sum(), abs=1e-12)
    assert g.loc["x2", "ST"] == pytest.approx((v2 + v1 * v2).sum() / var.sum(), abs=1e-12)
    assert g.loc["x1", "variance_covered"] == pytest.approx(1.0)
    assert bool(g["trusted"].all())
    st1, st2 = (v1 + v1 * v2).sum() / var.sum(), (v2 + v1 * v2).sum() / var.sum()     # 0.547, 0.551: 0.004 apart
    assert abs(st1 - st2) + g.loc["x1", "ST_error"] + g.loc["x2", "ST_error"] <= 0.02
    assert g["rank"].to_dict() == {"x1": "1=", "x2": "1=", "x3": "negligible"}    # a confirmed tie, x3 inert


def test_a_voided_bin_voids_the_generalised_rank() -> None:
    """A material bin whose bounds a rule voids (M-DRM's sign change: here bins where y < 0) takes every
    rank claim of the generalised rows that the bin enters; the error bound is the weighted bound."""
    res = ddgsa.sobol_signal(lambda x: product(x) - 1.5, UNIFORM, AXIS, "mdrm", signal="y", points=4)
    assert not res.bins["bounded"].all()
    g = res.generalised
    assert (g["rank"] == "").all() and not g["rank_confirmed"].any()


def test_constant_bins_drop_out_and_a_wrong_grid_is_refused() -> None:
    design = get_method("pce").design(UNIFORM, order=2, fit="quadrature")
    y = np.column_stack([additive(design.points), np.full(design.n_points, 3.0)])   # a constant last bin
    axis = SignalAxis("time", "s", np.append(T, 0.6))
    res = signal_indices("pce", UNIFORM, design, y, axis, "y")
    assert np.isnan(res.bins[res.bins["bin"] == len(T)]["S1"]).all()
    assert res.bins[res.bins["bin"] == len(T)]["variance"].eq(0.0).all()
    g = res.generalised.set_index("parameter")
    assert g.loc["x1", "S1"] == pytest.approx(GEN_X1, abs=1e-10)
    assert g.loc["x1", "variance_covered"] == pytest.approx(1.0)
    with pytest.raises(ddgsa.MethodError, match="do not match its grid"):
        signal_indices("pce", UNIFORM, design, y, AXIS, "y")


def test_generalised_of_one_bin_is_that_bin() -> None:
    import pandas as pd

    bins = pd.DataFrame({"signal": "s", "bin": [0], "axis": [1.0], "parameter": ["a"], "S1": [0.3],
                         "S1_conf": [0.01], "ST": [0.4], "ST_conf": [0.02], "variance": [2.0], "trusted": [True]})
    row = generalised(bins).iloc[0]
    assert (row["S1"], row["ST"], row["S1_conf"], row["ST_conf"]) == (0.3, 0.4, 0.01, 0.02)
