"""A study's ``confirm: {budget}`` block (issue 25): escalation in the pipeline, reuse of the store,
bad input. The indices are Ishigami's (the analytic model); their claims are checked in
``tests/gsa/test_escalate.py``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

import pytest

from ddgsa.cli import main
from ddgsa.gsa.escalate import PCE_NAME
from ddgsa.gsa.testfunctions import ishigami
from ddgsa.execute.pipeline import execute
from ddgsa.execute.kinds.gsa import GsaResult
from ddgsa.runner import EvaluationStore
from ddgsa.study.spec import load_study


def test_the_pipeline_adds_the_escalation_beside_the_methods(write_study, tmp_path: Path) -> None:
    """In process, one scene and realisation: M-DRM's 45 distinct points leave Ishigami unconfirmed;
    ``confirm: {budget: 300}`` adds 45 Sobol' points, after which the refitted pooled expansion
    confirms it; a rerun reads every evaluation from the store."""
    text = write_study().read_text().replace("  - {method: saltelli, n: 64, seed: 0}\n", "")
    text = text.replace("wind_speed: [8.0, 11.0]", "wind_speed: 11.0").replace("realisations: 2", "realisations: 1")
    path = tmp_path / "c.yaml"
    path.write_text(text.replace("outputs: [y, y_positive]", "outputs: [y]") + "confirm: {budget: 300}\n")
    store = EvaluationStore(tmp_path / "evaluations.sqlite")
    res = execute(load_study(path), store, quiet=True)
    assert type(res) is GsaResult                       # the gsa kind's own result type (issue 24)
    assert res.provenance["confirm"][0]["spent"] == 45
    assert res.provenance["evaluations"]["total"] == 90
    t = res.indices
    assert set(t["method"]) == {"mdrm", "pooled_pce", "given_data_s1", PCE_NAME}
    assert not t[t["method"] == "mdrm"]["rank_confirmed"].any()
    esc = t[t["method"] == PCE_NAME]
    assert (esc["trusted"] | esc["rank_confirmed"]).all() and (esc["n_evals"] == 90).all()
    again = execute(load_study(path), store, quiet=True)
    assert again.provenance["evaluations"]["evaluated"] == 0
    assert again.indices.equals(t)


def test_the_escalation_says_what_confirmed_and_lends_its_draws_to_the_moments(write_study, tmp_path: Path) -> None:
    """Newcomer trial (#48): the log said 'saltelli (...): every output confirmed' where confirmation.csv
    credited confirm_pce, and the summary said the cross-checks are 'not the study's answer' where a verdict
    came from pooled_pce; the moments came from M-DRM's 32-point check sample beside the escalation's larger
    sample; the summary did not say what the escalation spent or why it stopped. Ishigami (a = 7, b = 0.1)
    has mean a / 2 = 3.5 and variance a^2/8 + b pi^4/5 + b^2 pi^8/18 + 1/2 = 13.84 (std 3.72)."""
    from ddgsa.execute.confirm import verdicts
    from ddgsa.report.write import summary_markdown

    text = write_study().read_text().replace("  - {method: saltelli, n: 64, seed: 0}\n", "")
    text = text.replace("wind_speed: [8.0, 11.0]", "wind_speed: 11.0").replace("realisations: 2", "realisations: 1")
    path = tmp_path / "c.yaml"
    path.write_text(text.replace("outputs: [y, y_positive]", "outputs: [y]") + "confirm: {budget: 300}\n")
    res = execute(load_study(path), EvaluationStore(tmp_path / "evaluations.sqlite"), quiet=True)
    method = verdicts(res).set_index("output").loc["y", "method"]
    assert method == PCE_NAME
    assert res.provenance["confirm"][0]["log"][-1] == f"pce (+45 runs, 45 of 300): every output confirmed (by {method})"
    m = res.moments.set_index("output").loc["y"]
    assert m["n"] == 45 and m["source"] == "confirm: escalation's draws (45 points)"
    study = load_study(path)                            # the escalation's points: its Sobol' sequence, seed + 2
    y = ishigami().f(study.space.sample(64, seed=2, rule="sobol")[:45])
    assert m["mean"] == pytest.approx(y.mean(), rel=1e-6) and m["std"] == pytest.approx(y.std(ddof=1), rel=1e-6)
    var = 7**2 / 8 + 0.1 * np.pi**4 / 5 + 0.01 * np.pi**8 / 18 + 0.5    # and they are a sample of Ishigami:
    assert abs(m["mean"] - 3.5) < 0.6 and abs(m["std"] / np.sqrt(var) - 1) < 0.15   # ~1 plain-MC standard error
    summary = summary_markdown(res)
    assert ("- `confirm:` escalation, scene 0: 45 runs spent (budget: 300 points per scene); last: pce (+45 runs, "
            f"45 of 300): every output confirmed (by {method})") in summary
    # a cross-check (pooled_pce) may give a verdict like any method: the summary no longer says it cannot
    assert "not the study's answer" not in summary and "confirms that (scene, output) pair" in summary


@pytest.mark.slow
def test_a_study_confirm_block_escalates_and_reuses_the_store(write_study, tmp_path: Path, capsys) -> None:
    """The CLI (about 15 s): ``confirm: {budget: 300}`` on the analytic model (Ishigami x wind_speed / 11): M-DRM alone
    exits 3 (unconfirmed), with the block the study is confirmed in both scenes (each stage told on the
    console), the added points are in provenance, and a second run finds every evaluation in the store."""
    text = write_study(n=64).read_text().replace("  - {method: saltelli, n: 64, seed: 0}\n", "")
    study = tmp_path / "c.yaml"
    study.write_text(text.replace("outputs: [y, y_positive]", "outputs: [y]"))
    out = tmp_path / "out"
    assert main(["-q", "run", str(study), "--out", str(out)]) == 3
    study.write_text(study.read_text() + "confirm: {budget: 300}\n")
    capsys.readouterr()
    assert main(["run", str(study), "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert "ddgsa: confirm, scene 0: next: pce points +" in err and "ddgsa: confirm, scene 1: pce (+" in err
    table = pd.read_csv(out / "indices.csv")
    esc = table[table["method"] == PCE_NAME]
    assert sorted(esc["scene"].unique()) == [0, 1]
    assert (esc["trusted"] | esc["rank_confirmed"]).all()
    prov = pd.read_json(out / "provenance.json", typ="series")
    assert [c["spent"] for c in prov["confirm"]] == [45, 45]
    assert prov["evaluations"]["total"] == 2 * 2 * (45 + 45)     # 2 scenes x 2 realisations
    assert main(["-q", "run", str(study), "--out", str(out)]) == 0
    prov = pd.read_json(out / "provenance.json", typ="series")
    assert prov["evaluations"]["evaluated"] == 0


def test_a_confirm_block_outside_a_gsa_study_is_exit_2(write_study, tmp_path: Path, capsys) -> None:
    text = write_study().read_text().replace("name: demo", "name: demo\nkind: fault")
    study = tmp_path / "bad.yaml"
    study.write_text(text.replace("methods:", "confirm: {budget: 10}\nmethods:"))
    assert main(["validate", str(study)]) == 2
    study.write_text(write_study().read_text() + "confirm: {budget: many}\n")
    assert main(["validate", str(study)]) == 2
    assert "confirm.budget" in capsys.readouterr().err


@pytest.mark.slow
def test_the_escalation_pools_the_points_auto_ran(write_study, tmp_path: Path) -> None:
    """``auto`` with a budget of 120 leaves Ishigami unconfirmed; the escalation starts from its
    distinct points (each once: a repeated point would flatter the leave-one-out error) and its
    pooled expansion is fitted on those plus the ones it added (about 5 s)."""
    text = write_study().read_text().replace("  - {method: saltelli, n: 64, seed: 0}\n", "")
    text = text.replace("{method: mdrm, points: 5}", "{method: auto, budget: 120}")
    text = text.replace("wind_speed: [8.0, 11.0]", "wind_speed: 11.0").replace("realisations: 2", "realisations: 1")
    path = tmp_path / "a.yaml"
    path.write_text(text.replace("outputs: [y, y_positive]", "outputs: [y]") + "confirm: {budget: 400}\n")
    res = execute(load_study(path), EvaluationStore(tmp_path / "evaluations.sqlite"), quiet=True)
    t = res.indices
    spent = res.provenance["confirm"][0]["spent"]
    ran = res.provenance["evaluations"]["total"]
    esc = t[t["method"] == PCE_NAME]
    assert (esc["n_evals"] == ran).all() and spent < ran        # every distinct point, auto's included
    assert not t[t["method"] == "auto"]["trusted"].all() and esc["trusted"].all()


def test_a_budget_per_scene_value_escalates_each_scene_to_its_own(write_study, tmp_path: Path, capsys) -> None:
    """``confirm: {budget: {8.0: 0, 11.0: 300}}`` keyed by the wind speed: the scene at 8 m/s spends nothing and
    stays unconfirmed, the one at 11 m/s spends 45 points and is confirmed (as with ``budget: 300`` alone, above);
    the unconfirmed pair's next step raises only its own key. Bad mappings are refused naming ``confirm.budget``."""
    from ddgsa.execute.confirm import verdicts

    text = write_study().read_text().replace("  - {method: saltelli, n: 64, seed: 0}\n", "")
    text = text.replace("realisations: 2", "realisations: 1").replace("outputs: [y, y_positive]", "outputs: [y]")
    path = tmp_path / "c.yaml"
    path.write_text(text + "confirm: {budget: {8.0: 0, 11.0: 300}}\n")
    res = execute(load_study(path), EvaluationStore(tmp_path / "evaluations.sqlite"), quiet=True)
    conf = res.provenance["confirm"]
    assert [(c["scene"], c["budget"], c["spent"]) for c in conf] == [(0, 0, 0), (1, 300, 45)]
    v = verdicts(res).set_index("scene")
    assert v.loc[1, "verdict"] in ("trusted", "rank-confirmed") and v.loc[0, "verdict"] == "unconfirmed"
    assert "`confirm: {budget: {8.0: " in v.loc[0, "next_step"] and ", 11.0: 300}}`" in v.loc[0, "next_step"]
    for bad, words in (("{8.0: 10}", "keyed by all of its values"), ("{8.0: true, 11.0: 5}", "whole number"),
                       ("{8.0: 1.5, 11.0: 5}", "whole number"), ("-1", "whole number"),
                       ("{low: 1, high: 2}", "keyed by all of its values")):
        path.write_text(text + f"confirm: {{budget: {bad}}}\n")
        assert main(["validate", str(path)]) == 2
        err = capsys.readouterr().err
        assert "confirm.budget" in err and words in err, (bad, err)


def test_a_per_value_budget_step_raises_and_counts_only_its_own_keys(write_study, tmp_path: Path) -> None:
    """The next step of a per-value budget (three wind speeds, ``{8.0: 2000, 11.0: 2000, 14.0: 5000}``): scene 0's
    largest ask (5 000 new points on top of its 1 000 spent) raises the key 8.0 to 6 000 and counts only its 5 000
    points, x 2 realisations; scene 1 (asked something, key 11.0) and scene 2 (left 4 600 of its 5 000 when it
    stopped) keep their budgets and add no runs (a single budget would have let them spend up to it too)."""
    from types import SimpleNamespace

    from ddgsa.execute.confirm import advice, budget_cost

    text = write_study().read_text().replace("wind_speed: [8.0, 11.0]", "wind_speed: [8.0, 11.0, 14.0]")
    path = tmp_path / "k.yaml"
    path.write_text(text + "confirm: {budget: {8.0: 2000, 11.0: 2000, 14.0: 5000}}\n")
    study = load_study(path)
    assert study.spec.scenes.realisations == 2
    asks0 = {"y": {"n": 512, "points": 1000, "control": True}, "z": {"n": 2048, "points": 5000, "control": True}}
    entries = [{"scene": 0, "budget": 2000, "spent": 1000, "log": ["budget of 2000 runs spent; unconfirmed: y, z"],
                "asks": asks0},
               {"scene": 1, "budget": 2000, "spent": 1500, "log": ["..."], "asks": {"z": {"n": 1024, "points": 900}}},
               {"scene": 2, "budget": 5000, "spent": 400, "log": ["stopped with 4600 of 5000 runs left: ..."],
                "asks": {"z": {"n": 4096, "points": 20000}}}]
    rows = pd.DataFrame({"scene": [0, 0, 1, 1, 2, 2], "output": "y", "parameter": ["a", "b"] * 3, "ST": [0.7, 0.3] * 3})
    result = SimpleNamespace(indices=rows, study=study, evaluations=pd.DataFrame({"seconds": [0.5]}),
                             provenance={"confirm": entries})
    grow = budget_cost(result, "y", [0])
    assert (grow.budget, grow.runs, grow.keyed) == (6000, 5000 * 2, ((8.0, 6000), (11.0, 2000), (14.0, 5000)))
    assert "`confirm: {budget: {8.0: 6000, 11.0: 2000, 14.0: 5000}}`" in advice(result, "y", [0])
