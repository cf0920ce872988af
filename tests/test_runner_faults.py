"""The runner under hostile evaluators and storage (issue 49): no silent loss, no SIGBUS, timeouts.

Each test here failed on the code before issue 49: an evaluator returning 6 rows for 8 points
was reported as 8 evaluated, 0 failed, with 6 stored; the store's '-shm' index was memory-mapped,
so storage made immutable mid-run ended the process with SIGBUS; a hung evaluation waited for ever.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ddgsa import runner
from ddgsa.runner import EvaluationStore, ModelId, Outcome, Task, TimedCalls, run_tasks, task_key

posix_fork = pytest.mark.skipif(not hasattr(os, "fork"), reason="timeouts fork a child process (POSIX)")
MID = ModelId("hostile", "exact")
_BEHAVIOUR: dict[str, Any] = {"shape": "ok"}
"""What :func:`hostile` returns (set by each test; inherited by forked children)."""


def _tasks(n: int, gain: float = 2.0) -> list[Task]:
    return [Task(task_key(MID, {"gain": gain}, {"x": float(x)}, "test"), MID, {"gain": gain}, {"x": float(x)})
            for x in range(n)]


def hostile(model: ModelId) -> Any:
    """A factory whose evaluator returns ``y = gain x`` in the shape :data:`_BEHAVIOUR` names."""

    def evaluate(points: pd.DataFrame, scene: dict[str, float]) -> Any:
        y = points["x"].to_numpy(dtype=float) * scene["gain"]
        n = len(points)
        good = pd.DataFrame({"y": y})
        shape = _BEHAVIOUR["shape"]
        if shape == "hang" and 3.0 in set(points["x"]):
            time.sleep(600)
        if shape == "die" and 3.0 in set(points["x"]):
            os._exit(3)
        return {
            "ok": good, "hang": good, "die": good,
            "fewer": good.iloc[: max(n - 2, 0)], "more": pd.concat([good, good.iloc[:1]]),
            "array": y, "list": y.tolist(), "none": None, "scalar": 1.0,
            "text": pd.DataFrame({"y": ["a"] * n}), "repeated": pd.DataFrame([[v, v] for v in y], columns=["y", "y"]),
            "transposed": good.T if n != 1 else good.T.iloc[:, :0],
            "bad_failure_row": good.assign().pipe(lambda f: (f.attrs.update(failures={n + 5: "x"}), f)[1]),
            "short_signal": good.pipe(lambda f: (f.attrs.update(signals={"s": np.ones((max(n - 1, 0), 3))}), f)[1]),
            "nan_first": good.assign(y=np.r_[np.nan, y[1:]]),
        }[shape]

    return evaluate


MALFORMED = ["fewer", "more", "array", "list", "none", "scalar", "text", "repeated", "transposed",
             "bad_failure_row", "short_signal"]


def _run(shape: str, n: int, batch: int, folder: Path, **kw: Any) -> tuple[dict[str, int], dict[str, Outcome]]:
    _BEHAVIOUR["shape"] = shape
    runner._evaluator.cache_clear()
    tasks = _tasks(n)
    store = EvaluationStore(folder / f"{shape}.sqlite")
    try:
        stats = run_tasks(tasks, store, hostile, batch_size=batch, quiet=True, **kw)
        return stats, store.get(t.key for t in tasks)
    finally:
        store.close()


def test_an_evaluator_returning_fewer_rows_fails_its_batch_loudly(tmp_path: Path) -> None:
    """Before: ``{'evaluated': 8, 'failed': 0}`` and 6 rows stored, 2 points lost without a word."""
    stats, got = _run("fewer", 8, 8, tmp_path)
    assert stats["evaluated"] == 8 and stats["failed"] == 8
    assert len(got) == 8 and all(o.outputs is None for o in got.values())
    assert all("returned 6 rows for 8 points" in o.error for o in got.values())


@settings(max_examples=60, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(shape=st.sampled_from(["ok", "nan_first", *MALFORMED]), n=st.integers(1, 9), batch=st.integers(1, 5))
def test_any_return_shape_stores_every_point_once_and_never_a_wrong_value(shape: str, n: int, batch: int) -> None:
    """Property over evaluator return shapes: every point is stored exactly once; a stored value is
    the point's own (``y = 2 x``, exactly); a malformed return fails every point of its batch with
    the reason; the run's counts match the store."""
    with tempfile.TemporaryDirectory() as tmp:
        stats, got = _run(shape, n, batch, Path(tmp))
    assert stats["evaluated"] == n and len(got) == n
    assert stats["failed"] == sum(o.outputs is None for o in got.values())
    for task in _tasks(n):
        o = got[task.key]
        if o.outputs is not None:
            assert o.outputs == {"y": 2.0 * task.point["x"]} and o.error is None
        else:
            assert isinstance(o.error, str) and o.error
    if shape in MALFORMED:
        assert stats["failed"] == n
    elif shape == "ok":
        assert stats["failed"] == 0
    else:                                                   # nan_first: the first point of each batch
        assert stats["failed"] == len(range(0, n, batch))


