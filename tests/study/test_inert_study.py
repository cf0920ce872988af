"""A study's M-DRM runs the inert check (``GsaMethod.followup``) as :func:`ddgsa.sobol` does: the same
extra runs, the same bounds, the same note."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import ddgsa
from ddgsa.execute.pipeline import execute
from ddgsa.gsa.testfunctions import ishigami
from ddgsa.runner import EvaluationStore
from ddgsa.study.spec import load_study
from studytext import ishigami_study


def test_a_study_runs_the_inert_check_as_the_api_does(tmp_path: Path) -> None:
    # Ishigami's x3 acts only with x1 (0.1 x3^4 sin x1): flat on the cut lines through 0, so M-DRM
    # tests it -- and the 32 pairs differ: nothing is proven, x3 stays untrusted
    path = tmp_path / "inert.yaml"
    path.write_text(ishigami_study("inert", "methods:\n  - {method: mdrm, points: 7}\n", speeds="11.0",
                                   pi=repr(np.pi)))
    res = execute(load_study(path), EvaluationStore(tmp_path / "evaluations.sqlite"), quiet=True)
    # M-DRM's 3 x 7 + 1 + 32 points hold the centre 4 times (7 nodes: 0 is one): 51 distinct, then 32 pairs
    assert res.provenance["evaluations"]["total"] == 51 + 32
    t = res.indices
    row = t[(t["method"] == "mdrm") & (t["parameter"] == "x3")].iloc[0]
    assert not row["trusted"]
    d = res.diagnostics
    notes = d[d["name"] == "mdrm_inert_check"]["message"].tolist()
    assert len(notes) == 1 and "x3" in notes[0] and "nothing is proven" in notes[0]
    tf = ishigami()
    api = ddgsa.sobol(lambda x: tf.f(x) + 12.0, tf.space, "mdrm", points=7)
    assert api.n_evals == 3 * 7 + 1 + 32 + 32
    a = api.indices.set_index("parameter")
    assert a.loc["x3", "ST_conf"] == pytest.approx(row["ST_conf"], rel=1e-6)
    assert a.loc["x1", "ST"] == pytest.approx(t[(t["method"] == "mdrm") & (t["parameter"] == "x1")]["ST"].iloc[0],
                                              rel=1e-9)
