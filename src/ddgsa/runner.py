"""Parallel, cached, resumable evaluation of ``model(points, scene)``.

The runner knows nothing of Sobol indices or turbines: it receives tasks (a key, a model
identity, an opaque scene dict, a full parameter dict) and a *model factory* (a picklable
callable turning a :class:`ModelId` into an evaluator ``f(points: DataFrame, scene: dict) ->
DataFrame``), skips the tasks already in the store, evaluates the rest in batches (one
evaluator call per batch of points of one scene) on joblib's loky backend or a Dask cluster,
and commits every finished batch to SQLite in one transaction, so a killed run loses at most
the batches in flight. A failed evaluation is stored with its reason. Evaluations are
deterministic (seeded scenes), so results do not depend on the number of workers, the
backend or the order batches finish in.

Local workers (``backend="loky"``, ``jobs > 1``): on Linux they are forked from the calling
process, once per :func:`local_workers` block (a study) or else per :func:`run_tasks` call, so
they start with its imported modules, loaded compiled kernels and warm caches (a spawned loky
worker spends ~1.5 s of CPU importing and loading them: a tenth of a paper-size study);
elsewhere they are joblib's loky workers. A forked worker dies with the thread that forked it
(``PR_SET_PDEATHSIG``: no orphans when a run is killed), ignores Ctrl-C (the parent stops it)
and runs BLAS on ``cpu_count // jobs`` threads, as loky's do.
"""

from __future__ import annotations

import ctypes
import hashlib
import json
import math
import multiprocessing
import os
import signal
import sqlite3
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator, Mapping
from concurrent.futures import Future, ProcessPoolExecutor, as_completed
from contextlib import closing, contextmanager, suppress
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

import joblib
import numpy as np
import pandas as pd
from numpy.typing import NDArray
from tqdm import tqdm

from ddgsa.errors import SchedulerLostError, StoreCorruptError, StoreLostError, StoreWriteError

Evaluator = Callable[[pd.DataFrame, Mapping[str, Any]], pd.DataFrame]
"""``f(points, scene)``: one row of outputs per point; failed rows NaN with reasons in ``attrs["failures"]``."""
ModelFactory = Callable[["ModelId"], Evaluator]
"""Builds the evaluator of a model identity (must be picklable: a module-level function)."""


@dataclass(frozen=True)
class ModelId:
    """What identifies a model configuration: registry name, fidelity and options."""

    name: str
    fidelity: str
    options: tuple[tuple[str, Any], ...] = ()
    signals: tuple[str, ...] = ()
    """Signal outputs each evaluation also computes and stores (:meth:`EvaluationStore.get_signals`)."""

    def as_dict(self) -> dict[str, Any]:
        """Plain-dict form (for keys and provenance); ``signals`` only when asked for, so the keys of
        evaluations without signals are those they always had."""
        out: dict[str, Any] = {"name": self.name, "fidelity": self.fidelity, "options": dict(self.options)}
        if self.signals:
            out["signals"] = list(self.signals)
        return out


@dataclass(frozen=True)
class Task:
    """One model evaluation: the store key, the model, the scene (a JSON-able dict the runner
    does not read) and the full parameter dict."""

    key: str
    model: ModelId
    scene: dict[str, Any]
    point: dict[str, float]


@dataclass(frozen=True)
class Outcome:
    """A stored evaluation: outputs (None when it failed), the failure reason, its cost [s]."""

    outputs: dict[str, float] | None
    error: str | None
    seconds: float
    signals: dict[str, Any] | None = None
    """Signal outputs (name -> float64 vector) of a successful evaluation that computed any."""


def task_key(model: ModelId, scene: Mapping[str, Any], point: dict[str, float], version: str) -> str:
    """Store key: SHA-256 of the model id, the scene, the point (exact float reprs) and the code version."""
    blob = json.dumps({"model": model.as_dict(), "scene": dict(scene), "version": version,
                       "point": {k: repr(float(v)) for k, v in sorted(point.items())}}, sort_keys=True)
    return hashlib.sha256(blob.encode()).hexdigest()


_CORRUPT = {"SQLITE_CORRUPT", "SQLITE_NOTADB"}
"""SQLite error names of a damaged file (everything else is a write or I/O failure)."""


def file_identity(path: Path) -> tuple[int, int] | None:
    """``(device, inode)`` of ``path``, or None when it does not exist: a file deleted, or
    replaced by another, no longer has the identity it had when opened."""
    try:
        st = os.stat(path)
    except OSError:
        return None
    return st.st_dev, st.st_ino


