"""Watching a run in another process: its evaluation store cannot be read while the run holds it
(SQLite's exclusive mode, so that no file of it is memory-mapped), so progress is judged from the
size of its write-ahead log."""

from __future__ import annotations

from pathlib import Path

WAL_FRAME_BYTES = 4096 + 24
"""One page written to a SQLite write-ahead log (a 4 kB page and its frame header)."""
WAL_HEADER_BYTES = 32


def pages_committed(store: Path) -> int:
    """Pages the run holding ``store`` has written to its write-ahead log so far (0 before it exists).
    A commit writes at least one page and, for a batch of up to 8 evaluations, at most 6 (the
    table's and the key index's pages, a split)."""
    wal = store.with_name(store.name + "-wal")
    try:
        size = wal.stat().st_size
    except FileNotFoundError:
        return 0
    return max(0, (size - WAL_HEADER_BYTES) // WAL_FRAME_BYTES)


def schema_pages() -> int:
    """Pages a new store writes to its log when it is opened (its tables' schema, before any evaluation):
    a run has stored a batch once :func:`pages_committed` exceeds this (measured, not assumed: it depends
    on SQLite's version)."""
    import tempfile

    from ddgsa.runner import EvaluationStore

    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "evaluations.sqlite"
        store = EvaluationStore(path)
        try:
            return pages_committed(path)
        finally:
            store.close()
