"""The accuracy-cost benchmark's machinery on a tiny grid (the full run is `ddgsa bench accuracy`)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from ddgsa.bench.accuracy_cost import analytic_rows, errors, plot_fidelity, plot_function  # noqa: E402
from ddgsa.gsa.result import SobolResult  # noqa: E402


def test_errors_are_max_absolute_and_rmse() -> None:
    res = SobolResult.from_arrays(outputs=["y"], parameters=["a", "b"], S1=np.array([[0.5, 0.2]]),
                                  ST=np.array([[0.6, 0.3]]), n_evals=10, method="x")
    e = errors(res, np.array([0.4, 0.2]), np.array([0.6, 0.0]))
    assert np.isclose(e["err_S1"], 0.1) and np.isclose(e["err_ST"], 0.3)
    assert np.isclose(e["rmse_S1"], np.sqrt(0.01 / 2)) and e["trusted"]


def test_small_grid_ranks_methods_as_expected() -> None:
    grid = [("mdrm", {"points": 3, "check": 0}), ("saltelli", {"n": 64, "seed": 0}), ("pce", {"order": 4})]
    t = analytic_rows(grid, progress=lambda _: None)
    assert set(t["function"]) == {"product", "additive", "ishigami", "g_easy", "g_hard"}
    row = t.set_index(["function", "method"])
    assert row.loc[("product", "mdrm"), "err_S1"] < 1e-12          # exact on products
    assert row.loc[("additive", "pce"), "err_S1"] < 1e-12           # exact on polynomials
    assert row.loc[("product", "saltelli"), "err_S1"] > 1e-3        # sampling error at N = 64
    assert np.isnan(row.loc[("ishigami", "mdrm"), "err_S1"])        # refused: h(c) = 0
    assert not row.loc[("ishigami", "mdrm"), "trusted"]
    fig = plot_function(t[t["function"] == "ishigami"], "ishigami")
    assert len(fig.axes) == 2


def test_fidelity_chart_from_a_table() -> None:
    df = pd.DataFrame({"fidelity": ["flexible (Radau rtol 1e-6)", "linear", "flexible"],
                       "time_step_s": [np.nan, np.nan, 0.005], "seconds_per_eval": [40.0, 0.05, 0.4],
                       "max_rel_error": [0.0, 3e-3, 1.6e-3], "max_rel_error_damage": [np.nan, 3e-3, 6e-4]})
    assert plot_fidelity(df).axes[0].get_xscale() == "log"
