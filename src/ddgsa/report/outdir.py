"""An output folder's guard: one live run at a time, one study per folder, no stale artefacts.

:func:`claim` locks the folder for the duration of a run or a report rebuild (an OS lock on
``.ddgsa.lock``, released by the OS even when the process is killed), refuses a folder that
holds another study's results or files ddgsa did not write (unless ``force``; results of another
version of the same study are replaced, :func:`replaced_version` says which), and
:func:`remove_stale` deletes the artefacts an earlier report wrote that the new one did not
(a study with fewer scenes leaves no old ``bars_scene2.png`` beside its new summary).
The list of written files is the ``files`` entry of ``provenance.json``. A completion mark
(``complete.json``) says "incomplete" from the moment a run starts (:func:`unmark_complete`) and
"complete", with each file's size, once the report's last file is written (:func:`mark_complete`),
so a report can tell a folder whose run was stopped from a finished one (:func:`incompleteness`).
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO

from ruamel.yaml import YAML
from ruamel.yaml.error import YAMLError

from ddgsa.errors import FolderBusyError, OutputFolderError

LOCK_NAME = ".ddgsa.lock"
STORE_NAME = "evaluations.sqlite"
COMPLETE_NAME = "complete.json"
"""The completion mark of a folder's outputs: ``{"complete": false}`` from the moment a run or a
report rebuild starts, ``{"complete": true, "files": {name: size}}`` written last, once every
file of the report is written."""
KEPT = {LOCK_NAME, "study.yaml", STORE_NAME, f"{STORE_NAME}-wal", f"{STORE_NAME}-shm", f"{STORE_NAME}-journal",
        COMPLETE_NAME}
"""Files of a ddgsa folder that are not report artefacts."""
REPORT_SUFFIXES = (".png", ".csv", ".md", ".json", ".html")
"""What a report writes (used for folders written before the ``files`` list existed)."""


def owner(folder: Path) -> str | None:
    """The study whose results ``folder`` holds (from ``provenance.json``, else ``study.yaml``), or None."""
    prov = folder / "provenance.json"
    try:
        name = json.loads(prov.read_text()).get("study")
        if isinstance(name, str):
            return name
    except (OSError, ValueError, AttributeError):
        pass
    try:
        data = YAML(typ="safe", pure=True).load((folder / "study.yaml").read_text())
    except (OSError, YAMLError):
        return None
    return data.get("name") if isinstance(data, dict) and isinstance(data.get("name"), str) else None


def replaced_version(folder: Path, study: str, digest: str) -> str | None:
    """The study file (as ``provenance.json`` names it) of results in ``folder`` that belong to
    study ``study`` but to another version of it (another ``study_sha256``, e.g. a copied and edited
    study that kept its ``name:``), or None when the folder holds no such results. Such results are
    replaced by the new run's; unlike another study's (:func:`claim`) they are not refused, since
    editing a study and running it again is the ordinary loop."""
    try:
        prov = json.loads((folder / "provenance.json").read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(prov, dict) or prov.get("study") != study:
        return None
    old = prov.get("study_sha256")
    if not isinstance(old, str) or old == digest:
        return None
    return str(prov.get("study_file") or "study.yaml")


def previous_files(folder: Path) -> set[str]:
    """Names of the report artefacts in ``folder`` from its last report."""
    try:
        files = json.loads((folder / "provenance.json").read_text()).get("files")
    except (OSError, ValueError, AttributeError):
        files = None
    if isinstance(files, list):
        return {f for f in files if isinstance(f, str) and "/" not in f and f not in KEPT}
    if owner(folder) is None:                       # not a ddgsa folder: nothing of ours to remove
        return set()
    return {p.name for p in folder.iterdir() if p.is_file() and p.suffix in REPORT_SUFFIXES and p.name not in KEPT}


def unmark_complete(folder: Path) -> None:
    """Mark the folder's outputs incomplete: they are being rewritten."""
    _write_mark(folder, {"complete": False})


def mark_complete(folder: Path, names: Iterable[str]) -> None:
    """Mark ``folder``'s outputs complete, listing the files ``names`` and their sizes [B]."""
    sizes = {n: (folder / n).stat().st_size for n in sorted(set(names)) if n != COMPLETE_NAME}
    _write_mark(folder, {"complete": True, "files": sizes})


def _write_mark(folder: Path, mark: dict[str, object]) -> None:
    """Write the mark beside and rename it: it is whole or absent."""
    tmp = folder / f".{COMPLETE_NAME}.{os.getpid()}.tmp"
    tmp.write_text(json.dumps(mark, indent=1))
    os.replace(tmp, folder / COMPLETE_NAME)


