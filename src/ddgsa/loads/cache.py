"""Realisations of the hub loads stored as files, shared by every process of a study.

A realisation is a pure function of its scene and turbine, and each costs ~0.1 s; a study
with many parameter points per scene would otherwise generate it once per worker process
(the in-memory cache is per process). With a directory set (:func:`set_directory`; the
pipeline sets one beside the evaluation store), the first process to need a realisation
generates it under an exclusive file lock and writes it atomically; every other process
waits for the lock and reads the file. Each generation appends one line to
``generated.log`` (key and process id), so a study can show it generated each realisation
once. Files are keyed by the scene, the turbine and the ddgsa version.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ddgsa._version import __version__

LOG = "generated.log"
_directory: Path | None = None


def set_directory(path: str | Path | None) -> None:
    """Share realisations through files under ``path`` (None: in memory only, per process)."""
    global _directory
    _directory = None if path is None else Path(path)


@contextmanager
def shared(path: str | Path | None) -> Iterator[None]:
    """:func:`set_directory` for the duration of a ``with`` block, then the previous setting."""
    previous = _directory
    set_directory(path)
    try:
        yield
    finally:
        set_directory(previous)


def directory() -> Path | None:
    """The directory set by :func:`set_directory`, or None."""
    return _directory


def _content(obj: Any, digest: Any) -> None:
    """Feed a dataclass's declared fields (arrays by their bytes) to ``digest``; cached properties,
    which differ between processes that did or did not use them, are not fields."""
    if dataclasses.is_dataclass(obj):
        for f in dataclasses.fields(obj):
            digest.update(f.name.encode())
            _content(getattr(obj, f.name), digest)
    elif isinstance(obj, np.ndarray):
        digest.update(np.ascontiguousarray(obj).tobytes())
    else:
        digest.update(repr(obj).encode())


def key(scene: Any, turbine: Any) -> str:
    """File key of a realisation: SHA-256 of the scene fields, the turbine's fields and the version."""
    digest = hashlib.sha256(json.dumps(scene.to_dict(), sort_keys=True).encode() + __version__.encode())
    _content(turbine, digest)
    return digest.hexdigest()[:32]


@contextmanager
def _locked(path: Path) -> Iterator[None]:
    """An exclusive lock on ``path`` across processes (POSIX ``flock``; no lock where unavailable)."""
    try:
        import fcntl
    except ImportError:                     # pragma: no cover (non-POSIX): duplicates possible, never wrong
        yield
        return
    with open(path, "a") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


def load_or_compute(scene: Any, turbine: Any,
                    compute: Callable[[Any, Any], NDArray[np.float64]]) -> NDArray[np.float64]:
    """``compute(scene, turbine)``, through the shared directory when one is set."""
    if _directory is None:
        return compute(scene, turbine)
    _directory.mkdir(parents=True, exist_ok=True)
    k = key(scene, turbine)
    path = _directory / f"{k}.npy"
    with _locked(_directory / f"{k}.lock"):
        if path.exists():
            return np.load(path)
        values = compute(scene, turbine)
        tmp = _directory / f"{k}.{os.getpid()}.tmp.npy"
        np.save(tmp, values)
        os.replace(tmp, path)
        with open(_directory / LOG, "a") as fh:
            fh.write(f"{k} {os.getpid()}\n")
    return values


def generations(path: str | Path) -> dict[str, int]:
    """How many times each realisation key was generated under ``path`` (from ``generated.log``)."""
    log = Path(path) / LOG
    counts: dict[str, int] = {}
    if log.exists():
        for line in log.read_text().splitlines():
            counts[line.split()[0]] = counts.get(line.split()[0], 0) + 1
    return counts