class EvaluationStore:
    """SQLite table of evaluations keyed by :func:`task_key` (WAL mode, exclusive: one process
    opens it at a time, and no file of it is memory-mapped).

    The store is the truth of a run, and it is checked: before every commit, :meth:`check`
    compares the store file (and the ``watch`` files, e.g. the folder's lock) with the files
    it opened (device and inode); one deleted or replaced stops the run with
    :class:`~ddgsa.errors.StoreLostError`, saying how many evaluations went with it. A file
    SQLite cannot read raises :class:`~ddgsa.errors.StoreCorruptError` (see :func:`set_aside`);
    one it cannot write, :class:`~ddgsa.errors.StoreWriteError`.
    """

    def __init__(self, path: Path, watch: Iterable[Path] = ()) -> None:
        path.parent.mkdir(parents=True, exist_ok=True)
        self.path = path
        with self._sqlite("open"):
            self._db = sqlite3.connect(str(path))
            try:
                # no file of the store is memory-mapped: in WAL mode SQLite maps the '-shm' index file, and a
                # fault on it (truncated, made immutable, its storage gone) ends the process with SIGBUS and no
                # message. EXCLUSIVE locking keeps that index in this process's memory (no '-shm' file), so a
                # storage fault is an I/O error with a message; another process cannot read the store meanwhile
                # (one writer per folder anyway: the folder's lock)
                self._db.execute("PRAGMA locking_mode=EXCLUSIVE")
                self._db.execute("PRAGMA mmap_size=0")
                self._db.execute("PRAGMA journal_mode=WAL")
                # WAL with synchronous=NORMAL: a commit survives a killed process (no fsync per batch, which
                # cost ~10 % of a fast model's time); only an OS crash could lose the last batches
                self._db.execute("PRAGMA synchronous=NORMAL")
                verdict = self._db.execute("PRAGMA quick_check(1)").fetchone()[0]
                if verdict != "ok":
                    raise StoreCorruptError(corrupt_message(path, str(verdict)))
                self._db.execute("CREATE TABLE IF NOT EXISTS evaluations (key TEXT PRIMARY KEY, scene TEXT, "
                                 "point TEXT, outputs TEXT, error TEXT, seconds REAL)")
                # signal outputs: one row per (evaluation, signal), the vector as little-endian float64 bytes
                self._db.execute("CREATE TABLE IF NOT EXISTS signals (key TEXT, name TEXT, data BLOB, "
                                 "PRIMARY KEY (key, name))")
                self._db.commit()
            except BaseException:
                self._db.close()
                raise
        self._identity = {p: file_identity(p) for p in (path, *watch)}
        self.opened_with = self.count()
        """Evaluations the store held when opened."""

    @contextmanager
    def _sqlite(self, doing: str) -> Iterator[None]:
        """SQLite's errors as ddgsa's, naming the file and the way out."""
        try:
            yield
        except sqlite3.DatabaseError as exc:
            if getattr(exc, "sqlite_errorname", "") in _CORRUPT or "malformed" in str(exc):
                raise StoreCorruptError(corrupt_message(self.path, str(exc))) from None
            kept = "" if doing == "open" else f"; the {self._safe_count()} evaluations committed before are kept in it"
            raise StoreWriteError(f"{self.path}: cannot {doing} the evaluation store: {exc}{kept}; free disk "
                                  "space or make the folder writable, then rerun the same command to resume") from None

    def _safe_count(self) -> str:
        try:
            return str(self.count())
        except sqlite3.Error:
            return "unknown number of"

    def check(self) -> None:
        """Raise :class:`~ddgsa.errors.StoreLostError` when the store or a watched file is no
        longer the file opened (deleted, or replaced by another run)."""
        for path, ident in self._identity.items():
            if file_identity(path) == ident:
                continue
            held = self._safe_count()
            if path == self.path:
                raise StoreLostError(
                    f"{path}: the evaluation store was deleted or replaced while this run was writing to it; its "
                    f"{held} evaluations ({held if held == 'unknown number of' else int(held) - self.opened_with} "
                    "of them from this run) are lost and nothing more is stored; rerun to start again")
            raise StoreLostError(
                f"{path}: deleted or replaced while this run held it, so another run may write to the same store; "
                f"this run stops here. Its {held} evaluations are kept in {self.path}; rerun the same command "
                "to resume once no other run uses the folder")

    def close(self) -> None:
        """Close the database."""
        self._db.close()

    def known(self, keys: Iterable[str]) -> set[str]:
        """The subset of ``keys`` already stored."""
        keys = list(keys)
        found: set[str] = set()
        with self._sqlite("read"):
            for i in range(0, len(keys), 500):
                chunk = keys[i:i + 500]
                rows = self._db.execute(f"SELECT key FROM evaluations WHERE key IN ({','.join('?' * len(chunk))})",
                                        chunk).fetchall()
                found.update(r[0] for r in rows)
        return found

    def get(self, keys: Iterable[str]) -> dict[str, Outcome]:
        """Stored outcomes of ``keys`` (missing keys are absent from the result)."""
        keys = list(keys)
        out: dict[str, Outcome] = {}
        with self._sqlite("read"):
            for i in range(0, len(keys), 500):
                chunk = keys[i:i + 500]
                rows = self._db.execute("SELECT key, outputs, error, seconds FROM evaluations WHERE key IN "
                                        f"({','.join('?' * len(chunk))})", chunk).fetchall()
                for key, outputs, error, seconds in rows:
                    out[key] = Outcome(None if outputs is None else json.loads(outputs), error, seconds)
        return out

    def forget_failed(self, keys: Iterable[str]) -> int:
        """Delete the stored failures among ``keys`` (and their signals), so that they run again;
        returns how many were deleted (``ddgsa run --retry-failed``, after their cause is fixed)."""
        keys = list(keys)
        gone = 0
        self.check()
        with self._sqlite("write"), self._db:
            for i in range(0, len(keys), 500):
                chunk = keys[i:i + 500]
                marks = ",".join("?" * len(chunk))
                failed = [r[0] for r in self._db.execute(
                    f"SELECT key FROM evaluations WHERE error IS NOT NULL AND key IN ({marks})", chunk).fetchall()]
                if failed:
                    marks = ",".join("?" * len(failed))
                    self._db.execute(f"DELETE FROM evaluations WHERE key IN ({marks})", failed)
                    self._db.execute(f"DELETE FROM signals WHERE key IN ({marks})", failed)
                    gone += len(failed)
        return gone

    def put(self, tasks: list[Task], outcomes: list[Outcome]) -> None:
        """Store a finished batch atomically, after :meth:`check`."""
        self.check()
        with self._sqlite("write"), self._db:
            self._db.executemany(
                "INSERT OR REPLACE INTO evaluations VALUES (?, ?, ?, ?, ?, ?)",
                [(t.key, json.dumps(t.scene), json.dumps(t.point),
                  None if o.outputs is None else json.dumps(o.outputs), o.error, o.seconds)
                 for t, o in zip(tasks, outcomes, strict=True)])
            self._db.executemany(
                "INSERT OR REPLACE INTO signals VALUES (?, ?, ?)",
                [(t.key, name, np.asarray(v, dtype="<f8").tobytes()) for t, o in zip(tasks, outcomes)
                 for name, v in (o.signals or {}).items()])

    def get_signals(self, keys: Iterable[str], name: str) -> dict[str, NDArray[np.float64]]:
        """Stored vectors of signal ``name`` at ``keys`` (keys without it are absent from the result)."""
        keys = list(keys)
        out: dict[str, NDArray[np.float64]] = {}
        with self._sqlite("read"):
            for i in range(0, len(keys), 500):
                chunk = keys[i:i + 500]
                rows = self._db.execute(f"SELECT key, data FROM signals WHERE name = ? AND key IN "
                                        f"({','.join('?' * len(chunk))})", [name, *chunk]).fetchall()
                out.update((k, np.frombuffer(data, dtype="<f8").copy()) for k, data in rows)
        return out

    def count(self) -> int:
        """Number of stored evaluations."""
        return int(self._db.execute("SELECT COUNT(*) FROM evaluations").fetchone()[0])


