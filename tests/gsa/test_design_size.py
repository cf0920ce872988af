"""``GsaMethod.n_points`` (the size a study's run estimate uses, issue 29) against the designs built."""

from __future__ import annotations

import pytest

from ddgsa.gsa.base import get_method
from ddgsa.gsa.space import ParameterSpace

SPACE = ParameterSpace.from_dict({
    "a": {"dist": "uniform", "low": 0.0, "high": 1.0},
    "b": {"dist": "normal", "mean": 1.0, "std": 0.1},
    "c": {"dist": "triangular", "low": 1.0, "mode": 2.0, "high": 4.0},
    "d": {"dist": "uniform", "low": -1.0, "high": 1.0},
})


@pytest.mark.parametrize("method, options", [
    ("mdrm", {}), ("mdrm", {"points": 7, "check": 0}), ("mdrm", {"points": 2, "check": 64}),
    ("saltelli", {"n": 64}), ("saltelli", {"n": 2}), ("fast", {"n": 65}), ("rbd_fast", {"n": 77}),
    ("pce", {}), ("pce", {"order": 2, "n": 128}), ("pce", {"fit": "sparse", "order": 5}),
    ("pce", {"fit": "quadrature", "order": 3}),
], ids=lambda v: v if isinstance(v, str) else "-".join(f"{k}{x}" for k, x in v.items()) or "defaults")
def test_n_points_is_the_size_of_the_design_built(method: str, options: dict) -> None:
    m = get_method(method)
    assert m.n_points(SPACE, **options) == m.design(SPACE, **options).n_points
