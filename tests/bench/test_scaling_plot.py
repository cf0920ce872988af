"""The scaling chart draws the three drive models' runs (issue 27: "the scaling chart includes both models")."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from ddgsa.bench.scaling import format_scaling, plot  # noqa: E402


def test_runs_panel_shows_every_model_with_its_cost_a_run() -> None:
    runs = [{"runs": n, "jobs": 2, "wall_s": 1.5e-3 * n} for n in (100, 1000)]
    models = [{"model": m, "runs": n, "jobs": 2, "wall_s": c * n} for m, c in (("hss_rig", 0.05), ("indirect_drive", 0.04))
              for n in (100, 1000)]
    res = {"machine": "test", "quick": False, "runs": runs, "models": models, "runs_exponent": 1.0,
           "parameters": [{"parameters": 5, "wall_s": 0.2, "runs": 58}, {"parameters": 10, "wall_s": 0.3, "runs": 83}],
           "parameters_exponent": 0.5, "workers_runs": 100,
           "workers": [{"backend": "loky", "workers": 1, "wall_s": 2.0, "efficiency": 1.0},
                       {"backend": "loky", "workers": 2, "wall_s": 1.1, "efficiency": 0.91}]}
    fig = plot(res)
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert any(lab.startswith("direct drive") for lab in labels)
    assert "test rig, steady 1.2 s (50 ms a run at 1000)" in labels
    assert "geared drive, 600 s scene (40 ms a run at 1000)" in labels
    plt.close(fig)
    text = format_scaling(res)
    assert "hss_rig: 100: 5.00 s, 1000: 50.00 s" in text and "indirect_drive: 100: 4.00 s" in text
