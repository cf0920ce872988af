"""Faults while a study runs (issue 29): a vanished store or lock, a corrupt store, a full disk.

Each case runs ``ddgsa run`` in a subprocess on the analytic model, does to its folder what a
user or the machine might (delete the store, the folder or the lock mid-run; corrupt the
store; limit the file size as a full disk does) and checks the exit code, that one line says
what happened, what is kept and how to resume, and that no traceback is printed.
"""

from __future__ import annotations

import os
import resource
import shutil
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest

from ddgsa.cli import main
from running import pages_committed
from studytext import SALTELLI, analytic_study

SRC = str(Path(__file__).resolve().parents[2] / "src")


def _env() -> dict[str, str]:
    return {**os.environ, "PYTHONPATH": SRC + os.pathsep + os.environ.get("PYTHONPATH", "")}


def _stored(store: Path) -> int:
    """Rows in ``store`` once its run has ended (0 while it does not exist or is held by a run: the
    store is opened in SQLite's exclusive mode, so no other process reads it meanwhile)."""
    try:
        with sqlite3.connect(f"file:{store}?mode=ro", uri=True, timeout=0.1) as db:
            return int(db.execute("SELECT COUNT(*) FROM evaluations").fetchone()[0])
    except sqlite3.Error:
        return 0


def _start(study: Path, out: Path, *extra: str, preexec=None) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "ddgsa.cli", "run", str(study), "--out", str(out), "-q", *extra],
                            env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=preexec)


def _wait_for_rows(proc: subprocess.Popen, store: Path, rows: int = 16, timeout: float = 120.0) -> None:
    """Wait until the running ``proc`` has committed at least ``rows`` evaluations, judged from its
    write-ahead log (:mod:`running`): ``rows`` pages, and a commit of 8 rows writes at most 6."""
    t0 = time.monotonic()
    while pages_committed(store) < rows:
        assert proc.poll() is None, f"the run ended before storing {rows} rows: {proc.communicate()}"
        assert time.monotonic() - t0 < timeout, "the run stored nothing"
        time.sleep(0.05)


@pytest.mark.parametrize("what", ["store", "folder", "lock"])
def test_a_store_or_lock_deleted_mid_run_stops_the_run_and_says_what_is_lost(tmp_path: Path, what: str) -> None:
    """Before: exit 0, "wrote 12 files", no store (issue 29 failure 1). Now exit 1, one line
    naming the file and how many evaluations went with it (or are kept), no report written."""
    study = tmp_path / "slow.yaml"
    study.write_text(analytic_study("slow", "{delay_s: 0.002}", 256, jobs=1, methods=SALTELLI))   # 5120 runs, ~10 s
    out = tmp_path / "out"
    proc = _start(study, out)
    _wait_for_rows(proc, out / "evaluations.sqlite")
    if what == "store":
        (out / "evaluations.sqlite").unlink()
    elif what == "folder":
        shutil.rmtree(out)
    else:
        (out / ".ddgsa.lock").unlink()
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 1, (stdout, stderr)
    assert "Traceback" not in stderr and "wrote" not in stdout
    assert len(stderr.strip().splitlines()) == 1, stderr
    assert not (out / "summary.md").exists()                   # no report from a store that is gone
    if what == "lock":
        assert ".ddgsa.lock: deleted or replaced" in stderr and "are kept in" in stderr
        n_kept = int(stderr.split("Its ")[1].split(" evaluations")[0])
        assert n_kept == _stored(out / "evaluations.sqlite") > 0
    else:
        assert "evaluations.sqlite: the evaluation store was deleted or replaced" in stderr
        lost = int(stderr.split("its ")[1].split(" evaluations")[0])
        assert 16 <= lost < 5120                               # what the vanished file held, counted
        assert f"({lost} of them from this run)" in stderr


def _write_finished_run(tmp_path: Path, write_study) -> tuple[Path, Path]:
    study = write_study("demo", n=16)
    out = tmp_path / "out"
    assert main(["run", str(study), "--out", str(out), "-q", "--allow-untrusted"]) == 0
    return study, out


