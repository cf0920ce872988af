"""Groups, correlation with Shapley, targets and HSIC from a YAML study through the CLI into the report."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import ddgsa
from ddgsa.cli import main
from ddgsa.closed_forms import ishigami
from studytext import ishigami_study


def beyond_study(name: str, extra: str, output: str) -> str:
    """A one-scene Ishigami study (11 m/s) of ``output`` with ``extra`` (methods and the fields under test)."""
    return ishigami_study(name, extra + "\n", speeds="11.0", output=output)


def _run(tmp_path: Path, name: str, extra: str, output: str = "y") -> Path:
    path = tmp_path / f"{name}.yaml"
    path.write_text(beyond_study(name=name, extra=extra, output=output))
    out = tmp_path / name
    assert main(["run", str(path), "--out", str(out), "-q", "--allow-untrusted"]) == 0
    return out


def test_groups_study_writes_closed_and_total_group_indices(tmp_path: Path) -> None:
    """The study's group indices are those of the Python API on the same design (y_positive = Ishigami + 12
    at 11 m/s); their values against closed forms are tests/gsa/test_beyond.py's."""
    out = _run(tmp_path, "grp", "groups: {x12: [x1, x2], x3only: [x3]}\nmethods: [{method: mdrm, points: 4, check: 8}]",
               output="y_positive")
    g = pd.read_csv(out / "groups.csv")
    g = g[g["method"] == "mdrm"]          # the pooled PCE cross-check gives its own
    assert list(g.columns) == ["scene", "method", "output", "group", "members", "S_closed", "S_closed_conf", "ST",
                               "ST_conf", "trusted", "rank_confirmed", "rank"]
    space = ddgsa.ParameterSpace.from_dict({f"x{i}": {"low": -3.14159265, "high": 3.14159265} for i in (1, 2, 3)},
                                           groups={"x12": ["x1", "x2"], "x3only": ["x3"]})
    api = ddgsa.sobol(lambda x: ishigami(x) + 12.0, space, method="mdrm", points=4, check=8).groups
    np.testing.assert_allclose(g[["S_closed", "ST"]].to_numpy(float), api[["S_closed", "ST"]].to_numpy(float),
                               rtol=1e-6)
    assert g["trusted"].tolist() == api["trusted"].tolist()
    assert g["rank"].astype(object).where(g["rank"].notna(), "").tolist() == api["rank"].tolist()
    summary = (out / "summary.md").read_text()
    assert "## Groups: closed and total indices" in summary and "| 0 | `y_positive` | mdrm | x12 (x1 x2) |" in summary
    assert (out / "groups_scene0.png").exists()


def test_correlated_study_needs_shapley_and_reports_it(tmp_path: Path, capsys) -> None:
    corr = "correlation: [[x1, x2, 0.5]]\n"
    path = tmp_path / "bad.yaml"
    path.write_text(beyond_study(name="bad", output="y", extra=corr + "methods: [{method: mdrm, points: 4}]"))
    assert main(["validate", str(path)]) == 2
    err = capsys.readouterr().err
    assert "field 'methods[0]': method 'mdrm' assumes independent inputs" in err and "use method 'shapley'" in err
    path.write_text(beyond_study(name="bad", output="y", extra="correlation: [[x1, x9, 0.5]]\nmethods: [{method: shapley}]"))
    assert main(["validate", str(path)]) == 2
    assert "field 'correlation[0]': 'x9' is not a parameter of the space" in capsys.readouterr().err
    out = _run(tmp_path, "shap", corr + "methods: [{method: shapley, n_v: 100, n_o: 20, n_i: 3}]")
    t = pd.read_csv(out / "indices.csv")
    assert {"Sh", "Sh_conf"} <= set(t.columns) and abs(t["Sh"].sum() - 1.0) < 0.3
    assert "## Shapley effects (dependent inputs)" in (out / "summary.md").read_text()


