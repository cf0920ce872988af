"""One verdict everywhere (issues 48.2, 51.6): a study's ``confirmation.csv`` is the one place its
verdict per (scene, output) lives, and the console, the exit code, ``summary.md``, ``indices.csv``,
``report.html`` and the NetCDF export say the same, row by row; ``ranking:`` changes the claims, not
the runs."""

from __future__ import annotations

import html
import re
from pathlib import Path

import pandas as pd
import pytest

from ddgsa.cli import main

xr = pytest.importorskip("xarray")

STUDY = """\
name: verdicts
model: {{name: analytic, fidelity: exact}}
parameters:
  x1: {{low: -3.14159265, high: 3.14159265}}
  x2: {{low: -3.14159265, high: 3.14159265}}
  x3: {{low: -3.14159265, high: 3.14159265}}
scenes: {{wind_speed: [8.0, 11.0], turbulence_intensity: 0.0, duration: 1.0, dt: 0.05}}
outputs: [y, y_positive]
methods: [{{method: saltelli, n: {n}, seed: 0}}]
{extra}"""
# y_positive = 12 + (wind / 11) Ishigami: ST 0.558, 0.442, 0.244 (no ties, none negligible); y is the
# same function less 12, so its indices are the same


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, int, str]:
    tmp = tmp_path_factory.mktemp("verdicts")
    study = tmp / "verdicts.yaml"
    study.write_text(STUDY.format(n=128, extra=""))
    import contextlib
    import io

    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = main(["run", str(study), "--out", str(tmp / "out"), "--quiet"])
    return tmp / "out", code, err.getvalue()


def test_every_reader_says_the_verdict_of_confirmation_csv(folder: tuple[Path, int, str]) -> None:
    out, code, console = folder
    table = pd.read_csv(out / "confirmation.csv", keep_default_na=False)
    assert len(table) == 4 and set(table["verdict"]) <= {"trusted", "rank-confirmed", "confirmed tie",
                                                          "nothing to rank", "unconfirmed"}
    verdict = {(int(r.scene), r.output): r.verdict for r in table.itertuples()}
    open_ = {k for k, v in verdict.items() if v == "unconfirmed"}
    # exit code and console: exit 3 exactly when a pair is unconfirmed; the console names those outputs
    assert code == (3 if open_ else 0)
    named = set(re.findall(r"output '(\w+)': no method's indices are confirmed", console))
    assert named == {o for _, o in open_}
    # summary.md: the count of each verdict
    summary = (out / "summary.md").read_text()
    done = sum(v != "unconfirmed" for v in verdict.values())
    assert f"Confirmed: {done} of 4 (scene, output) pairs" in summary
    # indices.csv: each row carries its pair's verdict
    idx = pd.read_csv(out / "indices.csv", keep_default_na=False)
    assert all(verdict[(int(r.scene), r.output)] == r.verdict for r in idx.itertuples())
    # report.html: the Verdicts table holds the same rows
    html = (out / "report.html").read_text()
    section = html[html.index('id="confirmation"'):]
    section = section[:section.index("</table>")]
    cells = re.findall(r"<tr[^>]*><td>(\d+)</td><td>(\w+)</td><td>([\w -]+)</td>", section)
    assert {(int(s), o): v for s, o, v in cells} == verdict
    for (s, o), v in verdict.items():                      # each bar chart's caption says its pair's verdict
        assert f"scene {s} (" in html and f"{o}: verdict {v} (" in html
    # the NetCDF export: variable verdict over (scene, output)
    assert main(["export", str(out)]) == 0
    ds = xr.open_dataset(out / "indices.nc")
    got = {(int(s), str(o)): str(ds["verdict"].sel(scene=s, output=o).item())
           for s in ds["scene"].values for o in ds["output"].values}
    assert got == verdict
    # the rows no longer carry a per-scene rank_confirmed coordinate (it was read as a scene field)
    assert "rank_confirmed" not in ds.coords and "rank_confirmed" not in html.split('id="indices"')[1][:2000]


def test_a_ranking_block_changes_the_claims_and_keeps_the_runs(tmp_path: Path) -> None:
    """``ranking: {tie_margin: 0.5}``: with a margin that wide x1 (0.558) and x2 (0.442) are a confirmed
    tie wherever their intervals (+-~0.1 at n = 128) allow it; the digest and the stored runs stay."""
    from ddgsa.study.spec import load_study

    plain, wide = tmp_path / "a.yaml", tmp_path / "b.yaml"
    plain.write_text(STUDY.format(n=128, extra=""))
    wide.write_text(STUDY.format(n=128, extra="ranking: {tie_margin: 0.5, negligible: 0.01}\n"))
    assert load_study(plain).digest == load_study(wide).digest
    main(["run", str(wide), "--out", str(tmp_path / "out"), "--quiet"])
    idx = pd.read_csv(tmp_path / "out" / "indices.csv", keep_default_na=False)
    ranks = idx[(idx["scene"] == 0) & (idx["output"] == "y_positive")
                & (idx["method"] == "saltelli")].set_index("parameter")["rank"]
    assert ranks["x1"] == ranks["x2"] == "1="
    # the summary and the report say what a tie means here
    words = "Tie margin 0.5, negligible floor 0.01 (the study's `ranking:`)."
    assert words in (tmp_path / "out" / "summary.md").read_text()
    page = (tmp_path / "out" / "report.html").read_text()
    verdicts = html.unescape(re.sub("<[^>]+>", "", page[page.index('id="confirmation"'):]))
    assert words.replace("`", "") in verdicts
    bad = tmp_path / "c.yaml"
    bad.write_text(STUDY.format(n=128, extra="ranking: {tie_margin: 2}\n"))
    assert main(["validate", str(bad)]) == 2


