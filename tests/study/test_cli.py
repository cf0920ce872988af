"""The ddgsa CLI end to end: files written, indices equal the Python API, reproducibility across
workers and backends, kill and resume, failures, malformed studies."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import ddgsa
from ddgsa.cli import main
from ddgsa.gsa.testfunctions import ishigami
from ddgsa.runner import EvaluationStore
from running import pages_committed

REPORT_FILES = {"indices.csv", "diagnostics.csv", "evaluations.csv", "accuracy.csv", "provenance.json",
                "summary.md", "bars_scene0.png", "bars_scene1.png", "heatmap_ST_mdrm.png", "mdrm_vs_crosscheck.png"}


def test_run_writes_report_and_equals_the_python_api(write_study, tmp_path: Path) -> None:
    out = tmp_path / "out"      # plain Ishigami is untrusted: its exit 3 is test_cli_habits.py's test_exit_codes_...
    assert main(["-q", "run", str(write_study()), "--out", str(out), "--allow-untrusted"]) == 0
    assert REPORT_FILES <= {p.name for p in out.iterdir()}
    table = pd.read_csv(out / "indices.csv")
    assert set(table.columns) >= {"study", "scene", "wind_speed", "output", "method", "parameter", "S1", "S1_conf",
                                  "ST", "ST_conf", "n_evals", "trusted"}
    tf = ishigami()
    for method, opts in (("mdrm", {"points": 5}), ("saltelli", {"n": 64, "seed": 0})):
        api = ddgsa.sobol(lambda x: tf.f(x) * 8.0 / 11.0, tf.space, method, **opts)
        got = table[(table["method"] == method) & (table["output"] == "y") & (table["scene"] == 0)]
        np.testing.assert_allclose(got["ST"].to_numpy(float), api.indices["ST"].to_numpy(float), rtol=1e-5)
        assert list(got["trusted"]) == list(api.indices["trusted"])
    # M-DRM flags plain Ishigami; the report says so
    assert "mdrm_cut_value" in set(pd.read_csv(out / "diagnostics.csv")["name"])
    # report rebuilds from stored evaluations without model runs
    assert main(["-q", "report", str(out), "--allow-untrusted"]) == 0


def _identical_for(write_study, tmp_path: Path, runs: list[list[str]]) -> None:
    """The same study's indices.csv, byte for byte, under each of ``runs``' command-line options."""
    study = write_study()
    tables = []
    for args in runs:
        if "dask" in args:
            pytest.importorskip("dask.distributed")
        out = tmp_path / "_".join(args).replace("-", "")
        assert main(["-q", "run", str(study), "--out", str(out), "--allow-untrusted", *args]) == 0
        tables.append((out / "indices.csv").read_text())
    assert all(t == tables[0] for t in tables[1:])


def test_results_identical_for_one_and_two_workers(write_study, tmp_path: Path) -> None:
    _identical_for(write_study, tmp_path, [["--jobs", "1"], ["--jobs", "2"]])


@pytest.mark.slow  # a Dask LocalCluster's start-up (~7 s)
def test_results_identical_with_the_dask_backend(write_study, tmp_path: Path) -> None:
    _identical_for(write_study, tmp_path, [["--jobs", "1"], ["--jobs", "2", "--backend", "dask"]])


@pytest.mark.slow  # ~25 s of subprocess study runs; tests/test_runner.py's SIGKILL tests stay in the default run
def test_kill_and_resume_evaluates_only_the_missing_points(write_study, tmp_path: Path) -> None:
    study = write_study("slow", options="{delay_s: 0.01}", n=32, batch=4)       # ~1 100 runs: killed after 200 WAL pages
    out = tmp_path / "killed"
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    proc = subprocess.Popen([sys.executable, "-m", "ddgsa.cli", "-q", "run", str(study), "--out", str(out)],
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    store_path = out / "evaluations.sqlite"
    deadline = time.time() + 60
    while time.time() < deadline and pages_committed(store_path) < 200:       # >= 34 commits of 4 runs
        time.sleep(0.2)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    store = EvaluationStore(store_path)
    done = store.count()
    store.close()
    assert done > 0
    assert main(["-q", "run", str(study), "--out", str(out), "--allow-untrusted"]) == 0
    prov = pd.read_json(out / "provenance.json", typ="series")
    total = prov["evaluations"]["total"]                   # scenes x realisations x pooled unique points
    assert done < total
    assert prov["evaluations"]["cached"] == done and prov["evaluations"]["evaluated"] == total - done
    clean = tmp_path / "clean"
    assert main(["-q", "run", str(study), "--out", str(clean), "--allow-untrusted"]) == 0
    assert (out / "indices.csv").read_text() == (clean / "indices.csv").read_text()


def test_failing_points_are_listed_and_their_indices_untrusted(write_study, tmp_path: Path) -> None:
    out = tmp_path / "fail"
    assert main(["-q", "run", str(write_study("failing", options="{fail_above: 2.5}")), "--out", str(out)]) == 3
    prov = pd.read_json(out / "provenance.json", typ="series")
    assert len(prov["failures"]) > 0 and "above fail_above" in prov["failures"][0]["error"]
    table = pd.read_csv(out / "indices.csv")
    assert not table["trusted"].any()                          # every output saw a failed point
    assert table["ST"].isna().all()                            # refused, not imputed
    assert "nonfinite_values" in set(pd.read_csv(out / "diagnostics.csv")["name"])


def test_validate_and_models(write_study, capsys) -> None:
    assert main(["validate", str(write_study())]) == 0
    assert "valid (gsa study 'demo'" in capsys.readouterr().out
    assert main(["models"]) == 0
    text = capsys.readouterr().out
    assert "direct_drive: fidelities flexible, rigid" in text and "k_front_y" in text


def test_yaml_1_2_numbers(write_study, tmp_path: Path) -> None:
    text = Path(write_study()).read_text().replace("x3: {low: -3.14159, high: 3.14159}", "x3: {low: -1e0, high: 1.0e0}")
    study = ddgsa.study.spec.load_study(write_study("sci", text=text))
    assert study.space["x3"].args == {"low": -1.0, "high": 1.0}


BASE = Path(__file__).with_name("conftest.py")


@pytest.mark.parametrize("edit, message", [
    (None, "no such study file"),
    ("model: {name: analytic\n", "YAML syntax error at line"),
    ("- just\n- a list\n", "a study is a mapping of fields"),
    ("REPLACE:parameters:|paramters:", "field 'paramters': unknown field"),
    ("REPLACE:model: {name: analytic, fidelity: exact, options: {}}|", "field 'model': required field is missing"),
    ("REPLACE:name: analytic|name: analytik", "field 'model.name': unknown model 'analytik'; known: analytic"),
    ("REPLACE:fidelity: exact|fidelity: rigid", "field 'model.fidelity': model 'analytic': unknown fidelity 'rigid'"),
    ("REPLACE:  x3: {|  x4: {", "field 'parameters.x4': not a parameter of model 'analytic'"),
    ("REPLACE:x1: {low|x1: {dist: gauss, low", "parameter 'x1': unknown dist 'gauss'"),
    ("REPLACE:x2: {low: -3.14159, high: 3.14159}|x2: {low: 1, high: 0}",
     r"parameter 'x2': low (1.0) must be < high (0.0)"),
    ("REPLACE:outputs: [y, y_positive]|outputs: [y, z]", "field 'outputs[1]': unknown output 'z'"),
    ("REPLACE:method: mdrm|method: mdmr", "field 'methods[0].method': unknown GSA method 'mdmr'"),
    ("REPLACE:points: 5|points: 1", "field 'methods[0]': method 'mdrm': option 'points' must be in [2, 40]"),
    ("REPLACE:wind_speed: [8.0, 11.0]|wind_speed: []", "field 'scenes.wind_speed': an empty list"),
    ("REPLACE:realisations: 2|realisations: many", "field 'scenes.realisations'"),
    ("REPLACE:wind_speed: [8.0, 11.0]|wind_speed: [-8.0]", "scene field 'wind_speed' must be in (0, 50]"),
    ("REPLACE:name: demo|name: my demo", "field 'name': String should match pattern"),
    ("REPLACE:name: demo|name: demo\nkind: fault", "kind 'fault' needs a 'fault' block"),
    ("REPLACE:x1: {low: -3.14159, high: 3.14159}|x1: {dist: normal, mean: 0, std: 1}",
     "field 'parameters.x1': parameter 'x1' support [-inf, inf] leaves its allowed range"),
    ("REPLACE:run: {jobs: 1|run: {jobs: 0", "field 'run.jobs': must be >= 1 (given: 0)"),
    ("REPLACE:name: demo|name: demo\ngrid: {x1: [0.0]}", "'grid' and 'model.variants' need kind: sweep"),
    ("REPLACE:method: mdrm, points: 5|method: auto, budget: 5", "field 'methods[0]': method 'auto': option 'budget'"),
])
def test_malformed_studies_exit_2_naming_the_field(write_study, tmp_path: Path, capsys, edit, message) -> None:
    if edit is None:
        path = tmp_path / "missing.yaml"
    elif edit.startswith("REPLACE:"):
        old, new = edit[len("REPLACE:"):].split("|")
        text = Path(write_study()).read_text()
        assert old in text
        path = write_study("bad", text=text.replace(old, new))
    else:
        path = write_study("bad", text=edit)
    for command in ("validate", "run"):
        assert main([command, str(path)]) == 2
        err = capsys.readouterr().err
        assert message in err and "Traceback" not in err
        assert str(path) in err


def test_quickstart_study_end_to_end(tmp_path: Path) -> None:
    """The README's quickstart through the CLI equals the same study through the Python API."""
    from ddgsa.gsa.base import get_method
    from ddgsa.study.spec import load_study

    study_file = Path(__file__).parents[2] / "studies" / "quickstart.yaml"
    out = tmp_path / "qs"
    assert main(["-q", "run", str(study_file), "--out", str(out)]) == 0
    assert {"indices.csv", "accuracy.csv", "provenance.json", "summary.md", "bars_scene0.png",
            "mdrm_vs_crosscheck.png", "evaluations.csv"} <= {p.name for p in out.iterdir()}
    table = pd.read_csv(out / "indices.csv")
    study = load_study(study_file)
    model = study.make_model()
    scene = study.spec.scenes.scene(study.spec.scenes.grid()[0], 0)
    mdrm = get_method("mdrm")
    design = mdrm.design(study.space, **study.spec.methods[0].options)
    values = model.evaluate(study.space.frame(design.points), scene)[study.outputs]
    api = mdrm.analyze(study.space, design, values)
    got = table[table["method"] == "mdrm"]
    np.testing.assert_allclose(got["ST"].to_numpy(float), api.indices["ST"].to_numpy(float), rtol=1e-5, atol=1e-9)