def corrupt_message(path: Path, reason: str) -> str:
    """What a corrupt store is and the way out."""
    return (f"{path}: the evaluation store is corrupt ({reason}); rerun with --force to move it aside to "
            f"{path.name}.corrupt (kept, never deleted) and rebuild the store by evaluating again")


def set_aside(path: Path) -> Path:
    """Rename a corrupt store (and its ``-wal``/``-shm`` files) to ``<name>.corrupt`` (``.corrupt.1``,
    ... when taken) beside it; returns the new path of the store file. Nothing is deleted."""
    k = 0
    while True:
        aside = path.with_name(f"{path.name}.corrupt" + (f".{k}" if k else ""))
        if not any(aside.with_name(aside.name + s).exists() for s in ("", "-wal", "-shm")):
            break
        k += 1
    for suffix in ("-wal", "-shm", ""):
        side = path.with_name(path.name + suffix)
        if side.exists():
            side.rename(aside.with_name(aside.name + suffix))
    return aside


@lru_cache(maxsize=8)
def _evaluator(factory: ModelFactory, model: ModelId) -> Evaluator:
    """One evaluator per model identity and process (models are built once per worker)."""
    return factory(model)


def evaluate_batch(factory: ModelFactory, model: ModelId, scene: Mapping[str, Any],
                   points: list[dict[str, float]], timeout: float | None = None) -> list[Outcome]:
    """Evaluate one batch in a worker; every failure becomes an :class:`Outcome` with its reason.

    A return that is not one row per point (a row missing or added, not a DataFrame, outputs
    that are not numbers, failure or signal entries beyond the batch) fails every point of the
    batch with that reason: no row of it is stored as a result. With ``timeout`` [s] each point
    is evaluated alone in a child process (:class:`TimedCalls`) and one running longer fails
    with "timed out after ... s"; without it, the batch runs here in one call.
    """
    try:
        evaluate = _evaluator(factory, model)
    except Exception as exc:  # noqa: BLE001 -- a model that cannot be built fails its points, never the run
        return [Outcome(None, failure_reason(exc), 0.0) for _ in points]
    if timeout is not None:
        calls = _timed_calls(evaluate, timeout)
        return [evaluate_batch_in(calls, scene, [p])[0] for p in points]
    return evaluate_batch_in(evaluate, scene, points)


