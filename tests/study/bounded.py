"""``ddgsa validate`` in this process with its memory and CPU measured (the bad-input and fuzz tests
bound both)."""

from __future__ import annotations

import contextlib
import io
import time
import tracemalloc
from pathlib import Path

from ddgsa.cli import main


def measured_validate(path: Path) -> tuple[int, str, int, float]:
    """Exit code, stderr, peak traced memory [bytes] and CPU time [s] of ``ddgsa validate path``."""
    err = io.StringIO()
    tracemalloc.start()
    t0 = time.process_time()
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            rc = main(["validate", str(path)])
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    return rc, err.getvalue(), peak, time.process_time() - t0