def incompleteness(folder: Path, ignore: Iterable[str] = ()) -> str | None:
    """None when ``folder``'s outputs are complete, else why they are not: its mark says a run or
    report started and did not finish, or a file the mark lists is missing or has another size
    (``ignore`` aside). A folder written before completion marks (no mark) is judged by the files
    its ``provenance.json`` lists. None for a folder that is not a study's (no ``study.yaml``,
    store or ``provenance.json``: e.g. ``ddgsa modes`` output)."""
    if not any((folder / n).exists() for n in ("study.yaml", STORE_NAME, "provenance.json")):
        return None
    try:
        mark = json.loads((folder / COMPLETE_NAME).read_text())
    except FileNotFoundError:
        return _unmarked(folder)
    except (OSError, ValueError):
        return "its completion mark cannot be read"
    if not isinstance(mark, dict) or mark.get("complete") is not True or not isinstance(mark.get("files"), dict):
        return "the run or report that wrote this folder did not finish"
    skip = set(ignore)
    for name, size in mark["files"].items():
        if name in skip:
            continue
        try:
            now = (folder / str(name)).stat().st_size
        except OSError:
            return f"{name}, written by the run, is missing"
        if now != size:
            return f"{name} changed after the run wrote it ({now} bytes, written {size})"
    return None


def _unmarked(folder: Path) -> str | None:
    """A folder without a mark (written before marks existed): complete when its ``provenance.json``
    (written near the end) lists files that are all there."""
    try:
        files = json.loads((folder / "provenance.json").read_text()).get("files")
    except (OSError, ValueError, AttributeError):
        files = None
    if not isinstance(files, list):
        return "the run that wrote this folder did not finish (no completion mark, no list of its files)"
    gone = [f for f in files if isinstance(f, str) and f not in (COMPLETE_NAME, "report.html") and not (folder / f).exists()]
    return f"{gone[0]}, written by the run, is missing" if gone else None


def remove_stale(folder: Path, before: Iterable[str], written: Iterable[str]) -> list[str]:
    """Delete the files of ``before`` that are not in ``written``; returns their names."""
    stale = sorted(set(before) - set(written))
    for name in stale:
        (folder / name).unlink(missing_ok=True)
    return stale


@contextmanager
def _locked(folder: Path) -> Iterator[None]:
    """An exclusive, non-blocking OS lock on ``folder/.ddgsa.lock`` (released when the process ends)."""
    path = folder / LOCK_NAME
    for _ in range(3):
        handle: IO[str] = open(path, "a+")          # noqa: SIM115 -- held for the whole run
        try:
            _lock_file(handle)
        except OSError:
            handle.seek(0)
            holder = handle.read().strip() or "unknown"
            handle.close()
            raise FolderBusyError(f"{folder}: another ddgsa run (pid {holder}) is writing to this folder; "
                                  "wait for it to finish or choose another --out") from None
        if path.exists() and os.path.samestat(os.fstat(handle.fileno()), os.stat(path)):
            break
        handle.close()                               # its holder removed the file as we opened it: again
    try:
        handle.seek(0)
        handle.truncate()
        handle.write(str(os.getpid()))
        handle.flush()
        yield
    finally:
        path.unlink(missing_ok=True)                 # no stale lock file is left behind (the lock held it)
        handle.close()                               # closing the file releases the lock


def _lock_file(handle: IO[str]) -> None:
    try:
        import fcntl
    except ImportError:                              # Windows
        import msvcrt

        msvcrt.locking(handle.fileno(), msvcrt.LK_NBLCK, 1)
        return
    fcntl.flock(handle.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)


@contextmanager
def claim(folder: Path, study: str, force: bool = False) -> Iterator[Path]:
    """Hold ``folder`` for study ``study`` while the block runs.

    Raises
    ------
    FolderBusyError
        When another live ddgsa process holds the folder.
    OutputFolderError
        When the folder holds another study's results, or files that ddgsa did not write,
        and ``force`` is false.
    """
    folder.mkdir(parents=True, exist_ok=True)
    with _locked(folder):
        held = owner(folder)
        if not force and held is not None and held != study:
            raise OutputFolderError(f"{folder}: holds the results of study {held!r}, not {study!r}; choose "
                                    "another --out, or pass --force to replace them (its stale files are removed)")
        foreign = sorted(p.name for p in folder.iterdir() if p.name not in KEPT)
        if not force and held is None and foreign:
            raise OutputFolderError(f"{folder}: is not empty and is not a ddgsa output folder ({', '.join(foreign[:3])}"
                                    f"{', ...' if len(foreign) > 3 else ''}); choose another --out, or pass --force")
        yield folder
