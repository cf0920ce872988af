"""Issue 49's failure classes at the study level: bounded and regular input files, ordered
collections only (the digest independent of the hash seed), a completion mark, timeouts in a
study, and messages that name the file. Each test failed on the code before issue 49."""

from __future__ import annotations

import json
import os
import sqlite3
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from ruamel.yaml import YAML

from bounded import measured_validate
from ddgsa.cli import main
from ddgsa.errors import StudyError
from ddgsa.study.spec import load_study, validate_study
from studytext import SALTELLI, analytic_study

SRC = str(Path(__file__).resolve().parents[2] / "src")
PEAK_BYTES = 64 << 20
"""Memory one refusal may take [B] (as the bad-input tests)."""


def _cli(*args: str, cwd: Path | None = None, env: dict[str, str] | None = None,
         timeout: float = 60.0) -> subprocess.CompletedProcess[str]:
    """``ddgsa ARGS`` in a new process (a FIFO or a deleted folder must not block or change this one)."""
    return subprocess.run([sys.executable, "-m", "ddgsa.cli", *args], capture_output=True, text=True, cwd=cwd,
                          timeout=timeout, env={**os.environ, "PYTHONPATH": SRC, **(env or {})})


def _with_parameters_file(tmp_path: Path, name: str) -> Path:
    study = tmp_path / "study.yaml"
    text = analytic_study("demo").split("parameters:\n")
    rest = text[1].split("scenes:", 1)[1]
    study.write_text(f"{text[0]}parameters: {name}\nscenes:{rest}")
    return study


# --- class 2: every file a study names is bounded --------------------------------------------------------

@pytest.mark.parametrize("name, size", [("params.txt", 2 << 20), ("params.txt", 2 << 30), ("params.json", 2 << 20)],
                         ids=["text_2MiB", "text_2GiB_sparse", "json_2MiB"])