def unbuildable(model: ModelId) -> Any:
    raise ValueError("no such configuration")


@pytest.mark.parametrize("timeout", [None, 30.0])
def test_a_model_that_cannot_be_built_fails_its_points_not_the_run(tmp_path: Path, timeout: float | None) -> None:
    store = EvaluationStore(tmp_path / "s.sqlite")
    stats = run_tasks(_tasks(3), store, unbuildable, quiet=True, timeout=timeout)
    assert stats["failed"] == 3
    assert {o.error for o in store.get(t.key for t in _tasks(3)).values()} == {"ValueError: no such configuration"}
    store.close()


def test_a_batch_with_fewer_outcomes_than_points_is_never_stored(tmp_path: Path) -> None:
    """The store refuses a batch whose outcomes do not pair with its tasks (``zip(strict=True)``)."""
    store = EvaluationStore(tmp_path / "s.sqlite")
    with pytest.raises(ValueError):
        store.put(_tasks(3), [Outcome({"y": 0.0}, None, 0.0)] * 2)
    assert store.count() == 0
    store.close()


def _store_mappings(folder: Path) -> list[str]:
    return [line for line in Path("/proc/self/maps").read_text().splitlines() if str(folder) in line]


@pytest.mark.skipif(not Path("/proc/self/maps").exists(), reason="reads /proc/self/maps (Linux)")
def test_no_file_of_the_store_is_memory_mapped(tmp_path: Path) -> None:
    """Before: SQLite mapped ``evaluations.sqlite-shm`` (its WAL index); a fault on a mapped file is
    SIGBUS, which no handler can turn into a message."""
    store = EvaluationStore(tmp_path / "evaluations.sqlite")
    store.put(_tasks(4), [Outcome({"y": 1.0}, None, 0.0)] * 4)
    assert store.get(t.key for t in _tasks(4))
    assert _store_mappings(tmp_path) == []
    assert not (tmp_path / "evaluations.sqlite-shm").exists()
    store.close()


IMMUTABLE_SCRIPT = textwrap.dedent("""
    import subprocess, sys
    from pathlib import Path
    from ddgsa.runner import EvaluationStore, ModelId, Outcome, Task
    folder = Path(sys.argv[1])
    store = EvaluationStore(folder / "evaluations.sqlite")
    mid = ModelId("m", "f")
    def batch(k):
        return ([Task(f"k{k}-{i}", mid, {}, {"x": float(i)}) for i in range(4)],
                [Outcome({"y": float(i)}, None, 0.0) for i in range(4)])
    store.put(*batch(0))
    files = sorted(str(p) for p in folder.iterdir())
    subprocess.run(["chattr", "+i", *files], check=True)
    try:
        for k in range(1, 20):
            store.put(*batch(k))
    finally:
        subprocess.run(["chattr", "-i", *files], check=True)
""")