SEED003_DIR = Path(__file__).parents[2] / "studies"


def test_variant_and_grid_sweep_reproduce_seed003_frequencies(tmp_path: Path) -> None:
    """``model.variants`` x ``grid`` sweeps: seed 003's 34.5 / 38 Hz and the Fig. 14 trend, end to end."""
    out = tmp_path / "freq"
    assert main(["-q", "run", str(SEED003_DIR / "seed003_frequencies.yaml"), "--out", str(out)]) == 0
    table = pd.read_csv(out / "sweep_summary.csv").set_index("variant")["bearing_frequency_hz_mean"]
    assert round(table["config=one_mass, magnetic=False"], 1) == 34.5
    assert round(table["config=tower_side_to_side, magnetic=False"]) == 38
    assert table["config=substructure, magnetic=True"] < table["config=substructure, magnetic=False"]
    summary = (out / "summary.md").read_text()
    assert "| config=one_mass, magnetic=False | 34.4567" in summary
    # the aliasing guard: the 0.05 s load/controller interval cannot carry the 34 Hz bearing mode
    assert "## Sampling (aliasing guard)" in summary and "| load and controller interval (scene dt) | 0.05 |" in summary
    out = tmp_path / "sweep"
    assert main(["-q", "run", str(SEED003_DIR / "seed003_bearing_stiffness_sweep.yaml"), "--out", str(out)]) == 0
    sweep = pd.read_csv(out / "sweep_summary.csv")
    assert len(sweep) == 14 and {"sweep_bearing_frequency_hz.png", "sweep_tower_frequency_hz.png"} <= {
        p.name for p in out.iterdir()}
    tower = sweep[sweep["variant"] == "config=tower_torsion"].set_index("bearing_stiffness")["tower_frequency_hz_mean"]
    assert tower[1e10] == pytest.approx(tower[5e10], rel=0.01)