def test_a_corrupt_store_is_named_and_force_rebuilds_it_beside_a_kept_copy(tmp_path: Path, write_study,
                                                                          capsys) -> None:
    """Before: "database disk image is malformed", no file, no way out (issue 29 failure 4)."""
    study, out = _write_finished_run(tmp_path, write_study)
    indices = pd.read_csv(out / "indices.csv")
    store = out / "evaluations.sqlite"
    blob = bytearray(store.read_bytes())
    blob[100:4096] = b"\xa5" * (4096 - 100)                   # the header's tail and the schema page
    store.write_bytes(bytes(blob))
    capsys.readouterr()
    assert main(["run", str(study), "--out", str(out), "-q", "--allow-untrusted"]) == 2
    err = capsys.readouterr().err
    assert f"{store}: the evaluation store is corrupt" in err and "--force" in err and ".corrupt" in err
    assert main(["report", str(out)]) == 2                     # report names it too
    assert f"{store}: the evaluation store is corrupt" in capsys.readouterr().err
    assert main(["run", str(study), "--out", str(out), "-q", "--allow-untrusted", "--force"]) == 0
    assert "kept as" in capsys.readouterr().err
    assert (out / "evaluations.sqlite.corrupt").read_bytes() == bytes(blob)   # the damaged copy, untouched
    rebuilt = pd.read_csv(out / "indices.csv")
    pd.testing.assert_frame_equal(rebuilt, indices)           # evaluated again: the same indices


def _limit_file_size(limit: int):
    def preexec() -> None:
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)          # writes past the limit fail like a full disk
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
    return preexec


def test_a_full_disk_stops_with_one_line_and_the_rerun_completes_identically(tmp_path: Path) -> None:
    """Before: the forked pool's cleanup printed a traceback (issue 29 failure 4). Now one line
    saying what is kept and how to resume; the rerun finishes with the indices of a clean run."""
    study = tmp_path / "full.yaml"
    study.write_text(analytic_study("full", "{delay_s: 0.0}", 128, jobs=2, methods=SALTELLI))   # 2560 runs, ~0.8 MB store
    out = tmp_path / "out"
    proc = _start(study, out, preexec=_limit_file_size(150_000))
    stdout, stderr = proc.communicate(timeout=300)
    assert proc.returncode == 1, (stdout, stderr)
    assert "Traceback" not in stderr and len(stderr.strip().splitlines()) == 1, stderr
    kept = _stored(out / "evaluations.sqlite")
    assert f"the {kept} evaluations committed before are kept" in stderr and "rerun the same command" in stderr
    assert 0 < kept < 2560
    assert main(["run", str(study), "--out", str(out), "-q", "--allow-untrusted"]) == 0
    clean = tmp_path / "clean"
    assert main(["run", str(study), "--out", str(clean), "-q", "--allow-untrusted"]) == 0
    pd.testing.assert_frame_equal(pd.read_csv(out / "indices.csv"), pd.read_csv(clean / "indices.csv"))


def test_an_output_folder_that_cannot_be_written_is_one_line_saying_what_is_kept(tmp_path: Path, write_study,
                                                                                  capsys) -> None:
    """A folder that cannot be created (here: under a file; a read-only folder fails the same way
    for a non-root user) is exit 1 with one line: the file, the cause, what is kept, how to resume."""
    study = write_study("demo", n=16)
    (tmp_path / "plain").write_text("a file, not a folder")
    out = tmp_path / "plain" / "out"
    assert main(["run", str(study), "--out", str(out), "-q"]) == 1
    err = capsys.readouterr().err
    assert err.startswith("ddgsa: error: cannot write the run's files: ") and "Traceback" not in err
    assert "no evaluation store is kept" in err and "rerun the same command to resume" in err
    assert len(err.strip().splitlines()) == 1


@pytest.mark.slow
def test_a_lost_dask_scheduler_stops_the_run_with_one_line_and_the_batches_are_kept(tmp_path: Path) -> None:
    """Before: a run whose scheduler was killed waited with no output (over 4 minutes by hand).
    Now exit 1 after ``SCHEDULER_GRACE_S`` with one line: what happened, what is kept, how to resume."""
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    scheduler = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--port", str(port), "--no-dashboard"],
                                 env=_env(), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    worker = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", f"tcp://127.0.0.1:{port}", "--nthreads", "1",
                               "--no-dashboard"], env=_env(), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        study = tmp_path / "dask.yaml"
        study.write_text(analytic_study("dask", "{delay_s: 0.02}", 256, jobs=1, methods=SALTELLI))     # 5120 runs, ~100 s
        out = tmp_path / "out"
        proc = _start(study, out, "--backend", "dask", "--address", f"127.0.0.1:{port}")
        _wait_for_rows(proc, out / "evaluations.sqlite", rows=64, timeout=240)
        scheduler.kill()
        stdout, stderr = proc.communicate(timeout=240)
    finally:
        for p in (scheduler, worker):
            p.kill()
            p.wait()
    assert proc.returncode == 1, (stdout, stderr)
    assert "Traceback" not in stderr and len(stderr.strip().splitlines()) == 1, stderr
    kept = _stored(out / "evaluations.sqlite")
    assert f"lost the Dask scheduler at 127.0.0.1:{port}" in stderr
    assert f"the {kept} evaluations committed before are kept" in stderr and 64 <= kept < 5120
