"""The CLI as a newcomer meets it: exit codes, flag placement, Ctrl-C, typos, plurals, the API import."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

from ddgsa.cli import EXIT_INTERRUPTED, EXIT_UNTRUSTED, main
from ddgsa.report.outdir import claim
from ddgsa.runner import EvaluationStore
from running import pages_committed, schema_pages
from studytext import ishigami_study

SRC = str(Path(__file__).parents[2] / "src")


def trusted_study(name: str) -> str:
    """A one-scene Ishigami study whose order-10 PCE is trusted."""
    return ishigami_study(name, "methods: [{method: pce, order: 10, n: 1024, seed: 0}]\n", pi="3.14159")


def _env() -> dict[str, str]:
    return {**os.environ, "PYTHONPATH": SRC, "PYTHONUNBUFFERED": "1"}


def test_exit_codes_untrusted_and_allowed(write_study, tmp_path: Path, capsys) -> None:
    """Plain Ishigami with M-DRM and Saltelli n = 64 is trusted by no method: exit 3 naming the
    outputs, 0 with --allow-untrusted (a trusted study exits 0: test_report's PCE study)."""
    bad = write_study("bad")
    assert main(["run", str(bad), "--out", str(tmp_path / "bad")]) == EXIT_UNTRUSTED == 3
    err = capsys.readouterr().err
    assert "output 'y': no method's indices are confirmed (trusted or rank-confirmed) in scenes 0, 1" in err
    assert "--allow-untrusted" in err and "to confirm it add `saltelli` with n: " in err
    assert "## Problems" in (tmp_path / "bad" / "summary.md").read_text()
    assert main(["report", str(tmp_path / "bad"), "--allow-untrusted"]) == 0
    assert "ddgsa: warning: output 'y'" in capsys.readouterr().err
    assert main(["report", str(tmp_path / "bad")]) == 3                 # a rebuilt report says the same


def test_quiet_and_verbose_before_or_after_the_subcommand(write_study, tmp_path: Path, capsys) -> None:
    study = write_study("ok", text=trusted_study(name="ok"))
    assert main(["run", str(study), "--out", str(tmp_path / "a"), "-q"]) == 0
    assert capsys.readouterr().out == ""
    assert main(["-q", "run", str(study), "--out", str(tmp_path / "a")]) == 0
    assert capsys.readouterr().out == ""
    assert main(["validate", str(study), "-v"]) == 0
    assert main(["models", "-q"]) == 0


def test_validate_says_one_scene_one_realisation(write_study, capsys) -> None:
    assert main(["validate", str(write_study("ok", text=trusted_study(name="ok")))]) == 0
    assert "3 parameters, 1 scene x 1 realisation)" in capsys.readouterr().out


def test_parameter_typo_suggests_the_name_instead_of_listing_all(write_study, capsys) -> None:
    text = """\
name: typo
model: {name: direct_drive, fidelity: rigid}
parameters:
  k_fornt_y: {nominal: 3e9, spread: 0.3}
methods: [{method: mdrm}]
"""
    assert main(["validate", str(write_study("typo", text=text))]) == 2
    err = capsys.readouterr().err
    assert "field 'parameters.k_fornt_y': not a parameter of model 'direct_drive'" in err
    assert "did you mean 'k_front_y' or" in err and "`ddgsa models` lists all" in err
    assert "shaft_mass" not in err                                      # not the whole list of 31


def test_models_shows_output_units_and_meanings(capsys) -> None:
    assert main(["models"]) == 0
    text = capsys.readouterr().out
    assert "rms_deflection_hub" in text and "damage_front" in text
    line = next(ln for ln in text.splitlines() if ln.strip().startswith("damage_front"))
    assert "1/s" in line and "L10 rating life used per second" in line


def test_import_ddgsa_then_models_get_in_a_fresh_interpreter() -> None:
    code = "import ddgsa; m = ddgsa.models.get('analytic'); print(m.output('y').label)"
    run = subprocess.run([sys.executable, "-c", code], env=_env(), capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "y [-]"


def _start_slow_run(study: Path, out: Path) -> subprocess.Popen[bytes]:
    # the child starts with SIGINT at its default, as from a terminal: an earlier test (a Dask or loky
    # pool) can leave the test process ignoring SIGINT, and an ignored SIGINT is inherited
    proc = subprocess.Popen([sys.executable, "-m", "ddgsa.cli", "-q", "run", str(study), "--out", str(out),
                             "--allow-untrusted"], env=_env(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    store = out / "evaluations.sqlite"
    deadline = time.time() + 90
    while not store.exists() and time.time() < deadline:          # the store exists once the lock is held
        time.sleep(0.1)
    assert store.exists() and proc.poll() is None
    return proc


def test_a_second_live_run_is_refused_and_ctrl_c_exits_130(write_study, tmp_path: Path, capsys) -> None:
    """A slow run (10 ms a point, ~15 s) holds its folder: a second run into it exits 1 with a
    message naming the holder; SIGINT (Ctrl-C) ends the first with 130, its finished batches
    stored, and the folder is free again."""
    study = write_study("slow", options="{delay_s: 0.01}", n=64, batch=4)
    out = tmp_path / "shared"
    proc = _start_slow_run(study, out)
    try:
        assert main(["-q", "run", str(study), "--out", str(out)]) == 1
        err = capsys.readouterr().err
        assert f"another ddgsa run (pid {proc.pid}) is writing to this folder" in err
        deadline = time.time() + 60
        schema = schema_pages()                 # the store's tables are in the log before any batch
        while pages_committed(out / "evaluations.sqlite") <= schema and time.time() < deadline:
            time.sleep(0.1)
        proc.send_signal(signal.SIGINT)
        assert proc.wait(timeout=60) == EXIT_INTERRUPTED == 130
        assert b"interrupted; finished batches are stored" in proc.stderr.read()  # type: ignore[union-attr]
    finally:
        if proc.poll() is None:
            proc.kill()
    store = EvaluationStore(out / "evaluations.sqlite")
    assert store.count() > 0
    store.close()
    with claim(out, "slow"):                                            # released by the interrupted run
        pass


def test_validate_warns_when_the_nominal_point_is_outside_the_valid_region(write_study, capsys) -> None:
    """Front bearing fixed at 6 m behind the rear one at 5 m: valid fields, an impossible shaft; every
    point of the support is outside too, so the study is refused (ddgsa.study.checks)."""
    text = """\
name: crossed
model: {name: direct_drive, fidelity: rigid}
parameters:
  k_front_y: {nominal: 3e9, spread: 0.3}
fixed: {front_bearing_x: 6.0}
methods: [{method: mdrm}]
"""
    assert main(["validate", str(write_study("crossed", text=text))]) == 2
    err = capsys.readouterr().err
    assert "ddgsa: warning: " in err and "nominal point is outside model 'direct_drive'" in err
    assert "66 of 66 checked points" in err and "every evaluation would fail" in err
    assert "0 < front_bearing_x (6) < rear_bearing_x (5) < shaft_length" in err
    assert main(["validate", str(write_study("fine", text=text.replace("fixed: {front_bearing_x: 6.0}\n", "")))]) == 0
    assert "warning" not in capsys.readouterr().err


def test_a_slow_first_evaluation_is_explained(write_study, tmp_path: Path, monkeypatch, capsys) -> None:
    """The first evaluation runs alone; past SLOW_FIRST_S (here 0.05 s; a 0.2 s point) the user
    reads that kernels are compiling (first run only) and then how long it took; -q silences it."""
    import ddgsa.runner

    monkeypatch.setattr(ddgsa.runner, "SLOW_FIRST_S", 0.05)
    text = trusted_study(name="slow").replace("fidelity: exact}", "fidelity: exact, options: {delay_s: 0.2}}")
    text = text.replace("order: 10, n: 1024", "order: 1, n: 4")
    study = write_study("slow", text=text)
    main(["run", str(study), "--out", str(tmp_path / "a"), "--allow-untrusted"])
    err = capsys.readouterr().err
    assert "analytic (exact): first evaluation, compiling the model's kernels (a first run after installing" in err
    assert "analytic (exact): kernels ready after" in err
    main(["run", str(study), "--out", str(tmp_path / "b"), "--allow-untrusted", "-q"])
    assert "first evaluation" not in capsys.readouterr().err


def test_slow_model_checks_in_validate_are_explained(write_study, monkeypatch, capsys) -> None:
    """validate's model checks compile the model's kernels on a first use (about 2 min for the geared
    drive): past SLOW_FIRST_S the user reads what is happening; quick checks and -q print nothing."""
    import time

    import ddgsa.study.checks
    import ddgsa.runner

    study = write_study("ok", text=trusted_study(name="ok"))
    assert main(["validate", str(study)]) == 0 and "checking model" not in capsys.readouterr().err
    checks = ddgsa.study.checks.study_findings
    monkeypatch.setattr(ddgsa.runner, "SLOW_FIRST_S", 0.05)
    monkeypatch.setattr(ddgsa.study.checks, "study_findings", lambda s: (time.sleep(0.3), checks(s))[1])
    assert main(["validate", str(study)]) == 0
    assert "ddgsa: note: checking model 'analytic' (its modes and sampling; a first check" in capsys.readouterr().err
    assert main(["-q", "validate", str(study)]) == 0 and "checking model" not in capsys.readouterr().err
