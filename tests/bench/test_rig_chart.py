"""The rig's speed-against-accuracy chart (issue 46: block vs per-point linear vs nonlinear, ``ddgsa bench rig``)."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest

from ddgsa.bench.rig import OUTPUTS
from ddgsa.bench.rig_chart import PATHS, _errors, format_speed_accuracy, speed_accuracy, write


def test_error_is_the_largest_relative_difference_over_outputs_above_their_resolution() -> None:
    ref = pd.DataFrame({o: [2.0, 1.0] for o in OUTPUTS})
    out = ref.copy()
    out.loc[0, OUTPUTS[0]] = 2.2                    # 10 % off
    out.loc[1, OUTPUTS[1]] = 0.97                   # 3 % off
    ref.loc[1, OUTPUTS[2]], out.loc[1, OUTPUTS[2]] = 1e-9, 5e-9    # below its resolution: not judged
    resolution = {o: 1e-6 for o in OUTPUTS}
    np.testing.assert_allclose(_errors(out, ref, resolution), [0.1, 0.03], rtol=1e-12)
    out.loc[0, OUTPUTS[3]] = math.nan               # a failed point has no error
    assert np.isnan(_errors(out, ref, resolution)[0])


def test_chart_and_json_are_written(tmp_path) -> None:
    rows = [{"scene": s, "path": p, "points": 2, "cpu_s_per_run": c, "median_rel_error": e, "max_rel_error": 2 * e,
             "failed_points": 0}
            for s in ("steady", "startup", "coastdown") for p, c, e in zip(PATHS, (10.0, 0.1, 0.005), (1e-3, 3e-3, 3e-3))]
    res = {"machine": "test", "python": "3.11", "quick": True, "points": 2, "seed": 1, "outputs": list(OUTPUTS),
           "reference": "kloss", "rows": rows, "load_average": [0.0, 0.0, 0.0]}
    paths = write(res, tmp_path)
    assert [p.name for p in paths] == ["rig_speed_accuracy.json", "rig_speed_accuracy.png"]
    assert json.loads(paths[0].read_text())["rows"][2]["cpu_s_per_run"] == 0.005
    assert paths[1].stat().st_size > 10_000
    assert "linear, block" in format_speed_accuracy(res)


@pytest.mark.slow
def test_block_and_per_point_agree_with_each_other_and_the_nonlinear_rig() -> None:
    """One point a scene: the two linear paths' errors against ``kloss`` agree (they are the same model within
    1e-3) and stay within 2 % with an axisymmetric coupling (docs/hss_rig.md: 0.19-0.29 % at nominal)."""
    res = speed_accuracy(points=1, quick=True)
    by = {(r["scene"], r["path"]): r for r in res["rows"]}
    for scene in ("steady", "startup", "coastdown"):
        block, single = by[(scene, "linear, block")], by[(scene, "linear, per point")]
        assert block["failed_points"] == single["failed_points"] == 0
        assert abs(block["max_rel_error"] - single["max_rel_error"]) < 1e-3
        assert block["max_rel_error"] < 0.02