def test_the_wall_budget_runs_the_cheapest_stages_that_fit() -> None:
    from ddgsa.execute.kinds.gsa import WallBudget

    clock = WallBudget(10.0, 0.01)                   # 10 s, 10 ms a run: 1 000 runs fit
    assert clock.fitting({0: 800, 1: 150, 2: 100}) == [2, 1]       # 100 + 150 fit, 800 more would not
    assert clock.fitting({0: 2000}) == []
    assert "stopped by the time budget (10 s)" in clock.stopped(2000)
    assert WallBudget(None, 0.01).fitting({0: 10 ** 9}) == [0]      # no limit: everything
    assert WallBudget(10.0, float("nan")).fitting({0: 50, 1: 5}) == [1]   # no estimate: the smallest, to measure


def test_a_time_budget_stops_cleanly_and_says_what_the_rest_would_cost(tmp_path: Path,
                                                                       capsys: pytest.CaptureFixture[str]) -> None:
    """``ddgsa run --confirm-time '1 s'`` on a model that takes 20 ms a point: the escalations' first
    stages (32 points a scene, >= 0.64 s each) do not both fit, so one scene's runs and the other stops,
    saying so in provenance, and the unconfirmed pairs carry their cost in confirmation.csv."""
    import json

    study = tmp_path / "slow.yaml"
    study.write_text(STUDY.format(n=16, extra="").replace("fidelity: exact}", "fidelity: exact, options: "
                                                           "{delay_s: 0.02}}"))
    code = main(["run", str(study), "--out", str(tmp_path / "out"), "--quiet", "--jobs", "1",
                 "--confirm-time", "1 s"])
    prov = json.loads((tmp_path / "out" / "provenance.json").read_text())
    assert all(c["time_s"] == 1.0 for c in prov["confirm"])
    assert sum(c["spent"] for c in prov["confirm"]) <= 32      # at >= 20 ms a run, 1 s holds 50 runs at most
    table = pd.read_csv(tmp_path / "out" / "confirmation.csv", keep_default_na=False)
    assert code == (3 if (table["verdict"] == "unconfirmed").any() else 0)
    assert (table[table["verdict"] == "unconfirmed"]["next_runs"] > 0).all()
    stopped = [c for c in prov["confirm"] if any("stopped by the time budget (1 s)" in line for line in c["log"])]
    assert stopped and all(c["stopped_by_time"] == (c in stopped) for c in prov["confirm"])
    # the folder's study.yaml says the budget (newcomer trial: `ddgsa report` dropped the runs it spent)
    assert "time: 1 s" in (tmp_path / "out" / "study.yaml").read_text()
    before = (tmp_path / "out" / "confirmation.csv").read_text()
    assert main(["report", str(tmp_path / "out"), "--quiet"]) == code
    assert (tmp_path / "out" / "confirmation.csv").read_text() == before
    capsys.readouterr()
    assert main(["run", str(tmp_path / "nowhere.yaml"), "--confirm-time", "-1 s"]) == 2   # before the study loads
    assert "--confirm-time '-1 s': must be > 0" in capsys.readouterr().err
    assert main(["validate", str(study)]) == 0
    bad = tmp_path / "bad.yaml"
    bad.write_text(STUDY.format(n=16, extra="confirm: {time: 10 parsecs}\n"))
    assert main(["validate", str(bad)]) == 2
    none = tmp_path / "none.yaml"
    none.write_text(STUDY.format(n=16, extra="confirm: {seed: 1}\n"))
    assert main(["validate", str(none)]) == 2


def test_the_console_says_the_verdicts_on_success_too(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Newcomer trial: on exit 0 the console said no verdict; now one line, the counts of confirmation.csv."""
    study = tmp_path / "ok.yaml"
    study.write_text(STUDY.format(n=128, extra="").replace("[{method: saltelli, n: 128, seed: 0}]",
                                                           "[{method: pce, order: 9, fit: sparse, n: 512}]"))
    code = main(["run", str(study), "--out", str(tmp_path / "out")])
    table = pd.read_csv(tmp_path / "out" / "confirmation.csv", keep_default_na=False)
    done = int((table["verdict"] != "unconfirmed").sum())
    line = next(ln for ln in capsys.readouterr().out.splitlines() if "pairs confirmed" in ln)
    assert f"{done} of {len(table)} (scene, output) pairs confirmed" in line and code == (0 if done == len(table) else 3)
    for verdict, n in table["verdict"].value_counts().items():
        assert f"{n} {verdict}" in line


def test_the_api_takes_a_dict_of_distributions_and_a_dict_scene() -> None:
    """Newcomer trial: ddgsa.sobol(f, {dict}) and model.evaluate(x, {scene fields}) were tracebacks."""
    import numpy as np

    import ddgsa
    from ddgsa.errors import ModelError

    res = ddgsa.sobol(lambda x: x[:, 0] + 0.1 * x[:, 1], {"a": {"low": 0, "high": 1}, "b": {"low": 0, "high": 1}},
                      method="saltelli", n=512, seed=0)
    assert res.indices["ST"].to_numpy() == pytest.approx([1 / 1.01, 0.01 / 1.01], abs=0.03)   # linear: b_i^2 / sum
    model = ddgsa.models.get("analytic", fidelity="exact")
    assert model.evaluate(np.zeros((1, 3)), {"wind_speed": 11.0})["y_positive"].iloc[0] == pytest.approx(12.0)
    with pytest.raises(ModelError, match="did you mean 'wind_speed'"):
        model.evaluate(np.zeros((1, 3)), {"wind_sped": 11.0})