@pytest.mark.parametrize("edit, message", [
    ("grid: {bearing_stiffness: [1e3]}", "field 'grid.bearing_stiffness': parameter 'bearing_stiffness' = 1000 N/m leaves its allowed range"),
    ("grid: {stiffness: [1e9]}", "field 'grid.stiffness': not a parameter"),
    ("REPLACE:{config: one_mass, magnetic: false}|{config: one_mas}", "field 'model.variants[0]'"),
    ("REPLACE:outputs: [bearing_frequency_hz|outputs: [tower_frequency_hz",
     "output 'tower_frequency_hz' does not exist in model.variants[0]"),
])
def test_malformed_sweeps_name_the_field(write_study, capsys, edit: str, message: str) -> None:
    text = (SEED003_DIR / "seed003_frequencies.yaml").read_text()
    if edit.startswith("REPLACE:"):
        old, new = edit[len("REPLACE:"):].split("|")
        assert old in text
        text = text.replace(old, new)
    else:
        text += edit + "\n"
    path = write_study("bad_sweep", text=text)
    assert main(["validate", str(path)]) == 2
    err = capsys.readouterr().err
    assert message in err and str(path) in err


def test_method_auto_in_a_study_reports_its_decisions(write_study, tmp_path: Path) -> None:
    text = Path(write_study()).read_text().replace(
        "  - {method: mdrm, points: 5}\n  - {method: saltelli, n: 64, seed: 0}\n",
        "  - {method: auto, budget: 1500}\n")
    out = tmp_path / "auto"
    assert main(["-q", "run", str(write_study("auto", text=text)), "--out", str(out)]) == 0
    table = pd.read_csv(out / "indices.csv")
    tf = ishigami()
    for scene, factor in ((0, 8.0 / 11.0), (1, 1.0)):
        got = table[(table["scene"] == scene) & (table["output"] == "y")]
        assert set(got["source"]) == {"pce"} and got["trusted"].all()
        assert np.abs(got["ST"].to_numpy() - tf.ST).max() < 0.02
    summary = (out / "summary.md").read_text()
    assert "auto (from pce)" in summary and "## `method: auto` decisions" in summary
    assert "mdrm (48 runs): untrusted rows: y [x1, x2, x3]" in summary
    # the report rebuilds from the store without model runs; a rerun evaluates nothing
    assert main(["-q", "report", str(out)]) == 0
    assert main(["-q", "run", str(write_study("auto", text=text)), "--out", str(out)]) == 0
    prov = (out / "provenance.json").read_text()
    assert '"evaluated": 0' in prov