def test_a_parameters_file_over_the_cap_is_exit_2_naming_both_files(tmp_path: Path, name: str, size: int) -> None:
    """Before: a text parameters file was read whole (2 GB: MemoryError, exit 1); now the study
    file's 1 MiB cap, in the study file's one-line form, within the bad-input memory bound."""
    study = _with_parameters_file(tmp_path, name)
    path = tmp_path / name
    if size > 1 << 28:
        with path.open("wb") as fh:                           # sparse: no disk used
            fh.truncate(size)
    else:
        line = b"x1,-3.14,3.14\n" if name.endswith(".txt") else b" " * 63 + b"\n"
        path.write_bytes(line * (size // len(line)))
    rc, err, peak, _ = measured_validate(study)
    assert rc == 2, err
    assert err.startswith(f"ddgsa: error: {study}: field 'parameters': {path}: a parameters file is at most 1 MiB")
    assert peak < PEAK_BYTES


# --- class 3: special files are refused from their stat, never opened for reading ------------------------

@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="FIFOs are POSIX")
@pytest.mark.parametrize("where", ["study", "parameters"])
def test_a_fifo_is_refused_at_once(tmp_path: Path, where: str) -> None:
    """Before: ``ddgsa validate`` on a FIFO waited for a writer for ever (here: the 60 s timeout)."""
    fifo = tmp_path / ("fifo.yaml" if where == "study" else "params.txt")
    os.mkfifo(fifo)
    target = fifo if where == "study" else _with_parameters_file(tmp_path, "params.txt")
    proc = _cli("validate", str(target))
    assert proc.returncode == 2, proc.stderr
    what = "study file" if where == "study" else "parameters file"
    assert f"{fifo}: the {what} is a FIFO (named pipe), not a regular file" in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1 and "Traceback" not in proc.stderr


@pytest.mark.parametrize("path, kind", [("/dev/zero", "a character device"), (".", "a folder")])
def test_devices_and_folders_are_refused_by_kind(tmp_path: Path, path: str, kind: str) -> None:
    target = tmp_path if path == "." else Path(path)
    rc, err, _, _ = measured_validate(target)
    assert rc == 2 and f"{target}: the study file is {kind}, not a regular file" in err


# --- class 4: no unordered collection; the digest does not depend on the hash seed -----------------------

@pytest.mark.parametrize("outputs", ["!!set {y: null, y_positive: null}", "!!set\n  ? y\n  ? y_positive"])
def test_a_yaml_set_is_refused_naming_the_field(tmp_path: Path, outputs: str) -> None:
    """Before: accepted, with the order of outputs (and the digest) set by ``PYTHONHASHSEED``."""
    study = tmp_path / "set.yaml"
    study.write_text(analytic_study("demo").replace("outputs: [y, y_positive]", f"outputs: {outputs}"))
    rc, err, _, _ = measured_validate(study)
    assert rc == 2 and f"{study}: field 'outputs': an unordered set" in err, err


VALID: dict[str, Any] = YAML(typ="safe", pure=True).load(analytic_study("fuzz"))


def _set_somewhere(data: dict[str, Any], where: str) -> dict[str, Any]:
    data = json.loads(json.dumps(data))
    if where == "outputs":
        data["outputs"] = set(data["outputs"])
    elif where == "wind_speed":
        data["scenes"]["wind_speed"] = frozenset(data["scenes"]["wind_speed"])
    else:
        data["methods"][0]["points"] = {5}
    return data


@settings(max_examples=15, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(where=st.sampled_from(["outputs", "wind_speed", "methods"]), order=st.permutations(list(VALID)))
def test_a_set_anywhere_is_refused_and_key_order_never_changes_the_digest(where: str, order: list[str]) -> None:
    """Property over study data given to the API: a set at any field is refused naming the field;
    the same study with its keys in any order has the same digest (canonical JSON)."""
    with pytest.raises(StudyError, match=r"^<study>: field '(outputs|scenes\.wind_speed|methods\[0\]\.points)': "
                                         "an unordered set"):
        validate_study(_set_somewhere(VALID, where))
    shuffled = {k: VALID[k] for k in order}
    assert validate_study(json.loads(json.dumps(shuffled))).digest == validate_study(json.loads(json.dumps(VALID))).digest


DIGEST_SCRIPT = textwrap.dedent("""
    import json, sys
    from ddgsa.study.spec import load_study
    out = []
    for path in sys.argv[1:]:
        s = load_study(path)
        out.append([s.digest, list(s.outputs), [p.name for p in s.space.parameters]])
    print(json.dumps(out))
""")


@pytest.mark.slow
@settings(max_examples=3, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow,
                                                                                   HealthCheck.function_scoped_fixture])
@given(studies=st.lists(st.tuples(st.permutations(["y", "y_positive"]), st.permutations(["x1", "x2", "x3"]),
                                  st.lists(st.sampled_from([6.0, 8.0, 11.0, 14.0]), min_size=1, max_size=3,
                                           unique=True)), min_size=8, max_size=8))
def test_digests_and_orders_are_equal_across_hash_seeds(tmp_path: Path, studies: list[Any]) -> None:
    """Property across processes: 8 studies (outputs, parameters and wind speeds in drawn orders)
    load to the same digest, outputs and parameter order under ``PYTHONHASHSEED`` 1, 2 and 3."""
    paths = []
    for i, (outputs, params, speeds) in enumerate(studies):
        data = json.loads(json.dumps(VALID))
        data["outputs"] = list(outputs)
        data["parameters"] = {p: data["parameters"][p] for p in params}
        data["scenes"]["wind_speed"] = list(speeds)
        path = tmp_path / f"s{i}.yaml"
        path.write_text(json.dumps(data))
        paths.append(str(path))
    script = tmp_path / "digest.py"
    script.write_text(DIGEST_SCRIPT)
    seen = []
    for seed in ("1", "2", "3"):
        proc = subprocess.run([sys.executable, str(script), *paths], capture_output=True, text=True, timeout=120,
                              env={**os.environ, "PYTHONPATH": SRC, "PYTHONHASHSEED": seed})
        assert proc.returncode == 0, proc.stderr
        seen.append(json.loads(proc.stdout))
    assert seen[0] == seen[1] == seen[2]
    assert [row[1] for row in seen[0]] == [list(o) for o, _, _ in studies]       # the order written, kept


# --- class 6: a completion mark, written last ---------------------------------------------------------------

def _finished(tmp_path: Path) -> tuple[Path, Path]:
    study = tmp_path / "demo.yaml"
    study.write_text(analytic_study("demo", n=8, methods=SALTELLI))        # 160 runs
    out = tmp_path / "out"
    assert main(["run", str(study), "--out", str(out), "-q", "--allow-untrusted"]) == 0
    return study, out


def test_a_report_killed_while_written_is_shown_incomplete(tmp_path: Path, monkeypatch, capsys) -> None:
    """Before: ``ddgsa html`` on a folder whose run was killed while writing its report rendered a
    complete-looking page. Now the page and the command say the outputs are incomplete."""
    study, out = _finished(tmp_path)
    assert json.loads((out / "complete.json").read_text())["complete"] is True
    assert main(["html", str(out), "-q"]) == 0
    assert "Incomplete outputs" not in (out / "report.html").read_text()

    import ddgsa.report.write as report

    def killed(*args: Any, **kwargs: Any) -> None:
        raise KeyboardInterrupt                                # the run killed while drawing its figures

    monkeypatch.setattr(report, "render_figures", killed)
    assert main(["report", str(out)]) == 130
    monkeypatch.undo()
    capsys.readouterr()
    assert main(["html", str(out), "-q"]) == 0
    assert "outputs incomplete: the run or report that wrote this folder did not finish" in capsys.readouterr().err
    assert "<b>Incomplete outputs:</b> the run or report that wrote this folder did not finish" in \
        (out / "report.html").read_text()
    assert main(["report", str(out), "--allow-untrusted"]) == 0          # finished again: complete
    assert "Incomplete outputs" not in (out / "report.html").read_text()


def test_a_file_changed_after_the_run_is_named(tmp_path: Path, capsys) -> None:
    _, out = _finished(tmp_path)
    (out / "indices.csv").write_text("output,parameter\n")
    capsys.readouterr()
    assert main(["html", str(out), "-q"]) == 0
    assert "indices.csv changed after the run wrote it" in capsys.readouterr().err


def test_a_folder_written_before_completion_marks_is_judged_by_its_file_list(tmp_path: Path, capsys) -> None:
    """Committed results folders have no mark: complete while every file their provenance lists
    is there, so their pages get no banner."""
    _, out = _finished(tmp_path)
    (out / "complete.json").unlink()
    assert main(["html", str(out), "-q"]) == 0
    assert "Incomplete outputs" not in (out / "report.html").read_text()
    (out / "indices.csv").unlink()
    capsys.readouterr()
    assert main(["html", str(out), "-q"]) == 0
    assert "indices.csv, written by the run, is missing" in capsys.readouterr().err


# --- class 7: a per-evaluation timeout in a study -----------------------------------------------------------

SWEEP = """\
name: slow_sweep
kind: sweep
model: {name: analytic, fidelity: exact, options: {delay_s: 30}}
scenes: {wind_speed: 8.0, turbulence_intensity: 0.0, duration: 1.0, dt: 0.05}
grid: {x1: [0.0, 1.0]}
outputs: [y]
run: {jobs: 1, timeout: 0.5}
"""


def test_a_study_timeout_stores_hung_evaluations_as_failed(tmp_path: Path) -> None:
    """Before: ``run.timeout`` was an unknown field, and a 30 s evaluation ran its 30 s. Now each
    evaluation stops at 0.5 s and is a failure with its reason in the provenance."""
    study = tmp_path / "slow.yaml"
    study.write_text(SWEEP)
    out = tmp_path / "out"
    proc = _cli("run", str(study), "--out", str(out), "-q", "--allow-untrusted", timeout=120)
    assert proc.returncode == 0, proc.stderr
    failures = json.loads((out / "provenance.json").read_text())["failures"]
    assert [f["error"] for f in failures] == ["timed out after 0.5 s (the evaluation was stopped)"] * 2
    assert load_study(study).spec.run.timeout == 0.5


def test_a_study_without_timeout_keeps_its_digest() -> None:
    """``run.timeout`` left out (the default) leaves the digest the code before it gave (computed
    there: b20256b6...); given, it changes it."""
    data = YAML(typ="safe", pure=True).load(SWEEP.replace(", timeout: 0.5", ""))
    assert validate_study(data).digest == "b20256b6daba0367b49f82298b6fa91a85b6fc4d97afc5c913e3a55390884662"
    assert validate_study(YAML(typ="safe", pure=True).load(SWEEP)).digest != validate_study(data).digest


# --- class 8: messages that name the file and the cause ----------------------------------------------------

def test_a_deleted_working_folder_is_named_not_a_bare_file_not_found(tmp_path: Path) -> None:
    """Before: ``ddgsa: failed: FileNotFoundError: [Errno 2] No such file or directory``."""
    study = tmp_path / "demo.yaml"
    study.write_text(analytic_study("demo", n=16))
    gone = tmp_path / "gone"
    gone.mkdir()
    script = f"import os, sys; os.chdir({str(gone)!r}); os.rmdir({str(gone)!r}); " \
             f"from ddgsa.cli import main; sys.exit(main(['run', {str(study)!r}, '-q']))"
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120,
                          env={**os.environ, "PYTHONPATH": SRC, "PWD": str(gone)})
    assert proc.returncode == 1
    assert proc.stderr == (f"ddgsa: error: {gone}: the working folder was deleted after this shell entered it, so "
                           "relative paths (and the default output folder runs/<study>) cannot be resolved; cd to an "
                           "existing folder and rerun\n")


def test_a_store_missing_evaluations_is_named_first(tmp_path: Path, capsys) -> None:
    """Before: exit 2 with "N evaluations of scene {...} are not in the store", the one input
    message that did not start with the file it is about."""
    _, out = _finished(tmp_path)
    db = sqlite3.connect(out / "evaluations.sqlite")
    with db:
        db.execute("DELETE FROM evaluations WHERE rowid % 2 = 0")
    db.close()
    capsys.readouterr()
    assert main(["report", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"ddgsa: error: {out / 'evaluations.sqlite'}: ") and "not in this evaluation store" in err
