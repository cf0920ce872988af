"""Indices against sample size on nested sub-samples: the curve ends at the method's own index and narrows."""

from __future__ import annotations

import numpy as np
import pytest

from ddgsa.gsa.base import get_method
from ddgsa.gsa.convergence import convergence, nested_sizes
from ddgsa.gsa.testfunctions import ishigami
from ddgsa.gsa.space import ParameterSpace

F = ishigami()
SMOOTH_SPACE = ParameterSpace.from_dict({"a": {"dist": "uniform", "low": -1.0, "high": 1.0},
                                         "b": {"dist": "uniform", "low": -1.0, "high": 1.0}})


def smooth(x: np.ndarray) -> np.ndarray:
    """A smooth function an order-3 PCE nearly resolves (its bound narrows as the fit's overfit shrinks)."""
    return np.exp(0.8 * x[:, 0]) + np.sin(2 * x[:, 1]) + 0.3 * x[:, 0] * x[:, 1] ** 2


@pytest.mark.parametrize("method, options", [
    ("saltelli", {"n": 256, "num_resamples": 20}),
    ("pce", {"order": 3, "n": 256}),
    pytest.param("pce", {"order": 6, "n": 512}, marks=pytest.mark.slow),
    pytest.param("saltelli", {"n": 1024, "num_resamples": 50}, marks=pytest.mark.slow),
    pytest.param("pce", {"order": 5, "fit": "sparse", "n": 256}, marks=pytest.mark.slow),
    pytest.param("rbd_fast", {"n": 1024}, marks=pytest.mark.slow)])
def test_curve_ends_at_the_study_index_and_narrows(method: str, options: dict) -> None:
    space, f = (SMOOTH_SPACE, smooth) if options.get("order") == 3 else (F.space, F)
    m = get_method(method)
    design = m.design(space, **options)
    y = f(design.points)
    own_res = m.analyze(space, design, y, outputs=["y"])
    own = own_res.indices
    curve = convergence(space, design, y, ["y"])
    sizes = sorted(curve["n_evals"].unique())
    assert len(sizes) >= 3 and sizes[-1] == design.n_points
    last = curve[curve["n_evals"] == sizes[-1]].reset_index(drop=True)
    for q in ("S1", "ST"):
        np.testing.assert_array_equal(last[q].to_numpy(), own[q].to_numpy())
        err = own_res.extras.get(f"{q}_error", own[f"{q}_conf"].to_numpy())     # the bound trust uses
        np.testing.assert_array_equal(last[f"{q}_conf"].to_numpy(), np.ravel(err))
    # the bound narrows: the widest S1 bound of the smallest sub-sample against the full design
    first = curve[curve["n_evals"] == sizes[0]]
    assert last["S1_conf"].max() < 0.7 * first["S1_conf"].max()
    if method == "saltelli" and options["n"] >= 1024:     # and the full sample's indices are near Ishigami's
        assert np.abs(last["S1"].to_numpy() - F.S1).max() < 0.05


def test_methods_without_a_nested_design_give_no_curve() -> None:
    for method, options in (("mdrm", {}), ("pce", {"fit": "quadrature", "order": 3}), ("fast", {"n": 129})):
        design = get_method(method).design(F.space, **options)
        assert nested_sizes(design, F.space.dim) == []
        assert convergence(F.space, design, F(design.points), ["y"]).empty