def evaluate_batch_in(evaluate: Callable[[pd.DataFrame, Mapping[str, Any]], pd.DataFrame],
                      scene: Mapping[str, Any], points: list[dict[str, float]]) -> list[Outcome]:
    """The outcomes of ``evaluate(points, scene)``, one per point (see :func:`evaluate_batch`)."""
    t0 = time.perf_counter()
    try:
        frame = evaluate(pd.DataFrame(points), scene)
        values = _checked_values(frame, len(points))
    except Exception as exc:  # noqa: BLE001 -- any failure is data, never a crash of the run
        return [Outcome(None, failure_reason(exc), 0.0) for _ in points]
    per_point = (time.perf_counter() - t0) / max(len(points), 1)
    failures = frame.attrs.get("failures", {})
    signals = frame.attrs.get("signals", {})
    features = frame.attrs.get("features")             # a model's control features: stored beside the outputs
    extra = [dict(zip(map(str, features), v)) for v in zip(*features.values())] if features else None
    outcomes = []
    names = [str(c) for c in frame.columns]
    for i, row in enumerate(dict(zip(names, v)) for v in values.tolist()):
        bad = [k for k, v in row.items() if not math.isfinite(v)]
        bad += [k for k, v in signals.items() if not np.isfinite(v[i]).all()]
        if i in failures:
            outcomes.append(Outcome(None, failures[i], per_point))
        elif bad:
            outcomes.append(Outcome(None, f"non-finite output(s) {bad}", per_point))
        else:
            if extra is not None:                       # not checked: a feature a point lacks is NaN, not a failure
                row.update(extra[i])
            outcomes.append(Outcome(row, None, per_point, {k: v[i] for k, v in signals.items()} or None))
    return outcomes


class EvaluatorShapeError(ValueError):
    """An evaluator's return that is not one row of numbers per point it was given."""