@pytest.mark.skipif(shutil.which("chattr") is None or os.geteuid() != 0, reason="needs chattr and root")
def test_storage_made_immutable_mid_run_is_one_line_and_keeps_the_stored_batches(tmp_path: Path) -> None:
    """Before: the process ended with SIGBUS (exit -7) and no message. Now one error naming the
    store and the cause; the batch committed before is kept and the store opens again (resume)."""
    folder = tmp_path / "out"
    folder.mkdir()
    if subprocess.run(["chattr", "+i", str(folder)], capture_output=True).returncode != 0:
        pytest.skip("the file system has no immutable attribute")
    subprocess.run(["chattr", "-i", str(folder)], check=True)
    script = tmp_path / "immutable.py"
    script.write_text(IMMUTABLE_SCRIPT)
    src = str(Path(__file__).resolve().parents[1] / "src")
    proc = subprocess.run([sys.executable, str(script), str(folder)], capture_output=True, text=True, timeout=120,
                          env={**os.environ, "PYTHONPATH": src})
    assert proc.returncode == 1, (proc.returncode, proc.stderr[-2000:])
    last = proc.stderr.strip().splitlines()[-1]
    assert last.startswith("ddgsa.errors.StoreWriteError: ") and f"{folder / 'evaluations.sqlite'}: cannot write" in last
    assert "the 4 evaluations committed before are kept" in last
    store = EvaluationStore(folder / "evaluations.sqlite")
    assert store.count() == 4
    store.close()


@posix_fork
def test_a_hung_evaluation_is_stopped_and_stored_as_failed_with_its_reason(tmp_path: Path) -> None:
    """Before: the run waited for ever. Point x = 3 sleeps 600 s; with ``timeout=1`` it is failed,
    "timed out after 1 s", and every other point holds its exact value (in-process and 2 workers)."""
    for jobs in (1, 2):
        folder = tmp_path / str(jobs)
        folder.mkdir()
        t0 = time.monotonic()
        stats, got = _run("hang", 8, 4, folder, timeout=1.0, jobs=jobs)
        assert time.monotonic() - t0 < 60
        assert stats["evaluated"] == 8 and stats["failed"] == 1
        for task in _tasks(8):
            o = got[task.key]
            if task.point["x"] == 3.0:
                assert o.outputs is None and o.error == "timed out after 1 s (the evaluation was stopped)"
            else:
                assert o.outputs == {"y": 2.0 * task.point["x"]}
    assert runner._TIMED == {}                            # the in-process child was stopped with the run


@posix_fork
def test_a_timed_evaluation_whose_process_dies_is_failed_with_how(tmp_path: Path) -> None:
    stats, got = _run("die", 6, 3, tmp_path, timeout=30.0)
    assert stats["failed"] == 1
    dead = [o.error for o in got.values() if o.outputs is None]
    assert dead == ["the evaluation's process died (exit status 3)"]


@posix_fork
def test_timed_calls_keep_the_childs_state_and_restart_after_a_timeout() -> None:
    """The child keeps what the function built between calls (a counter), and a fresh child after
    a timeout starts from the parent's state again."""
    state = {"n": 0}

    def count(sleep: float) -> int:
        state["n"] += 1
        time.sleep(sleep)
        return state["n"]

    calls = TimedCalls(count, 0.5)
    try:
        assert [calls(0.0), calls(0.0), calls(0.0)] == [1, 2, 3]
        with pytest.raises(runner.EvaluationTimeout, match="timed out after 0.5 s"):
            calls(5.0)
        assert calls(0.0) == 1
        failing = TimedCalls(lambda: 1 / 0, 5.0)
        with pytest.raises(runner.EvaluationFailed, match="^ZeroDivisionError: division by zero$"):
            failing()
        failing.close()
    finally:
        calls.close()
    assert state["n"] == 0                                # the parent never ran it
