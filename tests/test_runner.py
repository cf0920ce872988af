"""The runner's local workers: forked from the caller on Linux, gone with it, same results as in-process."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pandas as pd
import pytest

from ddgsa import runner
from ddgsa.runner import EvaluationStore, ModelId, Task, run_tasks, task_key

linux_only = pytest.mark.skipif(not runner.FORK_WORKERS, reason="workers are forked on Linux only")


def pid_and_state(model: ModelId) -> object:
    """A factory whose outputs are the worker's process id and a module-level value it inherited."""

    def evaluate(points: pd.DataFrame, scene: dict[str, float]) -> pd.DataFrame:
        return pd.DataFrame({"pid": float(os.getpid()), "inherited": float(_STATE["value"]),
                             "y": points["x"] * scene["gain"]})

    return evaluate


_STATE = {"value": 0.0}


@linux_only
def test_forked_workers_inherit_the_callers_state_and_match_in_process_results(tmp_path: Path) -> None:
    """Two forked workers see a value set in the caller after import (a spawned worker would re-import
    the module and see 0), run in processes other than the caller, and give the in-process outputs."""
    _STATE["value"] = 7.0
    mid = ModelId("pid", "exact")
    tasks = [Task(task_key(mid, {"gain": 3.0}, {"x": x}, "test"), mid, {"gain": 3.0}, {"x": x}) for x in range(8)]
    outputs = {}
    for jobs in (1, 2):
        store = EvaluationStore(tmp_path / f"s{jobs}.sqlite")
        assert run_tasks(tasks, store, pid_and_state, jobs=jobs, batch_size=2, quiet=True)["failed"] == 0
        outputs[jobs] = [store.get([t.key])[t.key].outputs for t in tasks]
        store.close()
    assert {o["pid"] for o in outputs[1]} == {float(os.getpid())}
    assert float(os.getpid()) not in {o["pid"] for o in outputs[2]}
    assert all(o["inherited"] == 7.0 for o in outputs[2])
    assert [o["y"] for o in outputs[2]] == [o["y"] for o in outputs[1]] == [3.0 * x for x in range(8)]


@linux_only
def test_forked_workers_die_with_a_killed_parent(tmp_path: Path) -> None:
    """SIGKILL of the study's process leaves no worker behind (``PR_SET_PDEATHSIG``); within 5 s."""
    psutil = pytest.importorskip("psutil")
    script = tmp_path / "parent.py"
    script.write_text(textwrap.dedent(f"""
        from pathlib import Path
        from ddgsa.execute.kinds.common import make_task, model_evaluator
        from ddgsa.runner import EvaluationStore, ModelId, run_tasks
        from ddgsa.loads.scene import Scene
        mid = ModelId("analytic", "exact", (("delay_s", 0.5),))
        scene = Scene(wind_speed=8.0, turbulence_intensity=0.0, duration=10.0)
        tasks = [make_task(mid, scene, {{"x1": 0.01 * i}}) for i in range(400)]
        run_tasks(tasks, EvaluationStore(Path({str(tmp_path / 'e.sqlite')!r})), model_evaluator, jobs=2,
                  batch_size=1, quiet=True)
    """))
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(Path(runner.__file__).parents[1]),
                                                        os.environ.get("PYTHONPATH", "")])}
    proc = subprocess.Popen([sys.executable, str(script)], env=env)
    parent = psutil.Process(proc.pid)
    deadline = time.time() + 60
    workers: list = []
    while time.time() < deadline and len(workers) < 2:
        workers = [c for c in parent.children() if "resource_tracker" not in " ".join(c.cmdline())]
        time.sleep(0.1)
    assert len(workers) >= 2, "the workers did not start"
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    gone, alive = psutil.wait_procs(workers, timeout=5)
    assert not alive, f"workers outlived their parent: {[p.pid for p in alive]}"


@linux_only
def test_a_local_workers_block_keeps_its_workers_across_calls(tmp_path: Path) -> None:
    """Inside ``local_workers()`` the second call runs on the first call's workers (no new fork);
    outside, each call forks its own."""
    mid = ModelId("pid", "exact")

    def pids(tag: str) -> set[float]:
        tasks = [Task(task_key(mid, {"gain": 1.0}, {"x": x}, tag), mid, {"gain": 1.0}, {"x": x}) for x in range(6)]
        store = EvaluationStore(tmp_path / f"{tag}.sqlite")
        run_tasks(tasks, store, pid_and_state, jobs=2, batch_size=1, quiet=True)
        got = {store.get([t.key])[t.key].outputs["pid"] for t in tasks}
        store.close()
        return got

    with runner.local_workers():
        first, second = pids("a"), pids("b")
    assert len(first | second) <= 2                   # two workers served both calls
    assert not pids("c") & pids("d")