def _checked_values(frame: Any, n_points: int) -> NDArray[np.float64]:
    """The outputs of an evaluator's return as a float matrix, one row per point.

    Raises
    ------
    EvaluatorShapeError
        When ``frame`` is not a DataFrame of ``n_points`` rows with at least one column, distinct
        column names and numeric values, or its ``failures`` / ``signals`` attributes name rows beyond the batch.
    """
    if not isinstance(frame, pd.DataFrame):
        raise EvaluatorShapeError(f"the evaluator returned {type(frame).__name__}, not a DataFrame of one row per "
                                  f"point ({n_points} points); no point of the batch is stored as a result")
    if len(frame) != n_points:
        raise EvaluatorShapeError(f"the evaluator returned {len(frame)} rows for {n_points} points (one row per "
                                  "point is required); no point of the batch is stored as a result")
    if frame.shape[1] == 0:
        raise EvaluatorShapeError(f"the evaluator returned {n_points} rows without an output column")
    if not frame.columns.is_unique:
        raise EvaluatorShapeError(f"the evaluator returned repeated output columns "
                                  f"{sorted({str(c) for c in frame.columns[frame.columns.duplicated()]})}")
    failures = frame.attrs.get("failures", {})
    if not isinstance(failures, Mapping) or any(not isinstance(i, (int, np.integer)) or not 0 <= i < n_points for i in failures):
        raise EvaluatorShapeError(f"the evaluator's failures name rows outside 0..{n_points - 1}")
    signals = frame.attrs.get("signals", {})
    if not isinstance(signals, Mapping) or any(len(v) != n_points for v in signals.values()):
        raise EvaluatorShapeError(f"the evaluator's signals do not hold one vector per point ({n_points} points)")
    features = frame.attrs.get("features")
    if features is not None and (not isinstance(features, Mapping) or set(map(str, features)) & set(map(str, frame.columns))
                                 or any(len(v) != n_points or not all(isinstance(x, (float, int)) for x in v)
                                        for v in features.values())):
        raise EvaluatorShapeError(f"the evaluator's features do not hold one number per point ({n_points} points) "
                                  "under names apart from the outputs'")
    try:
        return frame.to_numpy(dtype=float)
    except (TypeError, ValueError) as exc:
        raise EvaluatorShapeError(f"the evaluator returned outputs that are not numbers ({exc})") from None


class EvaluationFailed(RuntimeError):
    """An evaluation in a :class:`TimedCalls` child that failed; the message is the reason."""


class EvaluationTimeout(EvaluationFailed, TimeoutError):
    """An evaluation that ran longer than its timeout (its process was killed)."""


def failure_reason(exc: BaseException) -> str:
    """The reason stored for a failed evaluation: ``Type: message``, or the message alone for an
    :class:`EvaluationFailed` (whose message already names the cause)."""
    return str(exc) if isinstance(exc, EvaluationFailed) else f"{type(exc).__name__}: {exc}"


class TimedCalls:
    """Calls of ``fn`` in a forked child process, each stopped after ``timeout`` seconds (POSIX).

    The child is forked at the first call, so it holds ``fn`` (which need not be picklable) and
    everything this process loaded; it keeps what ``fn`` builds or compiles between calls. Only
    the arguments and the result cross the pipe. A call past ``timeout`` kills the child (SIGKILL)
    and raises :class:`EvaluationTimeout`; the next call forks a new one. An exception in ``fn``
    is raised here as :class:`EvaluationFailed` with its type and message; a child that dies (a
    signal, ``os._exit``) raises :class:`EvaluationFailed` naming how. The child dies with the thread that
    forked it (``PR_SET_PDEATHSIG``) and ends when :meth:`close` closes the pipe.
    """

    def __init__(self, fn: Callable[..., Any], timeout: float) -> None:
        if not timeout > 0:
            raise ValueError(f"timeout must be a positive number of seconds, got {timeout!r}")
        self.fn = fn
        self.timeout = float(timeout)
        self._pid: int | None = None
        self._conn: Any = None
        self._owner = os.getpid()

    def __call__(self, *args: Any) -> Any:
        if self._owner != os.getpid():                    # inherited by a forked process: not its child
            self._pid, self._conn, self._owner = None, None, os.getpid()
        if self._pid is None:
            self._start()
        self._conn.send(args)
        if not self._conn.poll(self.timeout):
            self.close()
            raise EvaluationTimeout(f"timed out after {self.timeout:g} s (the evaluation was stopped)")
        try:
            ok, value = self._conn.recv()
        except (EOFError, OSError):
            status = self.close()
            raise EvaluationFailed(f"the evaluation's process died ({status})") from None
        if not ok:
            raise EvaluationFailed(value)
        return value

    def _start(self) -> None:
        parent, child = multiprocessing.Pipe()
        pid = os.fork()
        if pid == 0:                                          # the child: serve calls until the pipe closes
            parent.close()
            _die_with_parent()
            signal.signal(signal.SIGINT, signal.SIG_IGN)
            os._exit(_serve(self.fn, child))
        child.close()
        self._pid, self._conn = pid, parent

    def close(self) -> str:
        """Stop the child (if any); returns how it ended (``exit status N`` / ``signal N``)."""
        if self._pid is None:
            return "not started"
        self._conn.close()
        with suppress(ProcessLookupError):
            os.kill(self._pid, signal.SIGKILL)
        _, status = os.waitpid(self._pid, 0)
        self._pid, self._conn = None, None
        return f"signal {os.WTERMSIG(status)}" if os.WIFSIGNALED(status) else f"exit status {os.WEXITSTATUS(status)}"


