"""``ddgsa.sobol(..., timeout=)``: a hung point is a failed evaluation with its reason (issue 49).

Before issue 49 ``sobol`` had no timeout: a model that hangs at one point waited for ever
(``timeout=`` was passed to the method as an unknown option and refused).
"""

from __future__ import annotations

import os
import time

import numpy as np
import pandas as pd
import pytest

import ddgsa
from ddgsa.gsa.testfunctions import sobol_g

pytestmark = pytest.mark.skipif(not hasattr(os, "fork"), reason="timeouts fork a child process (POSIX)")
G = sobol_g([1.0, 2.0, 5.0])
HANG_ABOVE = 0.9
"""Points whose first coordinate exceeds this hang (a closure: not picklable, and need not be)."""


def _hangs_at_some_points(x: np.ndarray) -> np.ndarray:
    if (x[:, 0] > HANG_ABOVE).any():
        time.sleep(600)
    return G.f(x)


def test_hung_points_are_failed_with_their_reason_and_refused_not_imputed() -> None:
    design = ddgsa.gsa.get_method("saltelli").design(G.space, n=8, seed=0).points
    hung = np.flatnonzero(design[:, 0] > HANG_ABOVE)
    assert len(hung) > 0
    t0 = time.monotonic()
    res = ddgsa.sobol(_hangs_at_some_points, G.space, method="saltelli", n=8, seed=0, timeout=0.5)
    assert time.monotonic() - t0 < 30 + 0.5 * len(hung)
    failures = res.extras["failures"]
    assert [f["row"] for f in failures] == hung.tolist()
    assert all(f["error"] == "timed out after 0.5 s (the evaluation was stopped)" for f in failures)
    assert np.array_equal(np.array([f["point"] for f in failures]), design[hung])
    names = [d.name for d in res.diagnostics]
    assert "failed_evaluations" in names and "nonfinite_values" in names
    assert res.indices["S1"].isna().all() and not res.indices["trusted"].any()


@pytest.mark.parametrize("method, options", [("mdrm", {"points": 6}), ("saltelli", {"n": 16, "seed": 1})])
def test_a_timeout_that_never_fires_gives_the_same_indices(method: str, options: dict) -> None:
    """Point by point in a child process, the same numbers as the whole design in one call (the
    same arithmetic row by row: equal to 1e-12, round-off of a vectorised sum at most)."""
    plain = ddgsa.sobol(G.f, G.space, method=method, **options)
    timed = ddgsa.sobol(G.f, G.space, method=method, timeout=30.0, **options)
    np.testing.assert_allclose(timed.indices[["S1", "ST"]].to_numpy(dtype=float),
                               plain.indices[["S1", "ST"]].to_numpy(dtype=float), rtol=0, atol=1e-12)
    assert "failures" not in timed.extras and timed.n_evals == plain.n_evals


def test_dataframe_outputs_keep_their_names_and_exceptions_are_reasons() -> None:
    design = ddgsa.gsa.get_method("mdrm").design(G.space, points=4).points
    broken = design[2, 1]                                  # the points that share design row 2's x2 fail

    def frame(x: np.ndarray) -> pd.DataFrame:
        if (x[:, 1] == broken).any():
            raise ValueError("no convergence")
        return pd.DataFrame({"a": G.f(x), "b": 2.0 * G.f(x)})

    res = ddgsa.sobol(frame, G.space, method="mdrm", points=4, timeout=30.0)
    assert set(res.indices["output"]) == {"a", "b"}
    failed = np.flatnonzero(design[:, 1] == broken)
    assert [f["row"] for f in res.extras["failures"]] == failed.tolist()
    assert {f["error"] for f in res.extras["failures"]} == {"ValueError: no convergence"}


@pytest.mark.parametrize("bad", [0, -1.0, "5", True])
def test_a_bad_timeout_is_refused(bad: object) -> None:
    with pytest.raises(ddgsa.MethodError, match="timeout must be a positive number of seconds"):
        ddgsa.sobol(G.f, G.space, method="mdrm", points=4, timeout=bad)
