"""Shared pytest fixtures.

The tests run on as many processes as there are cores (``pytest -n auto``), so BLAS is held to one
thread per process, here and in every process a test starts: OpenBLAS threads that spin on an
oversubscribed machine made one least-squares fit 5x slower than with a single thread.
"""

from __future__ import annotations

import os
import sys

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"                              # inherited by the CLI processes tests start

import matplotlib  # noqa: E402
import pytest  # noqa: E402
from threadpoolctl import threadpool_limits  # noqa: E402

threadpool_limits(limits=1, user_api="blas")           # for a BLAS already loaded before this file

matplotlib.use("Agg")


@pytest.fixture(autouse=True)
def _fresh_aliasing_memory():
    """Each test starts with the rig's once-per-process aliasing memory empty
    (``ddgsa.models.hss_rig.model._SHOWN``), so no test hides a warning from the next."""
    module = sys.modules.get("ddgsa.models.hss_rig.model")
    if module is not None:
        module._SHOWN.clear()
    yield