def _serve(fn: Callable[..., Any], conn: Any) -> int:
    """The child's loop of :class:`TimedCalls`: ``(True, fn(*args))`` or ``(False, reason)`` per call."""
    while True:
        try:
            args = conn.recv()
        except (EOFError, OSError):
            return 0
        try:
            reply: tuple[bool, Any] = (True, fn(*args))
        except Exception as exc:  # noqa: BLE001 -- a failure is data, sent back
            reply = (False, f"{type(exc).__name__}: {exc}")
        try:
            conn.send(reply)
        except Exception as exc:  # noqa: BLE001 -- e.g. a result that cannot be pickled
            conn.send((False, f"the evaluation's result cannot be sent back ({type(exc).__name__}: {exc})"))


_TIMED: dict[tuple[int, float], TimedCalls] = {}
"""This process's :class:`TimedCalls` per (evaluator, timeout), kept across batches so that the
child keeps what the model built; stopped by :func:`stop_timed_calls`."""


def _timed_calls(evaluate: Evaluator, timeout: float) -> TimedCalls:
    key = (id(evaluate), float(timeout))
    if key not in _TIMED or _TIMED[key].fn is not evaluate:
        _TIMED[key] = TimedCalls(evaluate, timeout)
    return _TIMED[key]


def stop_timed_calls() -> None:
    """Stop the children of this process's :class:`TimedCalls` (at the end of a run)."""
    while _TIMED:
        _TIMED.popitem()[1].close()


@contextmanager
def _backend(backend: str, jobs: int, address: str | None) -> Iterator[None]:
    """joblib's loky backend, or the Dask backend on ``address`` (a LocalCluster when None)."""
    if backend == "loky":
        yield
        return
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise RuntimeError("the dask backend needs 'pip install ddgsa[dask]' (dask[distributed])") from None
    cluster = None if address else LocalCluster(n_workers=jobs, threads_per_worker=1, processes=True,
                                                dashboard_address=None)
    client = Client(address) if address else Client(cluster)
    lost = threading.Event()
    stop = threading.Event()
    watch = threading.Thread(target=_watch_scheduler, args=(client, lost, stop), daemon=True)
    watch.start()
    try:
        with joblib.parallel_config(backend="dask"):
            yield
    except KeyboardInterrupt:
        if lost.is_set():
            raise SchedulerLostError(f"lost the Dask scheduler at {address or 'the local cluster'} (no answer "
                                     f"for {SCHEDULER_GRACE_S:g} s)") from None
        raise
    finally:
        stop.set()
        with suppress(Exception):
            client.close(timeout=5)
        if cluster is not None:
            with suppress(Exception):
                cluster.close(timeout=5)


SCHEDULER_GRACE_S = 20.0
"""A Dask client not connected for this long [s] means the scheduler is lost: the run stops."""


def _watch_scheduler(client: Any, lost: threading.Event, stop: threading.Event) -> None:
    """Interrupt the run (SIGINT to this process, which wakes a blocked wait) when ``client`` has
    not been connected for :data:`SCHEDULER_GRACE_S`; ``lost`` tells the interrupt from Ctrl-C."""
    since: float | None = None
    while not stop.wait(1.0):
        if client.status == "running":
            since = None
            continue
        since = since if since is not None else time.monotonic()
        if time.monotonic() - since > SCHEDULER_GRACE_S:
            lost.set()
            os.kill(os.getpid(), signal.SIGINT)
            return