def test_fidelity_defaults_to_the_models_richest(write_study) -> None:
    import ddgsa.study.spec

    text = (SEED003_DIR / "seed003_frequencies.yaml").read_text().replace("  fidelity: linearised\n", "")
    study = ddgsa.study.spec.load_study(write_study("nofid", text=text))
    assert study.spec.model.fidelity == "linearised"
    quick = ddgsa.study.spec.load_study(SEED003_DIR / "quickstart.yaml")
    assert quick.spec.model.fidelity == "rigid"


def test_validate_a_sweep_counts_its_runs_and_claims_no_support(write_study, capsys) -> None:
    """A sweep has no parameter support to check (no distributions): validate does not claim "1 points of
    the parameters' support"; it says its runs, 3 grid points x 2 scenes x 2 realisations = 12 (newcomer trial)."""
    path = write_study("sw", text="name: sw\nkind: sweep\nmodel: {name: analytic}\ngrid: {x1: [0.0, 1.0, 2.0]}\n"
                                  "scenes: {wind_speed: [8, 11], realisations: 2}\n")
    assert main(["validate", str(path)]) == 0
    got = capsys.readouterr()
    assert "support" not in got.out and "checked: the sampling of every scene, parameters without effect" in got.out
    assert "evaluations: 3 grid points x 2 scenes x 2 realisations = 12 model runs" in got.err