def test_the_progress_bar_counts_a_quiet_warm_up_run_among_its_runs(tmp_path: Path, capsys) -> None:
    """Newcomer trial: the pipeline runs one evaluation quietly (kernel warm-up) and the bar of the
    remaining 84 then read 84/84 for a study of 85 runs. Here 6 tasks: one stored before with a bar of its
    own (shown, so cached), one run by a quiet call; the bar over all six then ends at 5/5."""
    mid = ModelId("pid", "exact")
    tasks = [Task(task_key(mid, {"gain": 1.0}, {"x": x}, "test"), mid, {"gain": 1.0}, {"x": x}) for x in range(6)]
    store = EvaluationStore(tmp_path / "s.sqlite")
    run_tasks(tasks[5:], store, pid_and_state, quiet=False)
    assert "1/1" in capsys.readouterr().err
    run_tasks(tasks[:1], store, pid_and_state, quiet=True)
    assert capsys.readouterr().err == ""
    got = run_tasks(tasks, store, pid_and_state, quiet=False)
    assert got == {"total": 6, "cached": 2, "evaluated": 4, "failed": 0}
    err = capsys.readouterr().err
    assert "5/5" in err and "4/4" not in err and "6/6" not in err
    again = run_tasks(tasks, store, pid_and_state, quiet=False)   # nothing left to run: no bar
    assert again["evaluated"] == 0 and capsys.readouterr().err == ""
    store.close()


_BROKEN = {"below": 3.0}


def breaks_below(model: ModelId) -> object:
    """A factory that fails for ``x`` below a module-level threshold (a model bug, later fixed)."""

    def evaluate(points: pd.DataFrame, scene: dict[str, float]) -> pd.DataFrame:
        if (points["x"] < _BROKEN["below"]).any():
            raise RuntimeError("the model's bug")
        return pd.DataFrame({"y": 2.0 * points["x"]})

    return evaluate


def test_stored_failures_run_again_only_when_forgotten(tmp_path: Path) -> None:
    """A failure is stored with its reason and not rerun; ``forget_failed`` (``ddgsa run --retry-failed``)
    deletes exactly the stored failures among the keys asked, which then run again, and leaves the rest."""
    mid = ModelId("breaks", "exact")
    tasks = [Task(task_key(mid, {}, {"x": x}, "test"), mid, {}, {"x": float(x)}) for x in range(6)]
    store = EvaluationStore(tmp_path / "s.sqlite")
    _BROKEN["below"] = 3.0
    assert run_tasks(tasks, store, breaks_below, jobs=1, batch_size=1, quiet=True)["failed"] == 3
    _BROKEN["below"] = -1.0                                  # the bug is fixed
    assert run_tasks(tasks, store, breaks_below, jobs=1, batch_size=1, quiet=True)["evaluated"] == 0
    assert store.get([tasks[0].key])[tasks[0].key].error is not None
    assert store.forget_failed(t.key for t in tasks[1:]) == 2           # x = 1, 2 (x = 0 not asked)
    got = run_tasks(tasks, store, breaks_below, jobs=1, batch_size=1, quiet=True)
    assert got["evaluated"] == 2 and got["failed"] == 0
    out = store.get([t.key for t in tasks])
    assert [out[t.key].outputs for t in tasks[1:]] == [{"y": 2.0 * x} for x in range(1, 6)]
    assert out[tasks[0].key].outputs is None and "the model's bug" in out[tasks[0].key].error
    store.close()


def test_the_main_process_keeps_blas_to_one_thread_while_workers_run() -> None:
    """:func:`main_blas_threads`: one BLAS thread inside for ``jobs`` > 1, the previous count after; no
    change for one job (the study's main process shares the cores with its workers)."""
    from threadpoolctl import threadpool_info, threadpool_limits

    from ddgsa.runner import main_blas_threads

    def blas_threads() -> list[int]:
        return [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"]

    if not blas_threads():
        pytest.skip("no BLAS library loaded that threadpoolctl can see")
    with threadpool_limits(limits=2, user_api="blas"):
        before = blas_threads()
        with main_blas_threads(2):
            assert set(blas_threads()) == {1}
        assert blas_threads() == before
        with main_blas_threads(1):
            assert blas_threads() == before