def run_tasks(tasks: list[Task], store: EvaluationStore, factory: ModelFactory, jobs: int = 1,
              batch_size: int = 4, backend: str = "loky", address: str | None = None,
              quiet: bool = False, setup: Callable[[], None] | None = None,
              timeout: float | None = None) -> dict[str, int]:
    """Evaluate the tasks missing from ``store`` with the evaluators ``factory`` builds.

    ``setup`` (picklable, idempotent) runs in each worker before its batches, e.g. to point the
    model's caches at shared files; the runner does not know what it does. ``timeout`` [s]
    bounds each evaluation: each point then runs alone in a child process of its worker and one
    that runs longer is stored as failed, "timed out after ... s" (:class:`TimedCalls`); without
    it (the default) the batches run in the workers themselves, at no cost.

    Returns
    -------
    dict
        ``total`` (unique tasks), ``cached`` (already stored), ``evaluated`` (run now) and
        ``failed`` (of those run now).
    """
    unique = list({t.key: t for t in tasks}.values())
    done = store.known(t.key for t in unique)
    todo = [t for t in unique if t.key not in done]
    batches: list[list[Task]] = []
    by_scene: dict[tuple[ModelId, str], list[Task]] = {}
    for t in todo:
        by_scene.setdefault((t.model, json.dumps(t.scene, sort_keys=True)), []).append(t)
    for group in by_scene.values():
        batches += [group[i:i + batch_size] for i in range(0, len(group), batch_size)]
    failed = 0
    unshown = {t.key for t in unique} & _UNSHOWN
    if quiet:
        _UNSHOWN.update(t.key for t in todo)
    else:
        _UNSHOWN.difference_update(unshown)
    with tqdm(total=len(todo) + len(unshown), initial=len(unshown), disable=quiet or not todo, unit="eval",
              desc="model runs", smoothing=0.1) as bar:
        if jobs == 1 and backend == "loky":
            results: Iterable[tuple[list[Task], list[Outcome]]] = (_batch_job(factory, b, setup, timeout) for b in batches)
            try:
                failed = _consume(results, store, bar)
            finally:
                stop_timed_calls()
        elif backend == "loky" and FORK_WORKERS:
            with closing(_forked(jobs, factory, batches, setup, timeout)) as finished:   # stopped here, not when collected
                failed = _consume(finished, store, bar)
        else:
            try:
                with _backend(backend, jobs, address):
                    ret = "generator_unordered" if backend == "loky" else "generator"
                    par = joblib.Parallel(n_jobs=jobs, return_as=ret)
                    results = par(joblib.delayed(_batch_job)(factory, b, setup, timeout) for b in batches)
                    failed = _consume(results, store, bar)
            except SchedulerLostError as exc:
                raise SchedulerLostError(f"{exc}; the {store.count()} evaluations committed before are kept in "
                                         f"{store.path}; restart the scheduler and its workers, then rerun the same "
                                         "command to resume") from None
    store.check()
    return {"total": len(unique), "cached": len(done), "evaluated": len(todo), "failed": failed}


_UNSHOWN: set[str] = set()
"""Keys evaluated in this process by a ``quiet`` :func:`run_tasks` call (e.g. the pipeline's one-run
warm-up before the parallel workers start) and not yet counted on a progress bar: the next bar over
them counts them as done, so its total is the number of runs of the step (85/85, not 84/84)."""


FORK_WORKERS = sys.platform.startswith("linux")
"""Local workers are forked from the calling process (Linux); elsewhere joblib's loky workers."""


_SCOPE: dict[str, Any] = {}
"""The pool of the innermost :func:`local_workers` scope (``jobs`` and ``pool`` once forked)."""


@contextmanager
def local_workers() -> Iterator[None]:
    """Keep forked workers for every :func:`run_tasks` call inside the ``with`` block.

    The pool is forked at the first parallel call in the block (so it inherits what the process
    loaded until then, e.g. a study's warmed-up kernels) and stopped at its end; a call with
    another ``jobs`` replaces it. Outside a block each call forks its own (~0.1 s). No effect
    where workers are not forked (loky keeps its own workers).
    """
    outer = dict(_SCOPE)
    _SCOPE.clear()
    _SCOPE["active"] = True
    try:
        yield
    finally:
        if "pool" in _SCOPE:
            _SCOPE["pool"].shutdown(wait=True, cancel_futures=True)
        _SCOPE.clear()
        _SCOPE.update(outer)