def test_target_study_adds_the_transformed_outputs(tmp_path: Path) -> None:
    """1{y > 3.5}: its indicator's mean is the exceedance probability, in (0, 1); unit '-'."""
    out = _run(tmp_path, "tgt", "target: {output: y, above: 3.5}\nmethods: [{method: saltelli, n: 32}]")
    t = pd.read_csv(out / "indices.csv")
    assert set(t["output"]) == {"y", "y_exceeds"}
    assert set(t.loc[t["output"] == "y_exceeds", "output_unit"]) == {"-"}
    m = pd.read_csv(out / "output_moments.csv").set_index("output")
    assert 0.2 < m.loc["y_exceeds", "mean"] < 0.8
    # at n 32 nothing is confirmed: the raw output is offered confirm:, the target output only a Saltelli design
    lines = {line.split("'")[1]: line for line in (out / "summary.md").read_text().splitlines()
             if line.startswith("- output '")}
    assert "`confirm: {budget:" in lines["y"] and "`confirm: {budget:" not in lines["y_exceeds"]
    assert "a target output: `confirm:` escalates the model's own outputs only" in lines["y_exceeds"]


def test_hsic_study_reports_screening_without_a_problem(tmp_path: Path) -> None:
    out = _run(tmp_path, "hs", "methods: [{method: hsic, n: 100, permutations: 200}]")
    t = pd.read_csv(out / "indices.csv").set_index("parameter")
    assert t.loc["x1", "p_value"] < 0.05 and t["S1"].isna().all()
    summary = (out / "summary.md").read_text()
    assert "## HSIC screening" in summary and "## Problems" not in summary


def test_hsic_study_writes_its_verdicts_and_its_next_step_ranks_them(tmp_path: Path) -> None:
    """An HSIC-only study (issue 46: every study folder gets a ``confirmation.csv``): one ``screened`` row per
    (scene, output), exit 0 without ``--allow-untrusted``, the parameters screened in as its ranking, the
    output's spread from the Latin hypercube's own runs; the next step it names (``--confirm-time``) then ranks
    them: Ishigami's closed-form indices (S1 0.314, 0.442, 0; ST 0.558, 0.442, 0.244) within the tolerance."""
    path = tmp_path / "hs.yaml"
    path.write_text(beyond_study(name="hs", extra="methods: [{method: hsic, n: 100, permutations: 200}]", output="y"))
    out = tmp_path / "hs"
    assert main(["run", str(path), "--out", str(out), "-q"]) == 0
    conf = pd.read_csv(out / "confirmation.csv")
    assert conf[["verdict", "method", "runs"]].values.tolist() == [["screened", "hsic", 100]]
    t = pd.read_csv(out / "indices.csv")
    inside = t[t["p_value"] < 0.05]["parameter"].tolist()
    assert "x1" in inside
    assert conf["ranking"][0] == "screened in: " + ", ".join(t.sort_values("p_value", kind="stable")
                                                             .query("p_value < 0.05")["parameter"])
    y = pd.read_csv(out / "evaluations.csv")["y"].to_numpy(float)
    assert conf["std"][0] == pytest.approx(y.std(ddof=1), rel=1e-5)
    assert "--confirm-time '5 min'" in conf["next_step"][0]
    summary = (out / "summary.md").read_text()
    assert "## Verdicts" in summary and "`y` in scene 0: screened in: " in summary
    assert main(["run", str(path), "--out", str(out), "-q", "--confirm-time", "2 min"]) == 0
    conf = pd.read_csv(out / "confirmation.csv")
    assert conf["verdict"][0] in ("trusted", "rank-confirmed")
    t = pd.read_csv(out / "indices.csv")
    rows = t[t["method"] == conf["method"][0]].set_index("parameter")
    np.testing.assert_allclose(rows.loc[["x1", "x2", "x3"], "ST"], [0.5576, 0.4424, 0.2437], atol=0.05)