def _new_pool(jobs: int) -> ProcessPoolExecutor:
    return ProcessPoolExecutor(max_workers=jobs, mp_context=multiprocessing.get_context("fork"),
                               initializer=_forked_worker,
                               initargs=(_blas_controller(), max(1, (os.cpu_count() or 1) // jobs)))


def _forked(jobs: int, factory: ModelFactory, batches: list[list[Task]], setup: Callable[[], None] | None,
            timeout: float | None = None) -> Iterator[tuple[list[Task], list[Outcome]]]:
    """Finished batches, in the order they finish, from ``jobs`` forked workers (the scope's, or
    forked for this call)."""
    if not batches:
        return
    scoped = bool(_SCOPE.get("active"))
    if scoped and _SCOPE.get("jobs") != jobs:
        if "pool" in _SCOPE:
            _SCOPE.pop("pool").shutdown(wait=True)
        _SCOPE.update(jobs=jobs, pool=_new_pool(jobs))
    pool = _SCOPE["pool"] if scoped else _new_pool(min(jobs, len(batches)))
    futures: list[Future[tuple[list[Task], list[Outcome]]]] = []
    clean = False
    try:
        futures = [pool.submit(_batch_job, factory, b, setup, timeout) for b in batches]
        for future in as_completed(futures):
            yield future.result()
        clean = True
    finally:
        if not clean:                     # interrupted or failed: stop the batches still running too
            for future in futures:
                future.cancel()
            for proc in list((getattr(pool, "_processes", None) or {}).values()):   # no public way to stop them
                proc.terminate()
        if not (clean and scoped):
            pool.shutdown(wait=True, cancel_futures=True)
            if scoped:
                _SCOPE.pop("pool", None)
                _SCOPE.pop("jobs", None)


SLOW_FIRST_S = 3.0
"""A silent step longer than this [s] (a first evaluation or model check, compiling the model's
kernels) says on screen what it is doing (:func:`said_if_slow`)."""


@contextmanager
def said_if_slow(text: str, quiet: bool = False, done: str = "") -> Iterator[None]:
    """Run the block; past :data:`SLOW_FIRST_S` print ``text`` on stderr while it runs and, when
    ``done`` is given, ``done`` with the seconds it took once it ends. ``quiet`` prints nothing."""
    note = threading.Timer(SLOW_FIRST_S, print, args=(text,), kwargs={"file": sys.stderr, "flush": True})
    if not quiet:
        note.start()
    t0 = time.perf_counter()
    try:
        yield
    finally:
        note.cancel()
    if done and not quiet and time.perf_counter() - t0 > SLOW_FIRST_S:
        print(f"{done} after {time.perf_counter() - t0:.0f} s", file=sys.stderr, flush=True)


@lru_cache(maxsize=1)
def _blas_controller() -> Any:
    """threadpoolctl's view of the loaded BLAS libraries, found once per process (the search costs
    ~50 ms; forked workers inherit the result)."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()


@contextmanager
def main_blas_threads(jobs: int | None) -> Iterator[None]:
    """BLAS on one thread in this process for the block, when the study runs ``jobs`` > 1 workers
    (a study's main process: its fits and pilots are small, and a two-thread OpenBLAS on a core its
    workers keep busy waits for the descheduled thread: a 2 001 x 7 QR took 24-47 ms instead of
    0.1 ms, measured). With one job the process keeps its threads."""
    if not jobs or jobs <= 1:
        yield
        return
    with _blas_controller().limit(limits=1, user_api="blas"):
        yield


def _die_with_parent() -> None:
    """This process gets SIGKILL when the thread that forked it ends (``PR_SET_PDEATHSIG``: no
    orphans when a run is killed)."""
    try:
        ctypes.CDLL(None).prctl(1, signal.SIGKILL)
    except (OSError, AttributeError):               # pragma: no cover (not glibc)
        pass


def _forked_worker(blas: Any, blas_threads: int) -> None:
    """Initialise a forked worker: die with the parent, leave Ctrl-C to it, cap BLAS threads."""
    _die_with_parent()
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    blas.limit(limits=blas_threads, user_api="blas")


def _batch_job(factory: ModelFactory, batch: list[Task], setup: Callable[[], None] | None = None,
               timeout: float | None = None) -> tuple[list[Task], list[Outcome]]:
    if setup is not None:
        setup()
    return batch, evaluate_batch(factory, batch[0].model, batch[0].scene, [t.point for t in batch], timeout)


def _consume(results: Iterable[tuple[list[Task], list[Outcome]]], store: EvaluationStore, bar: tqdm) -> int:
    failed = 0
    for batch, outcomes in results:
        if len(outcomes) != len(batch):             # evaluate_batch gives one per point; a guard, never partial
            raise RuntimeError(f"a batch of {len(batch)} points came back with {len(outcomes)} outcomes")
        store.put(batch, outcomes)
        failed += sum(o.outputs is None for o in outcomes)
        bar.update(len(batch))
    return failed
